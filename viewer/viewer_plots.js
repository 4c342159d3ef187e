/* The run viewer's time plots (docs/viewer.md): uPlot charts of the focused pipeline's errors
 * with their 2-sigma bounds, NEES and NIS with their chi-square bands, frame time and cost, then
 * the IMUs' (viewer_sensors.js), all on one synchronised time axis with the cursor's line. Part
 * of viewer.js's closure (scripts/pages.py inlines it where viewer.js says CORRIDORSIM_INCLUDE
 * viewer_plots.js); this opening comment stays out of the page. */
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
    if (focus) pipelinePlots(box, focus);
    else box.append(el("div", { cls: "cs-plot-empty", text: "No pipelines in this run." }));
    sensorPlots(box);   // the IMUs' (viewer_sensors.js)
  }

  /** The focused pipeline's plots: errors, NEES, NIS per type, frame time and cost. */
  function pipelinePlots(box, p) {
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

