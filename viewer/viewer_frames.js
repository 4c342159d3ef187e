/* The run viewer's camera frames (docs/viewer.md): each kept frame at or before the cursor with
 * the focused pipeline's detections drawn on it. Part of viewer.js's closure (scripts/pages.py
 * inlines it where viewer.js says CORRIDORSIM_INCLUDE viewer_frames.js); this opening comment
 * stays out of the page. */
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

