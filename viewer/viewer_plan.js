/* The run viewer's plan (docs/viewer.md): the world drawn top-down on a canvas, the truth and
 * every pipeline's path up to the cursor with their 2-sigma ellipses, the map's landmarks, pan
 * and zoom; and the legend that shows and hides the pipelines. Part of viewer.js's closure
 * (scripts/pages.py inlines it where viewer.js says CORRIDORSIM_INCLUDE viewer_plan.js); this
 * opening comment stays out of the page. */
  // ---------------------------------------------------------------- the plan
  const plan = { canvas: null, ctx: null, w: 0, h: 0, dpr: 1, cx: 0, cy: 0, s: 20, layer: null, layerKey: "" };
  let drawPending = false;

  function requestDraw() {
    if (drawPending) return;
    drawPending = true;
    requestAnimationFrame(() => { drawPending = false; drawPlanNow(); });
  }

  function worldBox() {
    const b = D.world.bounds;
    if (b.length === 4 && b.every(isFinite) && b[2] > b[0] && b[3] > b[1]) return b;
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    const add = (x, y) => { if (isFinite(x) && isFinite(y)) { x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); } };
    for (const w of D.world.walls) { add(w[0], w[1]); add(w[2], w[3]); }
    for (let i = 0; i < D.truth.n; i++) add(D.truth.x[i], D.truth.y[i]);
    for (const p of D.pipelines) for (let i = 0; i < p.path.n; i++) add(p.path.x[i], p.path.y[i]);
    return isFinite(x0) ? [x0 - 1, y0 - 1, x1 + 1, y1 + 1] : [-5, -5, 5, 5];
  }

  function fitPlan() {
    const [x0, y0, x1, y1] = worldBox();
    plan.cx = (x0 + x1) / 2; plan.cy = (y0 + y1) / 2;
    plan.s = Math.max(Math.min((plan.w - 30) / Math.max(x1 - x0, 1e-3), (plan.h - 30) / Math.max(y1 - y0, 1e-3)), 1e-3);
    requestDraw();
  }

  const toScreen = (x, y) => [plan.w / 2 + (x - plan.cx) * plan.s, plan.h / 2 - (y - plan.cy) * plan.s];
  const toWorld = (px, py) => [plan.cx + (px - plan.w / 2) / plan.s, plan.cy - (py - plan.h / 2) / plan.s];
  /** Canvas transform: world metres, y up. Line widths in metres then: px / plan.s. */
  function worldTransform(ctx) {
    const k = plan.dpr * plan.s;
    ctx.setTransform(k, 0, 0, -k, plan.dpr * (plan.w / 2 - plan.cx * plan.s), plan.dpr * (plan.h / 2 + plan.cy * plan.s));
  }
  function screenTransform(ctx) { ctx.setTransform(plan.dpr, 0, 0, plan.dpr, 0, 0); }

  function resizePlan() {
    const wrap = $("cs-plan-wrap");
    const r = wrap.getBoundingClientRect();
    const first = plan.w === 0;
    const w = Math.max(Math.round(r.width), 50), h = Math.max(Math.round(r.height), 50), dpr = window.devicePixelRatio || 1;
    // Setting a canvas' size clears it: only on a real change, and then redrawn at once, not in
    // the next animation frame. The observer calls this between layout and paint, so the frame
    // it paints (the first one too: its first call comes when the page's layout settles, after
    // start() drew) shows the plan; a headless screenshot may take that very frame.
    if (!first && w === plan.w && h === plan.h && dpr === plan.dpr) return;
    plan.w = w; plan.h = h; plan.dpr = dpr;
    plan.canvas.width = Math.round(plan.w * plan.dpr); plan.canvas.height = Math.round(plan.h * plan.dpr);
    plan.layer.width = plan.canvas.width; plan.layer.height = plan.canvas.height;
    plan.layerKey = "";
    if (first) fitPlan();
    drawPlanNow();
  }

  const DOOR_COLORS = { open: "#3fb970", closed: "#f0524f", ajar: "#e8a33d" };

  /** The parts that do not move with the cursor, cached in an offscreen canvas per view. */
  function drawStaticLayer() {
    const key = [plan.w, plan.h, plan.dpr, plan.cx, plan.cy, plan.s, showLabels()].join(",");
    if (key === plan.layerKey) return;
    plan.layerKey = key;
    const ctx = plan.layer.getContext("2d");
    screenTransform(ctx);
    ctx.fillStyle = "#101115";
    ctx.fillRect(0, 0, plan.w, plan.h);
    drawGrid(ctx);
    const W = D.world, px = 1 / plan.s;
    worldTransform(ctx);
    // lamps under everything: lit ones warm and filled, off ones dashed outlines
    for (const L of W.lamps) {
      const c = arr(L.center).map(num);
      if (!(isFinite(c[0]) && isFinite(c[1]))) continue;
      ctx.beginPath();
      if (Array.isArray(L.extent)) {
        const sx = num(L.extent[0]), sy = num(L.extent[1]);
        if (!(isFinite(sx) && isFinite(sy))) continue;
        ctx.rect(c[0] - sx / 2, c[1] - sy / 2, sx, sy);
      } else {
        const r = isFinite(num(L.extent)) ? num(L.extent) : 0.2;
        ctx.arc(c[0], c[1], Math.max(r, 0.02), 0, 2 * Math.PI);
      }
      ctx.setLineDash(L.on ? [] : [3 * px, 3 * px]);
      ctx.fillStyle = L.on ? "rgba(255, 214, 90, 0.28)" : "rgba(120, 120, 120, 0.08)";
      ctx.strokeStyle = L.on ? "rgba(255, 214, 90, 0.9)" : "rgba(140, 140, 140, 0.6)";
      ctx.lineWidth = 1 * px;
      ctx.fill(); ctx.stroke();
    }
    ctx.setLineDash([]);
    // walls
    ctx.strokeStyle = "#aab2c0"; ctx.lineWidth = 2 * px; ctx.lineCap = "round";
    ctx.beginPath();
    for (const w of W.walls) { ctx.moveTo(+w[0], +w[1]); ctx.lineTo(+w[2], +w[3]); }
    ctx.stroke();
    // doors, coloured by state
    ctx.lineWidth = 4 * px;
    for (const d of W.doors) {
      const a = arr(d.a).map(num), b = arr(d.b).map(num);
      if (![a[0], a[1], b[0], b[1]].every(isFinite)) continue;
      ctx.strokeStyle = DOOR_COLORS[d.state] || "#b48cff";
      ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
    }
    // plates: a bar along the wall and a tick along the normal
    ctx.strokeStyle = "#e0e0e0"; ctx.lineWidth = 2 * px;
    for (const p of W.plates) {
      const c = arr(p.center).map(num), n = arr(p.normal).map(num);
      if (!(isFinite(c[0]) && isFinite(c[1]))) continue;
      const nx = isFinite(n[0]) ? n[0] : 0, ny = isFinite(n[1]) ? n[1] : 1, l = Math.hypot(nx, ny) || 1;
      const ux = nx / l, uy = ny / l;
      ctx.beginPath();
      ctx.moveTo(c[0] - uy * 0.15, c[1] + ux * 0.15); ctx.lineTo(c[0] + uy * 0.15, c[1] - ux * 0.15);
      if (isFinite(n[0])) { ctx.moveTo(c[0], c[1]); ctx.lineTo(c[0] + ux * 0.12, c[1] + uy * 0.12); }
      ctx.stroke();
    }
    // distractors: small diamonds
    ctx.fillStyle = "#7d8591";
    for (const q of W.distractors) {
      const c = arr(q.center).map(num);
      if (!(isFinite(c[0]) && isFinite(c[1]))) continue;
      const r = Math.max(0.12, 4 * px);
      ctx.beginPath(); ctx.moveTo(c[0] + r, c[1]); ctx.lineTo(c[0], c[1] + r); ctx.lineTo(c[0] - r, c[1]); ctx.lineTo(c[0], c[1] - r);
      ctx.closePath(); ctx.fill();
    }
    // the whole true path, faint
    ctx.strokeStyle = "rgba(255, 255, 255, 0.16)"; ctx.lineWidth = 1.5 * px; ctx.lineJoin = "round";
    strokePath(ctx, D.truth, 0, D.truth.n - 1);
    // labels in screen space
    screenTransform(ctx);
    if (showLabels()) {
      ctx.font = "11px " + getComputedStyle(document.body).fontFamily;
      ctx.textAlign = "center"; ctx.textBaseline = "middle";
      for (const p of W.plates) {
        const c = arr(p.center).map(num), n = arr(p.normal).map(num);
        if (!(isFinite(c[0]) && isFinite(c[1])) || p.room === null || p.room === undefined || plan.s < 8) continue;
        const off = isFinite(n[0]) && isFinite(n[1]) ? 0.45 : 0.35, l = Math.hypot(n[0], n[1]) || 1;
        const [sx, sy] = toScreen(c[0] + (isFinite(n[0]) ? n[0] / l : 0) * off, c[1] + (isFinite(n[1]) ? n[1] / l : 1) * off);
        label(ctx, String(p.room), sx, sy, "#f3f3f3", "rgba(30, 34, 42, 0.85)");
      }
      for (const d of W.doors) {
        const a = arr(d.a).map(num), b = arr(d.b).map(num);
        if (![a[0], a[1], b[0], b[1]].every(isFinite) || plan.s < 20) continue;
        const [sx, sy] = toScreen((a[0] + b[0]) / 2, (a[1] + b[1]) / 2);
        ctx.fillStyle = DOOR_COLORS[d.state] || "#b48cff";
        ctx.fillText(str(d.state) + (d.room ? " " + d.room : ""), sx, sy - 10);
      }
      if (plan.s >= 30) {
        ctx.fillStyle = "#8b919c";
        for (const q of W.distractors) {
          const c = arr(q.center).map(num);
          if (!(isFinite(c[0]) && isFinite(c[1]))) continue;
          const [sx, sy] = toScreen(c[0], c[1]);
          ctx.fillText(str(q.class), sx, sy + 12);
        }
      }
    }
  }

  function label(ctx, text, x, y, fg, bg) {
    const w = ctx.measureText(text).width + 6;
    ctx.fillStyle = bg; ctx.fillRect(x - w / 2, y - 7, w, 14);
    ctx.fillStyle = fg; ctx.fillText(text, x, y);
  }

  /** A grid of 1, 2 or 5 x 10^k metres, at least 60 px apart, and the scale bar. */
  function drawGrid(ctx) {
    const raw = 60 / plan.s, p10 = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map((k) => k * p10).find((v) => v >= raw);
    const [wx0, wy1] = toWorld(0, 0), [wx1, wy0] = toWorld(plan.w, plan.h);
    ctx.strokeStyle = "rgba(255, 255, 255, 0.05)"; ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = Math.ceil(wx0 / step) * step; x <= wx1; x += step) { const sx = Math.round(toScreen(x, 0)[0]) + 0.5; ctx.moveTo(sx, 0); ctx.lineTo(sx, plan.h); }
    for (let y = Math.ceil(wy0 / step) * step; y <= wy1; y += step) { const sy = Math.round(toScreen(0, y)[1]) + 0.5; ctx.moveTo(0, sy); ctx.lineTo(plan.w, sy); }
    ctx.stroke();
    const bar = $("cs-scalebar");
    bar.firstElementChild.style.width = (step * plan.s).toFixed(0) + "px";
    bar.lastElementChild.textContent = fmt(step) + " m";
  }

  /** Strokes samples i0..i1 of a series with x, y (NaN breaks the line); world transform. */
  function strokePath(ctx, c, i0, i1) {
    if (i1 < i0) return;
    ctx.beginPath();
    let pen = false;
    for (let i = i0; i <= i1; i++) {
      const x = c.x[i], y = c.y[i];
      if (x === x && y === y) { if (pen) ctx.lineTo(x, y); else { ctx.moveTo(x, y); pen = true; } } else pen = false;
    }
    ctx.stroke();
  }

  /** A path up to sample i: whole cached chunks (Path2D) plus the rest, so long paths stay fast. */
  const CHUNK = 2048;
  const truthEntry = { get path() { return D.truth; }, chunks: null };   // the truth, cached like a pipeline
  function strokePathUpTo(ctx, p, i) {
    const c = p.path;
    if (!p.chunks) {
      p.chunks = [];
      for (let k = 0; k + CHUNK < c.n; k += CHUNK) {
        const path = new Path2D();
        let pen = false;
        for (let j = k; j <= k + CHUNK; j++) {
          const x = c.x[j], y = c.y[j];
          if (x === x && y === y) { if (pen) path.lineTo(x, y); else { path.moveTo(x, y); pen = true; } } else pen = false;
        }
        p.chunks.push(path);
      }
    }
    const full = Math.min(Math.floor(i / CHUNK), p.chunks.length);
    for (let k = 0; k < full; k++) ctx.stroke(p.chunks[k]);
    strokePath(ctx, c, full * CHUNK, i);
  }

  function drawArrow(ctx, x, y, yaw, color, size) {
    const [sx, sy] = toScreen(x, y);
    const a = -yaw; // screen y points down
    ctx.save();
    ctx.translate(sx, sy); ctx.rotate(isFinite(a) ? a : 0);
    ctx.beginPath();
    ctx.moveTo(size, 0); ctx.lineTo(-size * 0.6, size * 0.55); ctx.lineTo(-size * 0.3, 0); ctx.lineTo(-size * 0.6, -size * 0.55);
    ctx.closePath();
    ctx.fillStyle = color; ctx.strokeStyle = "rgba(0, 0, 0, 0.8)"; ctx.lineWidth = 1.2;
    ctx.fill(); ctx.stroke();
    ctx.restore();
  }

  function drawEllipse(ctx, e, color, dashed, fillAlpha) {
    if (!e || !(e.a >= 0 && e.b >= 0)) return;
    worldTransform(ctx);
    ctx.beginPath();
    ctx.ellipse(e.cx, e.cy, Math.max(e.a, 0.5 / plan.s), Math.max(e.b, 0.5 / plan.s), e.angle, 0, 2 * Math.PI);
    ctx.setLineDash(dashed ? [4 / plan.s, 3 / plan.s] : []);
    ctx.lineWidth = 1.2 / plan.s; ctx.strokeStyle = color; ctx.stroke();
    if (fillAlpha) { ctx.globalAlpha = fillAlpha; ctx.fillStyle = color; ctx.fill(); ctx.globalAlpha = 1; }
    ctx.setLineDash([]);
  }

  /** A pipeline's landmarks seen by t. Batched: one path per kind of mark, so that thousands of
   *  landmarks cost a few canvas calls, not thousands (software canvases flush on every stroke). */
  function drawLandmarks(ctx, p, t) {
    const px = 1 / plan.s;
    const [vx0, vy1] = toWorld(-50, -50), [vx1, vy0] = toWorld(plan.w + 50, plan.h + 50);
    const seen = [];
    for (const L of p.landmarks) {
      const fs = num(L.first_seen), x = num(L.x), y = num(L.y);
      if (!(L.first_seen === null || L.first_seen === undefined || fs <= t) || !isFinite(x) || !isFinite(y)) continue;
      const tr = arr(L.truth).map(num);
      const hasTruth = isFinite(tr[0]) && isFinite(tr[1]);
      const e = ellipse2(x, y, num(L.cxx), num(L.cxy), num(L.cyy));
      const r = Math.max(e ? e.a : 0, hasTruth ? Math.hypot(tr[0] - x, tr[1] - y) : 0);
      if (x + r < vx0 || x - r > vx1 || y + r < vy0 || y - r > vy1) continue;   // off screen
      seen.push({ L: L, x: x, y: y, tr: hasTruth ? tr : null, e: e });
    }
    if (!seen.length) return;
    const many = seen.length > 150;   // hundreds of corners: lighter marks, no labels
    worldTransform(ctx);
    // thin dashed lines to the matched truth (red when the association is wrong) and its spot
    ctx.lineWidth = 1 * px; ctx.setLineDash([3 * px, 2 * px]);
    for (const wrong of [false, true]) {
      ctx.beginPath();
      for (const q of seen) if (q.tr && !!q.L.wrong === wrong) { ctx.moveTo(q.x, q.y); ctx.lineTo(q.tr[0], q.tr[1]); }
      ctx.strokeStyle = wrong ? "rgba(240, 82, 79, 0.8)" : "rgba(200, 200, 200, 0.35)";
      ctx.stroke();
    }
    ctx.setLineDash([]);
    ctx.beginPath();
    for (const q of seen) if (q.tr) ctx.rect(q.tr[0] - 1.5 * px, q.tr[1] - 1.5 * px, 3 * px, 3 * px);
    ctx.fillStyle = "rgba(220, 220, 220, 0.6)"; ctx.fill();
    // 2-sigma ellipses: solid when converged, dashed while initializing
    ctx.globalAlpha = many ? 0.4 : 0.7; ctx.strokeStyle = p.color; ctx.lineWidth = 1.2 * px;
    for (const init of [false, true]) {
      ctx.setLineDash(init ? [4 * px, 3 * px] : []);
      ctx.beginPath();
      for (const q of seen) {
        if (!q.e || (q.L.status === "initializing") !== init) continue;
        const a = Math.max(q.e.a, 0.5 * px), b = Math.max(q.e.b, 0.5 * px);
        ctx.moveTo(q.x + a * Math.cos(q.e.angle), q.y + a * Math.sin(q.e.angle));
        ctx.ellipse(q.x, q.y, a, b, q.e.angle, 0, 2 * Math.PI);
      }
      ctx.stroke();
    }
    ctx.setLineDash([]); ctx.globalAlpha = 1;
    // the landmarks: a dot per landmark, filled by type, ringed in the pipeline's colour
    screenTransform(ctx);
    const rad = many ? 2 : 3.5, byType = new Map();
    for (const q of seen) {
      const k = str(q.L.type);
      if (!byType.has(k)) byType.set(k, []);
      byType.get(k).push(q);
    }
    ctx.strokeStyle = p.color; ctx.lineWidth = many ? 1 : 1.5;
    for (const [type, list] of byType) {
      ctx.beginPath();
      for (const q of list) { const [sx, sy] = toScreen(q.x, q.y); ctx.moveTo(sx + rad, sy); ctx.arc(sx, sy, rad, 0, 2 * Math.PI); }
      ctx.fillStyle = typeColor(type); ctx.fill(); ctx.stroke();
    }
    // wrong associations: a red cross and a label; other labels when zoomed in
    ctx.textAlign = "left"; ctx.textBaseline = "middle";
    const labels = showLabels() && plan.s >= (many ? 120 : 30);
    for (const q of seen) {
      const [sx, sy] = toScreen(q.x, q.y);
      if (q.L.wrong) {
        ctx.strokeStyle = "#ff4040"; ctx.lineWidth = 2.5;
        ctx.beginPath(); ctx.moveTo(sx - 7, sy - 7); ctx.lineTo(sx + 7, sy + 7); ctx.moveTo(sx + 7, sy - 7); ctx.lineTo(sx - 7, sy + 7); ctx.stroke();
        ctx.fillStyle = "#ff6060"; ctx.fillText("wrong " + str(q.L.label || q.L.type), sx + 9, sy - 8);
      } else if (labels && q.L.label) {
        ctx.fillStyle = "#c5cad3"; ctx.fillText(str(q.L.label), sx + 6, sy - 7);
      }
    }
  }

  const showLabels = () => $("cs-show-world-labels").checked;

  function drawPlanNow() {
    if (!plan.ctx || !snap) return;
    const ctx = plan.ctx, t = snap.t;
    if ($("cs-follow").checked && snap.truth) { plan.cx = snap.truth.x; plan.cy = snap.truth.y; }
    drawStaticLayer();
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(plan.layer, 0, 0);
    ctx.font = "11px " + getComputedStyle(document.body).fontFamily;
    // the true path up to the cursor
    if (snap.truth) {
      worldTransform(ctx);
      ctx.strokeStyle = "rgba(255, 255, 255, 0.75)"; ctx.lineWidth = 1.6 / plan.s; ctx.lineJoin = "round";
      strokePathUpTo(ctx, truthEntry, snap.truth.i);
    }
    const showLm = $("cs-show-landmarks").checked;
    for (const p of D.pipelines) {
      if (!p.visible) continue;
      if (showLm) drawLandmarks(ctx, p, t);
      const q = snap.pipelines[p.name];
      if (!q) continue;
      worldTransform(ctx);
      ctx.strokeStyle = p.color; ctx.lineWidth = 1.8 / plan.s; ctx.lineJoin = "round";
      strokePathUpTo(ctx, p, q.i);
      drawEllipse(ctx, q.ellipse, p.color, false, 0.12);
      screenTransform(ctx);
      if (isFinite(q.x) && isFinite(q.y)) drawArrow(ctx, q.x, q.y, q.yaw, p.color, 11);
    }
    if (D.sensors.lasers.length) drawScans(ctx, t);
    screenTransform(ctx);
    if (snap.truth && isFinite(snap.truth.x)) drawArrow(ctx, snap.truth.x, snap.truth.y, snap.truth.yaw, "#ffffff", 12);
  }

  function initPlan() {
    plan.canvas = $("cs-plan");
    plan.ctx = plan.canvas.getContext("2d");
    plan.layer = document.createElement("canvas");
    const c = plan.canvas;
    let drag = null;
    c.addEventListener("wheel", guard((e) => {
      e.preventDefault();
      const r = c.getBoundingClientRect(), mx = e.clientX - r.left, my = e.clientY - r.top;
      const [wx, wy] = toWorld(mx, my);
      const f = Math.exp(-e.deltaY * (e.deltaMode === 1 ? 0.05 : 0.0015));
      plan.s = Math.min(Math.max(plan.s * f, 0.05), 5000);
      // keep the point under the mouse where it is
      plan.cx = wx - (mx - plan.w / 2) / plan.s; plan.cy = wy + (my - plan.h / 2) / plan.s;
      requestDraw();
    }, "plan zoom"), { passive: false });
    c.addEventListener("pointerdown", guard((e) => {
      drag = { x: e.clientX, y: e.clientY, cx: plan.cx, cy: plan.cy };
      c.setPointerCapture(e.pointerId); c.classList.add("cs-dragging");
    }, "plan drag"));
    c.addEventListener("pointermove", guard((e) => {
      const r = c.getBoundingClientRect();
      const [wx, wy] = toWorld(e.clientX - r.left, e.clientY - r.top);
      $("cs-mouse").textContent = "x " + wx.toFixed(2) + " m   y " + wy.toFixed(2) + " m";
      if (!drag) return;
      if ($("cs-follow").checked) $("cs-follow").checked = false;
      plan.cx = drag.cx - (e.clientX - drag.x) / plan.s; plan.cy = drag.cy + (e.clientY - drag.y) / plan.s;
      requestDraw();
    }, "plan drag"));
    const end = () => { drag = null; c.classList.remove("cs-dragging"); };
    c.addEventListener("pointerup", end); c.addEventListener("pointercancel", end);
    c.addEventListener("pointerleave", () => { $("cs-mouse").textContent = ""; });
    $("cs-fit").addEventListener("click", guard(() => { $("cs-follow").checked = false; fitPlan(); }, "fit"));
    for (const id of ["cs-follow", "cs-show-landmarks", "cs-show-world-labels"]) $(id).addEventListener("change", requestDraw);
    new ResizeObserver(guard(resizePlan, "plan resize")).observe($("cs-plan-wrap"));
    resizePlan();
  }

  // ---------------------------------------------------------------- the legend
  function initLegend() {
    const box = $("cs-legend");
    box.append(el("span", {}, [el("span", { cls: "cs-swatch", style: "background:#fff" }), "truth"]));
    for (const p of D.pipelines) {
      const cb = el("input", { type: "checkbox" });
      cb.checked = true;
      cb.addEventListener("change", () => { p.visible = cb.checked; requestDraw(); });
      const err = el("span", { cls: "cs-hint" });
      p.legendErr = err;
      box.append(el("label", { title: p.failed ? "failed: " + p.failed : "show / hide " + p.name }, [
        cb, el("span", { cls: "cs-swatch", style: "background:" + p.color }), p.name,
        p.failed ? el("span", { cls: "cs-failed", text: "failed" }) : null, " ", err]));
    }
    // the position error at the cursor (pipeline sample against the truth at its stamp)
    listeners.push((s) => {
      for (const p of D.pipelines) {
        const q = s.pipelines[p.name];
        let text = "";
        if (q && p.truthAt) {
          const e = Math.hypot(q.x - p.truthAt.x[q.i], q.y - p.truthAt.y[q.i]);
          if (isFinite(e)) text = "Δ " + e.toFixed(3) + " m";
        }
        p.legendErr.textContent = text;
      }
    });
  }

