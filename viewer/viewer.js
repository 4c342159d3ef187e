/* corridorsim run viewer (docs/viewer.md): one time cursor driving the plan, the time plots,
 * the camera frames and the events of one run. Reads the JSON in
 * <script id="corridorsim-data">; plain browser JavaScript, no framework, works from file://.
 * Test API: window.corridorsimViewer = {ready, setTime(t), state(), errors}. */
(function () {
  "use strict";

  // ---------------------------------------------------------------- errors and the test API
  const api = { ready: false, errors: [], setTime: setTimeApi, state: stateApi };
  window.corridorsimViewer = api;

  function report(err, where) {
    const msg = (where ? where + ": " : "") +
      (err && err.stack ? String(err.stack).split("\n").slice(0, 3).join(" | ") : String(err));
    api.errors.push(msg);
    const box = document.getElementById("cs-errors");
    if (box) { box.hidden = false; box.textContent = "The page caught errors:\n" + api.errors.join("\n"); }
  }
  window.addEventListener("error", (e) => {
    // Chromium's notice that a resize callback changed the layout again: benign, not an error.
    if (!e.error && /^ResizeObserver loop/.test(String(e.message))) return;
    report(e.error || e.message, "window.onerror");
  });
  window.addEventListener("unhandledrejection", (e) => report(e.reason, "unhandled rejection"));
  /** fn wrapped so that an exception is recorded instead of escaping. */
  function guard(fn, where) {
    return function () {
      try { return fn.apply(this, arguments); } catch (e) { report(e, where); return undefined; }
    };
  }

  // ---------------------------------------------------------------- small helpers
  const $ = (id) => document.getElementById(id);
  const isObj = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
  const num = (v) => (typeof v === "number" && isFinite(v) ? v : NaN);
  const arr = (v) => (Array.isArray(v) ? v : []);
  const str = (v, dflt) => (v === null || v === undefined ? (dflt === undefined ? "" : dflt) : String(v));
  const DEG = 180 / Math.PI;

  function el(tag, attrs, children) {
    const e = document.createElement(tag);
    if (attrs) for (const k in attrs) {
      if (k === "text") e.textContent = attrs[k];
      else if (k === "cls") e.className = attrs[k];
      else if (k.startsWith("on")) e.addEventListener(k.slice(2), guard(attrs[k], tag + " " + k));
      else e.setAttribute(k, attrs[k]);
    }
    for (const c of children || []) if (c !== null && c !== undefined) e.append(c);
    return e;
  }

  /** A number for a table: 4 significant digits, integers as they are. */
  function fmt(v) {
    if (typeof v !== "number") return v === null || v === undefined ? "–" : String(v);
    if (!isFinite(v)) return String(v);
    if (Number.isInteger(v)) return String(v);
    const a = Math.abs(v);
    if (a !== 0 && (a < 1e-3 || a >= 1e6)) return v.toExponential(3);
    return String(Number(v.toPrecision(4)));
  }

  /** Largest i with a[i] <= t (a ascending), -1 when none. */
  function lastAtOrBefore(a, t) {
    let lo = 0, hi = a.length - 1, r = -1;
    while (lo <= hi) {
      const m = (lo + hi) >> 1;
      if (a[m] <= t) { r = m; lo = m + 1; } else hi = m - 1;
    }
    return r;
  }
  /** Smallest i with a[i] >= t, a.length when none. */
  function firstAtOrAfter(a, t) {
    let lo = 0, hi = a.length;
    while (lo < hi) { const m = (lo + hi) >> 1; if (a[m] < t) lo = m + 1; else hi = m; }
    return lo;
  }

  /** The 2-sigma ellipse of a 2x2 covariance: semi-axes a >= b (m), angle of a (rad, from +x). */
  function ellipse2(cx, cy, cxx, cxy, cyy) {
    if (![cx, cy, cxx, cxy, cyy].every(isFinite)) return null;
    const m = (cxx + cyy) / 2, r = Math.hypot((cxx - cyy) / 2, cxy);
    return {
      cx: cx, cy: cy,
      a: 2 * Math.sqrt(Math.max(m + r, 0)),
      b: 2 * Math.sqrt(Math.max(m - r, 0)),
      angle: 0.5 * Math.atan2(2 * cxy, cxx - cyy),
    };
  }

  /** Columns of a series object as Float64Arrays (NaN for null or missing), sorted by t. */
  function columns(obj, keys) {
    const tSrc = isObj(obj) ? arr(obj.t) : [];
    const n = tSrc.length;
    const out = { n: n };
    for (const k of ["t"].concat(keys)) {
      const src = isObj(obj) ? arr(obj[k]) : [];
      const a = new Float64Array(n);
      for (let i = 0; i < n; i++) a[i] = i < src.length ? num(src[i]) : NaN;
      out[k] = a;
    }
    // Samples without a finite stamp are dropped; out-of-order ones sorted (stable).
    let ok = true;
    for (let i = 0; i < n && ok; i++) ok = isFinite(out.t[i]) && (i === 0 || out.t[i] >= out.t[i - 1]);
    if (!ok) {
      const idx = [];
      for (let i = 0; i < n; i++) if (isFinite(out.t[i])) idx.push(i);
      idx.sort((i, j) => out.t[i] - out.t[j] || i - j);
      for (const k of ["t"].concat(keys)) out[k] = Float64Array.from(idx, (i) => out[k][i]);
      out.n = idx.length;
    }
    return out;
  }

  // ---------------------------------------------------------------- the data
  const PALETTE = ["#6ea8ff", "#ff9f43", "#2ed3b7", "#e86bd8", "#b5e853", "#ff6b6b", "#c9a0ff", "#ffd166"];
  const TYPE_COLORS = ["#4fc3f7", "#ffb74d", "#81c784", "#f06292", "#ba68c8", "#fff176", "#a1887f", "#90a4ae"];
  const typeColorMap = new Map();
  function typeColor(type) {
    if (!typeColorMap.has(type)) typeColorMap.set(type, TYPE_COLORS[typeColorMap.size % TYPE_COLORS.length]);
    return typeColorMap.get(type);
  }

  let D = null;          // the normalised data
  let stamps = new Float64Array([0]); // the cursor's times: truth.t union every path.t
  let cur = 0;           // the cursor: an index into stamps
  let snap = null;       // what is drawn at the cursor (state() reports it)

  function loadData() {
    let raw = {};
    const node = document.getElementById("corridorsim-data");
    const text = node ? node.textContent.trim() : "";
    if (text && text !== "CORRIDORSIM_" + "DATA_JSON") {
      try { raw = JSON.parse(text); } catch (e) { report(e, "reading the page's data"); raw = {}; }
    }
    if (!isObj(raw)) raw = {};
    const world = isObj(raw.world) ? raw.world : {};
    const d = {
      title: str(raw.title, "corridorsim run"), scenario: str(raw.scenario), seed: raw.seed,
      duration: num(raw.duration_s),
      world: {
        bounds: arr(world.bounds).map(num),
        walls: arr(world.walls).filter((w) => arr(w).length >= 4 && arr(w).slice(0, 4).every((v) => isFinite(num(v)))),
        doors: arr(world.doors).filter(isObj), plates: arr(world.plates).filter(isObj),
        lamps: arr(world.lamps).filter(isObj), distractors: arr(world.distractors).filter(isObj),
      },
      truth: columns(raw.truth, ["x", "y", "yaw"]),
      pipelines: [],
      events: arr(raw.events).filter(isObj).map((e) => ({ t: num(e.t), type: str(e.type, "event"), text: str(e.text) }))
        .filter((e) => isFinite(e.t)).sort((a, b) => a.t - b.t),
      expectations: arr(raw.expectations).filter(isObj),
      frames: isObj(raw.frames) ? raw.frames : {},
    };
    let ci = 0;
    arr(raw.pipelines).filter(isObj).forEach((p, k) => {
      const name = str(p.name, "pipeline_" + k);
      const path = columns(p.path, ["x", "y", "yaw", "cxx", "cxy", "cyy"]);
      // truth_at is parallel to path (same stamps) but carries no t of its own.
      const ta = isObj(p.truth_at) ? p.truth_at : {};
      const tAt = columns({ t: isObj(p.path) ? arr(p.path.t) : [], x: ta.x, y: ta.y, yaw: ta.yaw }, ["x", "y", "yaw"]);
      const nis = [];
      if (isObj(p.nis)) for (const type of Object.keys(p.nis)) {
        const s = p.nis[type];
        if (!isObj(s)) continue;
        nis.push({ type: type, dof: s.dof, band: arr(s.band).map(num), c: columns(s, ["nis", "accepted"]) });
      }
      const dets = arr(p.detections).filter((q) => isObj(q) && isFinite(num(q.t)));
      const detByCam = new Map();
      for (const q of dets) {
        const cam = str(q.camera, "?");
        if (!detByCam.has(cam)) detByCam.set(cam, []);
        detByCam.get(cam).push(q);
      }
      for (const list of detByCam.values()) list.sort((a, b) => a.t - b.t);
      const color = name === "odometry" ? "#a7adb8" : PALETTE[ci++ % PALETTE.length];
      d.pipelines.push({
        name: name, failed: p.failed === null || p.failed === undefined ? null : str(p.failed, "failed"),
        color: color, visible: true,
        path: path, truthAt: tAt.n === path.n ? tAt : null,
        errors: columns(p.errors, ["ex", "ey", "eyaw", "sx", "sy", "syaw", "nees"]),
        neesBand: arr(p.nees_band).map(num),
        nis: nis,
        frameMs: isObj(p.frame_ms) ? columns(p.frame_ms, ["ms", "landmarks"]) : null,
        cost: isObj(p.cost) ? p.cost : null,
        landmarks: arr(p.landmarks).filter(isObj),
        detByCam: detByCam, detTimes: new Map(Array.from(detByCam, ([k, v]) => [k, Float64Array.from(v, (q) => q.t)])),
        metrics: isObj(p.metrics) ? p.metrics : {},
        chunks: null,
      });
    });
    return d;
  }

  function buildStamps() {
    const parts = [D.truth.t].concat(D.pipelines.map((p) => p.path.t));
    let n = 0;
    for (const a of parts) n += a.length;
    const all = new Float64Array(n);
    let o = 0;
    for (const a of parts) { all.set(a, o); o += a.length; }
    all.sort();
    let m = 0;
    for (let i = 0; i < all.length; i++) if (isFinite(all[i]) && (m === 0 || all[i] !== all[m - 1])) all[m++] = all[i];
    stamps = m ? all.slice(0, m) : new Float64Array([0]);
  }
  const T0 = () => stamps[0];
  const T1 = () => Math.max(stamps[stamps.length - 1], isFinite(D.duration) ? D.duration : -Infinity);

  /** What is drawn at the cursor: for the truth and each pipeline the last sample at or before it. */
  function makeSnapshot() {
    const t = stamps[cur];
    const s = { t: t, truth: null, pipelines: {} };
    const ti = lastAtOrBefore(D.truth.t, t);
    if (ti >= 0) s.truth = { t: D.truth.t[ti], x: D.truth.x[ti], y: D.truth.y[ti], yaw: D.truth.yaw[ti], i: ti };
    for (const p of D.pipelines) {
      const c = p.path, i = lastAtOrBefore(c.t, t);
      if (i < 0) { s.pipelines[p.name] = null; continue; }
      s.pipelines[p.name] = {
        t: c.t[i], x: c.x[i], y: c.y[i], yaw: c.yaw[i], i: i,
        ellipse: ellipse2(c.x[i], c.y[i], c.cxx[i], c.cxy[i], c.cyy[i]),
      };
    }
    return s;
  }

  function stateApi() {
    if (!snap) return null;
    const pose = (q) => (q ? { t: q.t, x: q.x, y: q.y, yaw: q.yaw } : null);
    const out = { t: snap.t, truth: pose(snap.truth), pipelines: {} };
    for (const name in snap.pipelines) {
      const q = snap.pipelines[name];
      out.pipelines[name] = q ? Object.assign(pose(q), { ellipse: q.ellipse ? Object.assign({}, q.ellipse) : null }) : null;
    }
    return out;
  }

  function setTimeApi(t) {
    try {
      t = Number(t);
      if (!isFinite(t) || !D) return undefined;
      setIndex(Math.max(lastAtOrBefore(stamps, t), 0), { url: "now" });
      drawPlanNow();
      return stamps[cur];
    } catch (e) { report(e, "setTime"); return undefined; }
  }

  // ---------------------------------------------------------------- the cursor
  const listeners = [];   // called with the snapshot on every cursor move
  let urlTimer = 0;

  function setIndex(i, opts) {
    cur = Math.min(Math.max(i | 0, 0), stamps.length - 1);
    snap = makeSnapshot();
    for (const f of listeners) { try { f(snap); } catch (e) { report(e, "cursor listener"); } }
    requestDraw();
    // The URL follows the cursor; while playing at most four times a second.
    const mode = opts && opts.url;
    clearTimeout(urlTimer);
    if (mode === "now") writeUrl();
    else if (mode !== "none") urlTimer = setTimeout(guard(writeUrl, "url"), 250);
  }

  function writeUrl() {
    const hash = "#t=" + String(stamps[cur]);
    if (location.hash === hash) return;
    try { history.replaceState(null, "", hash); } catch (e) { /* some browsers refuse it on file:// */ }
  }

  function timeFromHash() {
    const m = /(?:^#|&)t=([-+0-9.eE]+)/.exec(location.hash || "");
    const t = m ? parseFloat(m[1]) : NaN;
    return isFinite(t) ? t : null;
  }

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

  // ---------------------------------------------------------------- time plots (uPlot)
  const plots = [];      // {u, line}
  let syncingScale = false;
  const AXIS = { stroke: "#8b919c", grid: { stroke: "rgba(255,255,255,0.06)", width: 1 }, ticks: { stroke: "rgba(255,255,255,0.12)", width: 1 }, font: "11px sans-serif", labelFont: "11px sans-serif" };

  /** Float64Array to a plain array with null gaps (uPlot draws gaps at null). */
  function gaps(a, f) {
    const out = new Array(a.length);
    for (let i = 0; i < a.length; i++) { const v = f ? f(a[i]) : a[i]; out[i] = v === v && isFinite(v) ? v : null; }
    return out;
  }
  const hasFinite = (a) => { for (let i = 0; i < a.length; i++) if (isFinite(a[i])) return true; return false; };

  const decades = (u, splits) => splits.map((v) => (Math.abs(Math.log10(v) - Math.round(Math.log10(v))) < 1e-6 ? v : null));

  /** One plot: spec = {title, note, unit, t, series:[{label, data, color, width, dash, points}],
   *  bands:[[upper, lower, fill]], hband:[lo, hi], log, y2:{label}}. */
  function addPlot(box, spec) {
    const wrap = el("div", { cls: "cs-plot" }, [el("div", { cls: "cs-plot-title" }, [spec.title, spec.note ? el("small", { text: spec.note }) : null])]);
    box.append(wrap);
    if (!spec.t.length) { wrap.append(el("div", { cls: "cs-plot-empty", text: "no samples" })); return; }
    const series = [{ label: "t", value: (u, v) => (v === null || v === undefined ? "–" : v.toFixed(3) + " s") }];
    for (const s of spec.series) {
      series.push({
        label: s.label, stroke: s.color, width: s.width || 1, dash: s.dash, scale: s.scale || "y",
        spanGaps: false, points: s.points ? { show: true, size: 3, fill: s.color, stroke: s.color } : { show: false },
        paths: s.points ? () => null : undefined,
        value: (u, v) => (v === null || v === undefined ? "–" : fmt(v)),
      });
    }
    const hband = spec.hband && spec.hband.length === 2 && spec.hband.every(isFinite) ? spec.hband : null;
    const axes = [Object.assign({ label: "time [s]", labelSize: 16, size: 34 }, AXIS),
      Object.assign({ label: spec.unit, labelSize: 16, size: 52 }, AXIS,
        // a log axis: ticks and grid at the decades only, the minor ones only clutter
        spec.log ? { filter: decades, values: (u, splits) => splits.map((v) => (v === null || v === undefined ? null : v >= 0.01 && v < 1e5 ? fmt(v) : v.toExponential(0))), grid: Object.assign({ filter: decades }, AXIS.grid), ticks: Object.assign({ filter: decades }, AXIS.ticks) } : {})];
    const scales = { x: { time: false }, y: spec.log ? { distr: 3, log: 10 } : {} };
    if (hband) scales.y.range = (u, lo, hi) => bandRange(lo, hi, hband, spec.log);
    if (spec.y2) { axes.push(Object.assign({ scale: "y2", side: 1, label: spec.y2.label, labelSize: 16, size: 46, grid: { show: false } }, AXIS, { grid: { show: false } })); scales.y2 = {}; }
    const data = [gaps(spec.t)].concat(spec.series.map((s) => s.data));
    const entry = { u: null, line: null, wrap: wrap, t: spec.t };
    const u = new uPlot({
      width: Math.max(box.clientWidth - 8, 200), height: spec.height || 150,
      legend: { live: true }, cursor: { sync: { key: "cs" }, drag: { x: true, y: false }, points: { size: 5 } },
      scales: scales, axes: axes, series: series,
      bands: (spec.bands || []).map((b) => ({ series: [b[0], b[1]], fill: b[2] })),
      hooks: {
        drawClear: [(u) => {   // the chi-square band, under the series
          if (!hband) return;
          const ctx = u.ctx, { left, width } = u.bbox;
          const y0 = u.valToPos(hband[1], "y", true), y1 = u.valToPos(hband[0], "y", true);
          if (!isFinite(y0) || !isFinite(y1)) return;
          ctx.save(); ctx.fillStyle = "rgba(63, 185, 112, 0.13)"; ctx.fillRect(left, y0, width, y1 - y0);
          ctx.strokeStyle = "rgba(63, 185, 112, 0.55)"; ctx.lineWidth = 1;
          ctx.beginPath(); ctx.moveTo(left, y0); ctx.lineTo(left + width, y0); ctx.moveTo(left, y1); ctx.lineTo(left + width, y1); ctx.stroke();
          ctx.restore();
        }],
        setScale: [(u, key) => { if (key === "x") onXScale(u); }],
        setSize: [() => placeLine(entry)],
        // with the mouse away the legend shows the values at the time cursor
        setCursor: [(u) => { if (u.cursor.idx === null || u.cursor.idx === undefined) legendAtCursor(entry); }],
      },
    }, data, wrap);
    const line = el("div", { cls: "cs-cursor-line" });
    u.over.append(line);
    // a click (not a drag) moves the cursor there
    let downX = null;
    u.over.addEventListener("mousedown", (e) => { downX = e.clientX; });
    u.over.addEventListener("click", guard((e) => {
      if (downX !== null && Math.abs(e.clientX - downX) > 3) return;
      const r = u.over.getBoundingClientRect();
      const t = u.posToVal(e.clientX - r.left, "x");
      if (isFinite(t)) { stop(); setIndex(Math.max(lastAtOrBefore(stamps, t), 0), { url: "now" }); }
    }, "plot click"));
    entry.u = u; entry.line = line;
    plots.push(entry);
    u.setScale("x", { min: T0(), max: T1() });
    placeLine(entry);
  }

  /** A y range that holds the data in view and the band [lo, hi] (a log one: positive values). */
  function bandRange(dmin, dmax, band, log) {
    let lo = band[0], hi = band[1];
    if (dmin !== null && isFinite(dmin)) lo = Math.min(lo, dmin);
    if (dmax !== null && isFinite(dmax)) hi = Math.max(hi, dmax);
    if (log) return uPlot.rangeLog(Math.max(lo, 1e-6), Math.max(hi, 1e-5), 10, true);
    return uPlot.rangeNum(lo, hi, 0.1, true);
  }

  function onXScale(u) {
    for (const p of plots) if (p.u === u) { placeLine(p); p.wrap.dataset.xmin = u.scales.x.min; p.wrap.dataset.xmax = u.scales.x.max; }
    if (syncingScale) return;
    syncingScale = true;   // zoom all plots together
    try { for (const p of plots) if (p.u !== u) p.u.setScale("x", { min: u.scales.x.min, max: u.scales.x.max }); } finally { syncingScale = false; }
  }

  function legendAtCursor(p) {
    if (!snap || !p.u) return;
    const i = lastAtOrBefore(p.t, snap.t);
    p.u.setLegend({ idx: i < 0 ? null : i }, false);
  }

  function placeLine(p) {
    if (!snap || !p.u) return;
    if (p.u.cursor.idx === null || p.u.cursor.idx === undefined) legendAtCursor(p);
    const x = p.u.valToPos(snap.t, "x");
    const inside = isFinite(x) && x >= 0 && x <= p.u.bbox.width / (window.devicePixelRatio || 1) + 0.5;
    p.line.style.display = inside ? "" : "none";
    if (inside) p.line.style.left = x + "px";
  }

  let focus = null;  // the pipeline whose plots and detections are shown

  function buildPlots() {
    for (const p of plots) p.u.destroy();
    plots.length = 0;
    const box = $("cs-plots");
    box.textContent = "";
    if (typeof uPlot !== "function") { box.append(el("div", { cls: "cs-plot-empty", text: "uPlot is not in this page: no plots." })); return; }
    const p = focus;
    if (!p) { box.append(el("div", { cls: "cs-plot-empty", text: "No pipelines in this run." })); return; }
    if (p.failed) box.append(el("div", { cls: "cs-plot-empty", text: p.name + " failed: " + p.failed }));
    const E = p.errors, t = E.t;
    const band = "rgba(110, 168, 255, 0.14)", sig = "rgba(110, 168, 255, 0.7)";
    const errPlot = (title, unit, e, s, k) => addPlot(box, {
      title: title, unit: unit, t: t, note: "± 2σ shaded",
      series: [{ label: "error", data: gaps(e, (v) => v * k), color: p.color, width: 1.2 },
        { label: "+2σ", data: gaps(s, (v) => 2 * v * k), color: sig, dash: [4, 3] },
        { label: "−2σ", data: gaps(s, (v) => -2 * v * k), color: sig, dash: [4, 3] }],
      bands: [[2, 3, band]],
    });
    errPlot("x error", "m", E.ex, E.sx, 1);
    errPlot("y error", "m", E.ey, E.sy, 1);
    errPlot("heading error", "deg", E.eyaw, E.syaw, DEG);
    const nb = p.neesBand;
    addPlot(box, {
      title: "NEES", unit: "NEES (log)", t: t, log: true, hband: nb,
      note: nb.length === 2 && nb.every(isFinite) ? "95 % band [" + fmt(nb[0]) + ", " + fmt(nb[1]) + "] shaded" : "",
      series: [{ label: "NEES", data: gaps(E.nees, (v) => (v > 0 ? v : NaN)), color: p.color, width: 1.2 }],
    });
    for (const s of p.nis) {
      const acc = s.c.accepted;
      const keep = (want) => gaps(s.c.nis, null).map((v, i) => (v !== null && v > 0 && (acc[i] !== 0) === want ? v : null));
      addPlot(box, {
        title: "NIS · " + s.type, unit: "NIS (log)", t: s.c.t, log: true, hband: s.band,
        note: (isFinite(num(s.dof)) ? s.dof + " dof, " : "") + (s.band.length === 2 ? "95 % band shaded, " : "") + "rejected in red",
        series: [{ label: "accepted", data: keep(true), color: typeColor(s.type), points: true },
          { label: "rejected", data: keep(false), color: "#ff4d4d", points: true }],
      });
    }
    if (p.frameMs && p.frameMs.n) {
      const F = p.frameMs;
      addPlot(box, {
        title: "time per frame", unit: "ms", t: F.t, y2: { label: "landmarks" },
        series: [{ label: "frame", data: gaps(F.ms), color: p.color, width: 1 },
          { label: "landmarks", data: gaps(F.landmarks), color: "#8b919c", width: 1, dash: [3, 3], scale: "y2" }],
      });
    }
    // What it cost (timing.json): the pipeline's own stages and CPU time; for a program, the round
    // trips and both sides of the connection, each named.
    const lines = costLines(p.cost);
    if (lines.length) {
      box.append(el("div", { cls: "cs-plot cs-cost" }, [el("div", { cls: "cs-plot-title" }, ["cost", el("small", { text: "timing.json, wall clock" })])]
        .concat(lines.map((l) => el("div", { cls: "cs-cost-line", text: l })))));
    } else if (!(p.frameMs && p.frameMs.n)) {
      box.append(el("div", { cls: "cs-plot" }, [el("div", { cls: "cs-plot-title", text: "cost" }),
        el("div", { cls: "cs-plot-empty", text: "not recorded for " + p.name })]));
    }
  }

  /** The lines of a pipeline's cost box from its timing.json section (docs/protocol.md, "Cost"). */
  function costLines(c) {
    const out = [];
    if (!isObj(c)) return out;
    const has = (v) => isFinite(num(v));
    const ms = (v) => fmt(num(v)) + " ms";
    const sec = (v) => fmt(num(v)) + " s";
    const stages = isObj(c.stage_seconds) ? Object.keys(c.stage_seconds).filter((k) => has(c.stage_seconds[k])) : [];
    const P = isObj(c.protocol) ? c.protocol : null;
    if (stages.length) {
      out.push((P ? "program's own stages (as it reports): " : "own stages: ") +
        stages.map((k) => k + " " + sec(c.stage_seconds[k])).join(", ") +
        (has(c.total_ms_per_frame) ? " · " + ms(c.total_ms_per_frame) + " a frame" : ""));
    }
    if (has(c.cpu_seconds)) {
      out.push("CPU time of its calls: " + sec(c.cpu_seconds) + (has(c.cpu_ms_per_frame) ? " · " + ms(c.cpu_ms_per_frame) + " a frame" : ""));
    }
    if (!P) return out;
    const trips = isObj(P.round_trip_ms) ? P.round_trip_ms : {};
    for (const kind of Object.keys(trips)) {
      const r = trips[kind];
      if (!isObj(r) || !has(r.p50)) continue;
      out.push("round trip, " + kind + " (" + fmt(num(r.messages)) + "): median " + ms(r.p50) +
        (has(r.p90) ? ", p90 " + ms(r.p90) : "") + (has(r.max) ? ", max " + ms(r.max) : ""));
    }
    out.push("program, as it reports (stage_seconds): " + (has(P.program_reported_seconds)
      ? sec(P.program_reported_seconds) + (has(P.program_reported_ms_per_message) ? " · " + ms(P.program_reported_ms_per_message) + " a message" : "")
      : "not sent"));
    out.push("program CPU, measured: " + (has(P.program_cpu_seconds)
      ? sec(P.program_cpu_seconds) + (has(P.program_cpu_ms_per_message) ? " · " + ms(P.program_cpu_ms_per_message) + " a message" : "") +
        (has(P.program_peak_rss_mib) ? " · peak " + fmt(num(P.program_peak_rss_mib)) + " MiB" : "")
      : "not known"));
    if (has(P.corridorsim_cpu_seconds)) {
      out.push("corridorsim's side CPU: " + sec(P.corridorsim_cpu_seconds) +
        (has(P.corridorsim_cpu_ms_per_message) ? " · " + ms(P.corridorsim_cpu_ms_per_message) + " a message" : ""));
    }
    return out;
  }

  function initPlots() {
    const sel = $("cs-focus");
    for (const p of D.pipelines) sel.append(el("option", { value: p.name, text: p.name + (p.failed ? " (failed)" : "") }));
    // the first working pipeline with errors, odometry last (the SLAM pipelines are what one looks at)
    const order = D.pipelines.filter((p) => p.name !== "odometry").concat(D.pipelines.filter((p) => p.name === "odometry"));
    focus = order.find((p) => !p.failed && p.errors.n) || order.find((p) => !p.failed) || order[0] || null;
    if (focus) sel.value = focus.name;
    sel.addEventListener("change", guard(() => {
      focus = D.pipelines.find((p) => p.name === sel.value) || null;
      buildPlots(); updateFrames(true);
    }, "pipeline choice"));
    buildPlots();
    listeners.push(() => { for (const p of plots) placeLine(p); });
    let lastW = 0;
    new ResizeObserver(guard(() => {
      const w = $("cs-plots").clientWidth;
      if (Math.abs(w - lastW) < 2) return;
      lastW = w;
      for (const p of plots) p.u.setSize({ width: Math.max(w - 8, 200), height: p.u.height });
    }, "plot resize")).observe($("cs-plots"));
  }

  // ---------------------------------------------------------------- camera frames
  const frameViews = [];   // {cam, data, img, canvas, cap, shown}

  function initFrames() {
    const box = $("cs-frames");
    const cams = Object.keys(D.frames).filter((k) => isObj(D.frames[k]));
    if (!cams.length) {
      box.append(el("div", { cls: "cs-frames-empty" }, ["This run did not keep its camera frames (run ",
        el("code", { text: "corridorsim run --keep-frames" }), " to keep them)."]));
      $("cs-frames-hint").textContent = "";
      return;
    }
    $("cs-frames-hint").textContent = "detections of the chosen pipeline drawn on the last frame at or before the cursor";
    for (const cam of cams) {
      const F = D.frames[cam];
      const t = arr(F.t).map(num), jpeg = arr(F.jpeg);
      const data = { t: Float64Array.from(t), jpeg: jpeg, scale: isFinite(num(F.scale)) ? num(F.scale) : 1 };
      const img = el("img", { alt: cam });
      const canvas = el("canvas");
      const cap = el("figcaption"), det = el("figcaption");
      const fig = el("figure", { cls: "cs-frame" }, [img, canvas, cap, det]);
      fig.style.margin = "0";
      box.append(fig);
      const v = { cam: cam, data: data, img: img, canvas: canvas, cap: cap, det: det, shown: -2 };
      img.addEventListener("load", guard(() => drawDetections(v), "frame load"));
      frameViews.push(v);
    }
    listeners.push(() => updateFrames(false));
    new ResizeObserver(() => requestAnimationFrame(guard(() => { for (const v of frameViews) drawDetections(v); }, "frame resize"))).observe(box);
  }

  function updateFrames(force) {
    if (!snap) return;
    for (const v of frameViews) {
      const i = lastAtOrBefore(v.data.t, snap.t);
      if (i === v.shown && !force) continue;
      v.shown = i;
      if (i < 0 || !isBase64(v.data.jpeg[i])) {
        v.img.removeAttribute("src");
        v.img.hidden = true;
        v.cap.textContent = v.cam + (i < 0 ? " · no frame yet" : " · frame " + (i + 1) + " is not a JPEG in base64");
        drawDetections(v);
        continue;
      }
      v.cap.textContent = v.cam + " · t = " + v.data.t[i].toFixed(3) + " s · frame " + (i + 1) + "/" + v.data.t.length;
      v.img.hidden = false;
      const src = "data:image/jpeg;base64," + v.data.jpeg[i];
      if (v.img.getAttribute("src") !== src) v.img.src = src; else drawDetections(v);
    }
  }

  /** A base64 string (a broken one would only give the browser's "invalid URL" error). */
  const isBase64 = (s) => typeof s === "string" && s.length > 0 && s.length % 4 === 0 && /^[A-Za-z0-9+/]+={0,2}$/.test(s);

  /** The focused pipeline's detections at the frame's stamp (within 1e-3 s), scaled to the image. */
  function drawDetections(v) {
    const img = v.img, c = v.canvas;
    const w = img.clientWidth, h = img.clientHeight, dpr = window.devicePixelRatio || 1;
    c.width = Math.round(w * dpr); c.height = Math.round(h * dpr);
    c.style.width = w + "px"; c.style.height = h + "px";
    const ctx = c.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    v.det.textContent = "";
    if (v.shown < 0 || !focus || !img.naturalWidth || !img.getAttribute("src")) return;
    const list = focus.detByCam.get(v.cam), times = focus.detTimes.get(v.cam);
    if (!list) { v.det.textContent = focus.name + ": no detections from " + v.cam; return; }
    const ft = v.data.t[v.shown];
    const k = (w / img.naturalWidth) * v.data.scale;  // rendered px -> displayed px
    ctx.font = "11px sans-serif"; ctx.textBaseline = "bottom"; ctx.lineWidth = 1.5;
    const counts = {};
    for (let i = firstAtOrAfter(times, ft - 1e-3); i < list.length && list[i].t <= ft + 1e-3; i++) {
      const q = list[i], col = typeColor(str(q.type));
      const assoc = num(q.landmark) >= 0;
      const n = counts[str(q.type)] || (counts[str(q.type)] = [0, 0]);
      n[0]++; if (assoc) n[1]++;
      ctx.strokeStyle = col; ctx.fillStyle = col;
      ctx.setLineDash(assoc ? [] : [4, 3]);
      const b = arr(q.box).map(num);
      let lx, ly;
      if (b.length === 4 && b.every(isFinite)) {
        ctx.strokeRect(b[0] * k, b[1] * k, (b[2] - b[0]) * k, (b[3] - b[1]) * k);
        lx = b[0] * k; ly = b[1] * k - 1;
      } else if (isFinite(num(q.u)) && isFinite(num(q.v))) {
        ctx.beginPath(); ctx.arc(num(q.u) * k, num(q.v) * k, 4, 0, 2 * Math.PI); ctx.stroke();
        lx = num(q.u) * k + 5; ly = num(q.v) * k - 4;
      } else continue;
      if (q.label) ctx.fillText(str(q.label) + (assoc ? " #" + q.landmark : ""), lx, ly);
    }
    ctx.setLineDash([]);
    v.det.textContent = Object.keys(counts).length ? focus.name + ": " + Object.keys(counts).map((k) =>
      counts[k][0] + " " + k + " (" + counts[k][1] + " associated)").join(" · ") + "; dashed: not associated" : focus.name + ": no detections on this frame";
  }

  // ---------------------------------------------------------------- events, expectations, metrics
  function eventColor(type) {
    const t = type.toLowerCase();
    if (t.includes("collision")) return "#f0524f";
    if (t.includes("slip")) return "#e8a33d";
    if (t.includes("drop")) return "#b48cff";
    if (t.includes("fail")) return "#ff4fd8";
    return "#8b919c";
  }

  let eventRows = [], eventCurrent = -1;

  function initEvents() {
    const marks = $("cs-marks"), span = T1() - T0();
    // one mark per event; more than a mark per pixel would only slow the page, so cap them
    const seen = new Set();
    for (const e of D.events) {
      const f = span > 0 ? (e.t - T0()) / span : 0;
      const key = Math.round(f * 1500) + e.type;
      if (seen.has(key)) continue;
      seen.add(key);
      const m = el("button", { cls: "cs-mark", type: "button", title: e.t.toFixed(3) + " s · " + e.type + (e.text ? ": " + e.text : ""),
        onclick: () => { stop(); setIndex(Math.max(lastAtOrBefore(stamps, e.t), 0), { url: "now" }); } });
      m.style.left = (Math.min(Math.max(f, 0), 1) * 100).toFixed(3) + "%";
      m.style.background = eventColor(e.type);
      m.dataset.t = e.t;
      marks.append(m);
    }
    const table = $("cs-events");
    if (!D.events.length) { table.replaceWith(el("div", { cls: "cs-empty", text: "No events." })); return; }
    const counts = {};
    for (const e of D.events) counts[e.type] = (counts[e.type] || 0) + 1;
    $("cs-events-hint").textContent = Object.keys(counts).map((k) => counts[k] + " " + k).join(" · ");
    table.append(el("tr", {}, [el("th", { text: "t [s]" }), el("th", { text: "type" }), el("th", { text: "what" })]));
    const LIMIT = 3000;
    D.events.slice(0, LIMIT).forEach((e) => {
      const tag = el("span", { cls: "cs-type", text: e.type });
      tag.style.background = eventColor(e.type);
      const row = el("tr", { cls: "cs-clickable", onclick: () => { stop(); setIndex(Math.max(lastAtOrBefore(stamps, e.t), 0), { url: "now" }); } },
        [el("td", { text: e.t.toFixed(3) }), el("td", {}, [tag]), el("td", { text: e.text })]);
      eventRows.push(row);
      table.append(row);
    });
    if (D.events.length > LIMIT) table.append(el("tr", {}, [el("td", { colspan: "3", cls: "cs-empty", text: (D.events.length - LIMIT) + " more events not listed" })]));
    const times = Float64Array.from(D.events.slice(0, LIMIT), (e) => e.t);
    listeners.push((s) => {   // highlight the last event at or before the cursor
      const i = lastAtOrBefore(times, s.t);
      if (i === eventCurrent) return;
      if (eventRows[eventCurrent]) eventRows[eventCurrent].classList.remove("cs-current");
      if (eventRows[i]) eventRows[i].classList.add("cs-current");
      eventCurrent = i;
    });
  }

  function initExpectations() {
    const table = $("cs-expectations"), list = D.expectations;
    if (!list.length) { table.replaceWith(el("div", { cls: "cs-empty", text: "This run states no expectations." })); return; }
    table.append(el("tr", {}, [el("th", { text: "" }), el("th", { text: "expectation" }), el("th", { cls: "cs-num", text: "measured" })]));
    let pass = 0;
    for (const x of list) {
      const ok = x.passed === true;
      if (ok) pass++;
      table.append(el("tr", {}, [el("td", {}, [el("span", { cls: "cs-badge " + (ok ? "cs-pass" : "cs-fail"), text: ok ? "PASS" : "FAIL" })]),
        el("td", { text: str(x.text) }), el("td", { cls: "cs-num", text: fmt(x.measured) })]));
    }
    const v = $("cs-verdict");
    v.textContent = pass === list.length ? "expectations: all " + pass + " pass" : "expectations: " + (list.length - pass) + " of " + list.length + " FAIL";
    v.className = "cs-badge " + (pass === list.length ? "cs-pass" : "cs-fail");
  }

  const MAIN_METRICS = ["ate_rmse_m", "ate_aligned_rmse_m", "rpe_1m_trans_rmse_m", "final_position_error_m", "nees_mean", "nees_in_band_fraction"];

  /** Nested metrics as dotted keys: {"a": {"b": 1}} -> {"a.b": 1}. */
  function flatten(obj, prefix, out) {
    for (const k of Object.keys(obj)) {
      const v = obj[k], key = prefix ? prefix + "." + k : k;
      if (isObj(v)) flatten(v, key, out); else out[key] = v;
    }
    return out;
  }

  function initMetrics() {
    const box = $("cs-metrics"), P = D.pipelines;
    if (!P.length) { box.append(el("div", { cls: "cs-empty", text: "No pipelines." })); return; }
    const flat = P.map((p) => flatten(p.metrics, "", {}));
    const head = () => el("tr", {}, [el("th", { text: "metric" })].concat(P.map((p) => {
      const th = el("th", { cls: "cs-num" }, [el("span", { cls: "cs-swatch", style: "background:" + p.color }), p.name]);
      if (p.failed) th.title = "failed: " + p.failed;
      return th;
    })));
    const row = (key, bestLow) => {
      const vals = flat.map((f) => f[key]);
      const nums = vals.filter((v) => typeof v === "number" && isFinite(v));
      const best = bestLow && nums.length > 1 ? Math.min.apply(null, nums) : null;
      return el("tr", {}, [el("td", { text: key })].concat(vals.map((v) => {
        const td = el("td", { cls: "cs-num", text: Array.isArray(v) ? JSON.stringify(v) : fmt(v) });
        if (best !== null && v === best) td.style.fontWeight = "700";
        return td;
      })));
    };
    const main = el("table", { cls: "cs-table" }, [head()].concat(MAIN_METRICS.map((k) => row(k, /_m$/.test(k)))));
    const failedRow = P.some((p) => p.failed) ? el("tr", {}, [el("td", { text: "failed" })].concat(P.map((p) =>
      el("td", { cls: "cs-num" }, [p.failed ? el("span", { cls: "cs-badge cs-fail", text: "failed", title: p.failed }) : "–"])))) : null;
    if (failedRow) main.append(failedRow);
    box.append(main);
    const rest = [];
    for (const f of flat) for (const k of Object.keys(f)) if (!MAIN_METRICS.includes(k) && !rest.includes(k)) rest.push(k);
    if (rest.length) {
      box.append(el("details", {}, [el("summary", { text: "all metrics (" + rest.length + " more)" }),
        el("table", { cls: "cs-table" }, [head()].concat(rest.map((k) => row(k, false))))]));
    }
  }

  // ---------------------------------------------------------------- transport: slider, play, keys
  let playing = false, speed = 1, playT = 0, lastNow = 0;

  function updateTransport(s) {
    $("cs-slider").value = String(cur);
    $("cs-time").textContent = "t = " + s.t.toFixed(3) + " s / " + (isFinite(T1()) ? T1().toFixed(1) : "?") + " s";
  }

  function play() {
    if (playing) return;
    if (cur >= stamps.length - 1) setIndex(0);
    playing = true; playT = stamps[cur]; lastNow = performance.now();
    $("cs-play").innerHTML = "&#10074;&#10074;"; $("cs-play").classList.add("cs-on");
    requestAnimationFrame(tick);
  }
  function stop() {
    if (!playing) return;
    playing = false;
    $("cs-play").innerHTML = "&#9654;"; $("cs-play").classList.remove("cs-on");
    clearTimeout(urlTimer); writeUrl();
  }
  const tick = guard((now) => {
    if (!playing) return;
    playT += Math.max(now - lastNow, 0) / 1000 * speed;   // real time x speed
    lastNow = now;
    const i = Math.max(lastAtOrBefore(stamps, playT), 0);
    if (i !== cur) setIndex(i);
    if (playT >= stamps[stamps.length - 1]) { stop(); return; }
    requestAnimationFrame(tick);
  }, "play");

  function step(n) { stop(); setIndex(cur + n, { url: "later" }); }

  function initTransport() {
    const slider = $("cs-slider");
    slider.max = String(stamps.length - 1);
    slider.addEventListener("input", guard(() => { stop(); setIndex(+slider.value); }, "slider"));
    $("cs-play").addEventListener("click", guard(() => (playing ? stop() : play()), "play"));
    $("cs-back").addEventListener("click", guard((e) => step(e.shiftKey ? -10 : -1), "step"));
    $("cs-fwd").addEventListener("click", guard((e) => step(e.shiftKey ? 10 : 1), "step"));
    $("cs-speed").addEventListener("change", () => { speed = parseFloat($("cs-speed").value) || 1; });
    listeners.push(updateTransport);
    document.addEventListener("keydown", guard((e) => {
      const tag = e.target && e.target.tagName;
      if ((tag === "INPUT" && e.target.type !== "range" && e.target.type !== "checkbox") || tag === "SELECT" || tag === "TEXTAREA") return;
      if (e.ctrlKey || e.metaKey || e.altKey) return;
      if (e.key === " ") { e.preventDefault(); playing ? stop() : play(); }
      else if (e.key === "ArrowLeft") { e.preventDefault(); step(e.shiftKey ? -10 : -1); }
      else if (e.key === "ArrowRight") { e.preventDefault(); step(e.shiftKey ? 10 : 1); }
      else if (e.key === "f" || e.key === "F") { $("cs-follow").checked = false; fitPlan(); }
    }, "keys"));
    window.addEventListener("hashchange", guard(() => {
      const t = timeFromHash();
      if (t !== null && t !== stamps[cur]) setIndex(Math.max(lastAtOrBefore(stamps, t), 0), { url: "now" });
    }, "hashchange"));
  }

  // ---------------------------------------------------------------- start
  function header() {
    document.title = D.title || document.title;
    $("cs-title").textContent = D.title;
    const bits = [];
    if (D.scenario) bits.push("scenario " + D.scenario);
    if (D.seed !== undefined && D.seed !== null) bits.push("seed " + D.seed);
    if (isFinite(D.duration)) bits.push(D.duration.toFixed(1) + " s");
    bits.push(D.pipelines.length + " pipeline" + (D.pipelines.length === 1 ? "" : "s"));
    $("cs-sub").textContent = bits.join(" · ");
  }

  function start() {
    D = loadData();
    buildStamps();
    // Each part on its own: one that fails is recorded and the others still work.
    for (const [name, f] of [["header", header], ["legend", initLegend], ["plan", initPlan], ["transport", initTransport],
      ["plots", initPlots], ["frames", initFrames], ["events", initEvents], ["expectations", initExpectations], ["metrics", initMetrics]]) {
      try { f(); } catch (e) { report(e, name); }
    }
    const t = timeFromHash();
    setIndex(t === null ? 0 : Math.max(lastAtOrBefore(stamps, t), 0), { url: t === null ? "none" : "now" });
    drawPlanNow();
    api.ready = true;
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", guard(start, "start"));
  else guard(start, "start")();
})();
