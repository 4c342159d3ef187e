/* corridorsim run viewer (docs/viewer.md): one time cursor driving the plan, the time plots,
 * the camera frames and the events of one run. Reads the JSON in
 * <script id="corridorsim-data">; plain browser JavaScript, no framework, works from file://.
 * Test API: window.corridorsimViewer = {ready, setTime(t), state(), plots(), errors}. */
(function () {
  "use strict";

  // ---------------------------------------------------------------- errors and the test API
  const api = { ready: false, errors: [], setTime: setTimeApi, state: stateApi, plots: () => plotsApi() };
  window.corridorsimViewer = api;

  /*CORRIDORSIM_INCLUDE page.js*/

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
    const raw = pageData();
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
      sensors: loadSensors(raw.sensors),
    };
    const colorOfPipeline = pipelineColors();
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
      const color = colorOfPipeline(name);
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
    if (D.sensors.lasers.length) out.scans = scanSnapshot(snap.t);   // only in a run with scanners
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

  /*CORRIDORSIM_INCLUDE viewer_plan.js*/
  /*CORRIDORSIM_INCLUDE viewer_plots.js*/
  /*CORRIDORSIM_INCLUDE viewer_frames.js*/
  /*CORRIDORSIM_INCLUDE viewer_tables.js*/
  /*CORRIDORSIM_INCLUDE viewer_sensors.js*/
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
    const bits = [];
    if (D.scenario) bits.push("scenario " + D.scenario);
    if (D.seed !== undefined && D.seed !== null) bits.push("seed " + D.seed);
    if (isFinite(D.duration)) bits.push(D.duration.toFixed(1) + " s");
    bits.push(D.pipelines.length + " pipeline" + (D.pipelines.length === 1 ? "" : "s"));
    pageHeader(D.title, bits);
  }

  function start() {
    D = loadData();
    buildStamps();
    startParts([["header", header], ["legend", initLegend], ["sensors", initSensors], ["plan", initPlan], ["transport", initTransport],
      ["plots", initPlots], ["frames", initFrames], ["events", initEvents], ["expectations", initExpectations], ["metrics", initMetrics]]);
    const t = timeFromHash();
    setIndex(t === null ? 0 : Math.max(lastAtOrBefore(stamps, t), 0), { url: t === null ? "none" : "now" });
    drawPlanNow();
    api.ready = true;
  }

  whenReady(start);
})();
