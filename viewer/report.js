/* corridorsim study report (docs/viewer.md): the runs of a study, their metrics per sweep point
 * and pipeline, paired differences, NEES over time, sweep curves and a sortable table of runs
 * linking to each run's viewer. Reads the JSON in <script id="corridorsim-data">; plain browser
 * JavaScript, works from file://. Test hook: window.corridorsimReport = {ready, errors}. */
(function () {
  "use strict";

  const api = { ready: false, errors: [] };
  window.corridorsimReport = api;

  /*CORRIDORSIM_INCLUDE page.js*/

  /** A link target as given when it is a relative path; null otherwise (no scheme, no absolute path). */
  function relHref(v) {
    if (typeof v !== "string" || !v) return null;
    if (/^[a-z][a-z0-9+.-]*:/i.test(v) || v.startsWith("/") || v.startsWith("\\")) return null;
    return v;
  }

  function quantile(sorted, q) {
    if (!sorted.length) return NaN;
    const pos = (sorted.length - 1) * q, i = Math.floor(pos), f = pos - i;
    return i + 1 < sorted.length ? sorted[i] * (1 - f) + sorted[i + 1] * f : sorted[i];
  }

  /** Round tick values between lo and hi, about n of them. */
  function ticks(lo, hi, n) {
    if (!(hi > lo)) { hi = lo + 1; lo -= 1; }
    const raw = (hi - lo) / Math.max(n, 1), p = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 2.5, 5, 10].map((k) => k * p).find((s) => s >= raw);
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    return out;
  }

  /** A tick label: short, no exponent for ordinary values (0.0002, 1500). */
  const tickText = (v) => (v !== 0 && (Math.abs(v) < 1e-5 || Math.abs(v) >= 1e7) ? v.toExponential(1) : String(Number(v.toPrecision(6))));

  function linear(d0, d1, r0, r1) {
    const k = d1 === d0 ? 0 : (r1 - r0) / (d1 - d0);
    return (v) => r0 + (v - d0) * k;
  }

  // ---------------------------------------------------------------- the data
  let D = null;
  const colorOf = new Map();

  function load() {
    const raw = pageData();
    const runs = arr(raw.runs).filter(isObj).map((r) => ({
      point: str(r.point, "?"), seed: r.seed, status: str(r.status, "unknown"), reason: r.reason === null || r.reason === undefined ? null : str(r.reason),
      viewer: relHref(r.viewer), metrics: isObj(r.metrics) ? r.metrics : {},
    }));
    const pipelines = arr(raw.pipelines).map((p) => str(p)).filter(Boolean);
    for (const r of runs) for (const p of Object.keys(r.metrics)) if (!pipelines.includes(p)) pipelines.push(p);
    let metrics = arr(raw.metrics).filter((m) => isObj(m) && m.name).map((m) => ({ name: str(m.name), unit: str(m.unit) }));
    if (!metrics.length) {   // none listed: the numeric keys the runs have
      const seen = new Set();
      for (const r of runs) for (const p of Object.keys(r.metrics)) if (isObj(r.metrics[p])) {
        for (const k of Object.keys(r.metrics[p])) if (typeof r.metrics[p][k] === "number") seen.add(k);
      }
      metrics = Array.from(seen).map((k) => ({ name: k, unit: /_m$/.test(k) ? "m" : /_rad$/.test(k) ? "rad" : "" }));
    }
    const points = arr(raw.points).filter(isObj).map((p) => ({ id: str(p.id, "?"), label: str(p.label), values: isObj(p.values) ? p.values : {} }));
    for (const r of runs) if (!points.some((p) => p.id === r.point)) points.push({ id: r.point, label: "", values: {} });
    const colorOfPipeline = pipelineColors();
    for (const p of pipelines) colorOf.set(p, colorOfPipeline(p));
    return {
      title: str(raw.title, "corridorsim study"), study: str(raw.study), command: str(raw.command),
      pipelines: pipelines, metrics: metrics, points: points, runs: runs,
      summary: arr(raw.summary).filter(isObj), paired: arr(raw.paired).filter(isObj),
      series: isObj(raw.series) ? raw.series : {}, sweep: isObj(raw.sweep) ? raw.sweep : null,
      expectations: arr(raw.expectations).filter(isObj),
    };
  }

  const pointById = (id) => D.points.find((p) => p.id === id) || { id: id, label: "", values: {} };
  const pointName = (id) => { const p = pointById(id); return p.label ? p.id + " · " + p.label : p.id; };
  function runValue(r, pipe, metric) {
    const m = r.metrics[pipe];
    return isObj(m) ? num(m[metric]) : NaN;
  }
  let metric = "";   // the metric the figures show
  const unitOf = (name) => { const m = D.metrics.find((x) => x.name === name); return m && m.unit ? m.unit : ""; };
  const withUnit = (name) => name + (unitOf(name) ? " [" + unitOf(name) + "]" : "");

  // ---------------------------------------------------------------- canvas charts with hover and click
  const tip = () => $("cs-tip");

  /** A canvas chart that redraws on resize; draw(c) fills c.items with {x, y, r, tip, href} for hovering. */
  function chart(container, height, draw) {
    const canvas = el("canvas", { cls: "cs-chart" });
    container.append(canvas);
    const c = { canvas: canvas, ctx: canvas.getContext("2d"), w: 0, h: height, items: [] };
    c.render = guard(() => {
      const dpr = window.devicePixelRatio || 1;
      c.w = Math.max(container.clientWidth - 12, 200);
      c.h = typeof height === "function" ? height() : height;
      canvas.width = Math.round(c.w * dpr); canvas.height = Math.round(c.h * dpr);
      canvas.style.height = c.h + "px";
      c.ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      c.ctx.clearRect(0, 0, c.w, c.h);
      c.ctx.font = "11px " + getComputedStyle(document.body).fontFamily;
      c.items = [];
      draw(c);
    }, "chart");
    const hit = (e) => {
      const r = canvas.getBoundingClientRect(), x = e.clientX - r.left, y = e.clientY - r.top;
      let best = null, bd = Infinity;
      for (const it of c.items) {
        const d = Math.hypot(it.x - x, it.y - y);
        if (d <= (it.r || 6) + 4 && d < bd) { bd = d; best = it; }
      }
      return best;
    };
    canvas.addEventListener("mousemove", guard((e) => {
      const it = hit(e), t = tip();
      canvas.style.cursor = it && it.href ? "pointer" : "default";
      if (!it) { t.hidden = true; return; }
      t.textContent = it.tip + (it.href ? "\n(click: open the run's viewer)" : "");
      t.hidden = false;
      t.style.left = Math.min(e.clientX + 14, window.innerWidth - t.offsetWidth - 8) + "px";
      t.style.top = Math.min(e.clientY + 14, window.innerHeight - t.offsetHeight - 8) + "px";
    }, "chart hover"));
    canvas.addEventListener("mouseleave", () => { tip().hidden = true; });
    canvas.addEventListener("click", guard((e) => {
      const it = hit(e);
      if (it && it.href) window.open(it.href, "_blank");
    }, "chart click"));
    let lastW = -1;
    new ResizeObserver(guard(() => {
      if (Math.abs(container.clientWidth - lastW) < 2) return;
      lastW = container.clientWidth; c.render();
    }, "chart resize")).observe(container);
    c.render();
    return c;
  }

  function yAxis(ctx, y, lo, hi, x0, x1, label, plotTop, plotBottom) {
    ctx.textAlign = "right"; ctx.textBaseline = "middle";
    for (const v of ticks(lo, hi, 5)) {
      const py = Math.round(y(v)) + 0.5;
      ctx.strokeStyle = v === 0 ? "rgba(255,255,255,0.25)" : "rgba(255,255,255,0.07)";
      ctx.beginPath(); ctx.moveTo(x0, py); ctx.lineTo(x1, py); ctx.stroke();
      ctx.fillStyle = "#8b919c"; ctx.fillText(tickText(v), x0 - 5, py);
    }
    ctx.save();
    ctx.translate(12, (plotTop + plotBottom) / 2); ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center"; ctx.fillStyle = "#8b919c"; ctx.fillText(label, 0, 0);
    ctx.restore();
  }

  function legend(ctx, names, x, y) {
    ctx.textAlign = "left"; ctx.textBaseline = "middle";
    for (const n of names) {
      ctx.fillStyle = colorOf.get(n) || "#ccc"; ctx.fillRect(x, y - 2, 12, 4);
      ctx.fillStyle = "#d7dae0"; ctx.fillText(n, x + 16, y);
      x += 16 + ctx.measureText(n).width + 14;
    }
  }

  function truncate(ctx, text, w) {
    if (ctx.measureText(text).width <= w) return text;
    while (text.length > 1 && ctx.measureText(text + "…").width > w) text = text.slice(0, -1);
    return text + "…";
  }

  /** A small number in [-1, 1] from a seed and a pipeline: the same jitter on every redraw. */
  function jitter(seed, k) {
    let h = 2166136261 ^ k;
    for (const ch of String(seed)) h = Math.imul(h ^ ch.charCodeAt(0), 16777619);
    return ((h >>> 0) % 1000) / 500 - 1;
  }

  // ---------------------------------------------------------------- figure: every run's value
  function drawStrip(c) {
    const ctx = c.ctx, P = D.pipelines;
    const groups = D.points.filter((p) => D.runs.some((r) => r.point === p.id));
    const all = [];
    for (const r of D.runs) for (const p of P) { const v = runValue(r, p, metric); if (isFinite(v)) all.push(v); }
    $("cs-strip-title").textContent = metric + " per run";
    if (!all.length || !groups.length) { empty(ctx, c, "no run has " + metric); return; }
    const L = 62, R = 10, T = 26, B = 42;
    let lo = Math.min.apply(null, all), hi = Math.max.apply(null, all);
    if (lo >= 0) lo = 0;
    hi += (hi - lo) * 0.06 || 1;
    const y = linear(lo, hi, c.h - B, T);
    yAxis(ctx, y, lo, hi, L, c.w - R, withUnit(metric), T, c.h - B);
    legend(ctx, P, L, 11);
    const gw = (c.w - L - R) / groups.length, sw = gw / Math.max(P.length, 1);
    groups.forEach((g, gi) => {
      const gx = L + gi * gw;
      if (gi) { ctx.strokeStyle = "rgba(255,255,255,0.08)"; ctx.beginPath(); ctx.moveTo(gx + 0.5, T); ctx.lineTo(gx + 0.5, c.h - B + 4); ctx.stroke(); }
      ctx.fillStyle = "#c5cad3"; ctx.textAlign = "center"; ctx.textBaseline = "top";
      ctx.fillText(truncate(ctx, g.id, gw - 4), gx + gw / 2, c.h - B + 6);
      ctx.fillStyle = "#8b919c";
      ctx.fillText(truncate(ctx, g.label, gw - 4), gx + gw / 2, c.h - B + 20);
      P.forEach((p, pi) => {
        const cx = gx + (pi + 0.5) * sw, col = colorOf.get(p);
        const rows = D.runs.filter((r) => r.point === g.id).map((r) => ({ r: r, v: runValue(r, p, metric) })).filter((q) => isFinite(q.v));
        const vs = rows.map((q) => q.v).sort((a, b) => a - b);
        if (vs.length >= 2) {   // box: quartiles and median; whiskers: min to max
          const bw = Math.min(sw * 0.6, 46), q1 = y(quantile(vs, 0.25)), q3 = y(quantile(vs, 0.75)), md = y(quantile(vs, 0.5));
          ctx.strokeStyle = col; ctx.lineWidth = 1;
          ctx.beginPath(); ctx.moveTo(cx, y(vs[0])); ctx.lineTo(cx, q1); ctx.moveTo(cx, q3); ctx.lineTo(cx, y(vs[vs.length - 1])); ctx.stroke();
          ctx.globalAlpha = 0.15; ctx.fillStyle = col; ctx.fillRect(cx - bw / 2, q3, bw, q1 - q3); ctx.globalAlpha = 1;
          ctx.strokeRect(cx - bw / 2 + 0.5, q3 + 0.5, bw - 1, q1 - q3);
          ctx.lineWidth = 2; ctx.beginPath(); ctx.moveTo(cx - bw / 2, md); ctx.lineTo(cx + bw / 2, md); ctx.stroke(); ctx.lineWidth = 1;
        }
        for (const q of rows) {
          const x = cx + jitter(q.r.seed, pi) * Math.min(sw * 0.3, 18), py = y(q.v);
          ctx.beginPath(); ctx.arc(x, py, 3.5, 0, 2 * Math.PI);
          ctx.fillStyle = col; ctx.fill();
          if (q.r.status !== "finished") { ctx.strokeStyle = "#f0524f"; ctx.lineWidth = 2; ctx.stroke(); ctx.lineWidth = 1; }
          c.items.push({ x: x, y: py, r: 4, href: q.r.viewer,
            tip: pointName(g.id) + "\n" + p + " · seed " + str(q.r.seed, "?") + "\n" + metric + " = " + fmt(q.v) + (unitOf(metric) ? " " + unitOf(metric) : "") +
              "\nstatus " + q.r.status + (q.r.reason ? ": " + q.r.reason : "") });
        }
      });
    });
  }

  function empty(ctx, c, text) {
    ctx.fillStyle = "#8b919c"; ctx.textAlign = "center"; ctx.textBaseline = "middle";
    ctx.fillText(text, c.w / 2, c.h / 2);
  }

  // ---------------------------------------------------------------- figure: paired differences
  const pairedRows = () => D.paired.filter((q) => q.metric === metric && isFinite(num(q.diff)));

  function drawPaired(c) {
    const ctx = c.ctx, rows = pairedRows();
    if (!rows.length) { empty(ctx, c, "no paired comparison of " + metric); return; }
    const labels = rows.map((q) => str(q.point) + " · " + str(q.a) + " − " + str(q.b));
    const L = Math.min(Math.max.apply(null, labels.map((s) => ctx.measureText(s).width)) + 14, c.w * 0.45), R = 14, T = 10, B = 34;
    const vals = [0];
    for (const q of rows) for (const k of ["diff", "diff_ci_low", "diff_ci_high"]) if (isFinite(num(q[k]))) vals.push(num(q[k]));
    let lo = Math.min.apply(null, vals), hi = Math.max.apply(null, vals);
    const pad = (hi - lo) * 0.08 || 1; lo -= pad; hi += pad;
    const x = linear(lo, hi, L, c.w - R), rowH = (c.h - T - B) / rows.length;
    ctx.textBaseline = "top"; ctx.textAlign = "center";
    for (const v of ticks(lo, hi, 6)) {
      const px = Math.round(x(v)) + 0.5;
      ctx.strokeStyle = v === 0 ? "rgba(255,255,255,0.45)" : "rgba(255,255,255,0.07)";
      ctx.beginPath(); ctx.moveTo(px, T); ctx.lineTo(px, c.h - B); ctx.stroke();
      ctx.fillStyle = "#8b919c"; ctx.fillText(tickText(v), px, c.h - B + 4);
    }
    ctx.fillText("difference in " + withUnit(metric) + " (a − b; below 0: a lower)", (L + c.w - R) / 2, c.h - 14);
    rows.forEach((q, i) => {
      const py = T + (i + 0.5) * rowH, cl = num(q.diff_ci_low), ch = num(q.diff_ci_high);
      const sig = isFinite(cl) && isFinite(ch) && (cl > 0 || ch < 0);
      const col = !sig ? "#8b919c" : ch < 0 ? "#6ea8ff" : "#ff9f43";
      ctx.fillStyle = "#c5cad3"; ctx.textAlign = "right"; ctx.textBaseline = "middle";
      ctx.fillText(truncate(ctx, labels[i], L - 10), L - 8, py);
      ctx.strokeStyle = col; ctx.lineWidth = 2;
      if (isFinite(cl) && isFinite(ch)) {
        ctx.beginPath(); ctx.moveTo(x(cl), py); ctx.lineTo(x(ch), py);
        ctx.moveTo(x(cl), py - 4); ctx.lineTo(x(cl), py + 4); ctx.moveTo(x(ch), py - 4); ctx.lineTo(x(ch), py + 4); ctx.stroke();
      }
      ctx.lineWidth = 1;
      ctx.beginPath(); ctx.arc(x(num(q.diff)), py, 4.5, 0, 2 * Math.PI);
      if (sig) { ctx.fillStyle = col; ctx.fill(); } else { ctx.fillStyle = "#1b1d22"; ctx.fill(); ctx.strokeStyle = col; ctx.lineWidth = 1.5; ctx.stroke(); ctx.lineWidth = 1; }
      c.items.push({ x: x(num(q.diff)), y: py, r: 6, tip: pointName(str(q.point)) + "\n" + str(q.a) + " − " + str(q.b) + ", " + metric +
        "\nn = " + fmt(q.n) + "\ndiff = " + fmt(q.diff) + "  CI [" + fmt(q.diff_ci_low) + ", " + fmt(q.diff_ci_high) + "]" +
        "\nratio a/b = " + fmt(q.ratio) + "\np sign = " + fmt(q.p_sign) + ", p Wilcoxon = " + fmt(q.p_wilcoxon) });
    });
  }

  // ---------------------------------------------------------------- figure: the sweep
  /** The value of a swept key at a point: points[].values, else sweep.values[point][key]. */
  function sweptValue(pid, key) {
    const p = pointById(pid);
    if (key in p.values) return p.values[key];
    const sv = D.sweep && isObj(D.sweep.values) && isObj(D.sweep.values[pid]) ? D.sweep.values[pid] : null;
    return sv && key in sv ? sv[key] : undefined;
  }

  /** Mean and CI of the metric at a point for a pipeline: from the summary, else from the runs. */
  function stat(pid, pipe) {
    const s = D.summary.find((q) => q.point === pid && q.pipeline === pipe && q.metric === metric);
    if (s && isFinite(num(s.mean))) return { mean: num(s.mean), lo: num(s.ci_low), hi: num(s.ci_high), n: s.n };
    const vs = D.runs.filter((r) => r.point === pid).map((r) => runValue(r, pipe, metric)).filter(isFinite);
    return vs.length ? { mean: vs.reduce((a, b) => a + b, 0) / vs.length, lo: NaN, hi: NaN, n: vs.length } : null;
  }

  /** A swept value as a number when it is one (YAML may hand "1.0e-4" over as text). */
  function asNumber(v) {
    if (typeof v === "number") return isFinite(v) ? v : NaN;
    if (typeof v === "string" && /^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$/.test(v)) return parseFloat(v);
    return NaN;
  }

  function drawSweep(c, key) {
    const ctx = c.ctx, others = arr(D.sweep.keys).filter((k) => k !== key);
    const raw = D.points.map((p) => sweptValue(p.id, key));
    const numeric = raw.length > 0 && raw.every((v) => isFinite(asNumber(v)));
    const cats = numeric ? [] : Array.from(new Set(raw.map((v) => (typeof v === "string" ? v : JSON.stringify(v === undefined ? null : v)))));
    const xOf = (v) => (numeric ? asNumber(v) : cats.indexOf(typeof v === "string" ? v : JSON.stringify(v === undefined ? null : v)));
    // a log axis for positive values spread over more than a decade and a bit
    const nv = raw.map(asNumber);
    const log = numeric && nv.every((v) => v > 0) && Math.max.apply(null, nv) / Math.min.apply(null, nv) >= 10;
    const fx = (v) => (log ? Math.log10(v) : v);
    // one curve per pipeline and combination of the other swept keys
    const curves = new Map();
    for (const p of D.points) for (const pipe of D.pipelines) {
      const s = stat(p.id, pipe);
      if (!s) continue;
      const rest = others.map((k) => k + "=" + str(sweptValue(p.id, k))).join(", ");
      const id = pipe + (rest ? " · " + rest : "");
      if (!curves.has(id)) curves.set(id, { pipe: pipe, label: id, pts: [] });
      curves.get(id).pts.push(Object.assign({ x: fx(xOf(sweptValue(p.id, key))), pid: p.id }, s));
    }
    const ys = [], xv = [];
    for (const cv of curves.values()) for (const q of cv.pts) {
      for (const v of [q.mean, q.lo, q.hi]) if (isFinite(v)) ys.push(v);
      if (isFinite(q.x)) xv.push(q.x);
    }
    if (!ys.length || !xv.length) { empty(ctx, c, "no values of " + metric + " along " + key); return; }
    const L = 62, R = 14, T = 26, B = 38;
    let lo = Math.min.apply(null, ys), hi = Math.max.apply(null, ys);
    if (lo >= 0) lo = 0;
    hi += (hi - lo) * 0.06 || 1;
    let x0 = Math.min.apply(null, xv), x1 = Math.max.apply(null, xv);
    const xp = (x1 - x0) * 0.06 || 0.5; x0 -= xp; x1 += xp;
    const y = linear(lo, hi, c.h - B, T), x = linear(x0, x1, L, c.w - R);
    yAxis(ctx, y, lo, hi, L, c.w - R, withUnit(metric), T, c.h - B);
    legend(ctx, D.pipelines, L, 11);
    ctx.fillStyle = "#8b919c"; ctx.textAlign = "center"; ctx.textBaseline = "top";
    if (log) for (let e = Math.ceil(x0); e <= Math.floor(x1); e++) ctx.fillText("1e" + e, x(e), c.h - B + 5);
    else if (numeric) for (const v of ticks(x0, x1, 6)) ctx.fillText(tickText(v), x(v), c.h - B + 5);
    else cats.forEach((s, i) => ctx.fillText(truncate(ctx, s, (c.w - L - R) / cats.length - 4), x(i), c.h - B + 5));
    if (log) for (const v of nv) { ctx.strokeStyle = "rgba(255,255,255,0.07)"; ctx.beginPath(); ctx.moveTo(x(fx(v)), T); ctx.lineTo(x(fx(v)), c.h - B); ctx.stroke(); }
    ctx.fillText(key + (log ? " (log)" : ""), (L + c.w - R) / 2, c.h - 16);
    const perPipe = new Map();   // dashes tell a pipeline's curves (other keys) apart
    for (const cv of curves.values()) {
      const col = colorOf.get(cv.pipe) || "#ccc", pts = cv.pts.filter((q) => isFinite(q.x)).sort((a, b) => a.x - b.x);
      const dash = perPipe.get(cv.pipe) || 0;
      perPipe.set(cv.pipe, dash + 1);
      ctx.strokeStyle = col; ctx.lineWidth = 1.5; ctx.setLineDash([[], [6, 3], [2, 3], [8, 3, 2, 3]][dash % 4]);
      ctx.beginPath();
      pts.forEach((q, i) => (i ? ctx.lineTo(x(q.x), y(q.mean)) : ctx.moveTo(x(q.x), y(q.mean))));
      ctx.stroke(); ctx.setLineDash([]);
      for (const q of pts) {
        if (isFinite(q.lo) && isFinite(q.hi)) {
          ctx.beginPath(); ctx.moveTo(x(q.x), y(q.lo)); ctx.lineTo(x(q.x), y(q.hi));
          ctx.moveTo(x(q.x) - 4, y(q.lo)); ctx.lineTo(x(q.x) + 4, y(q.lo)); ctx.moveTo(x(q.x) - 4, y(q.hi)); ctx.lineTo(x(q.x) + 4, y(q.hi)); ctx.stroke();
        }
        ctx.beginPath(); ctx.arc(x(q.x), y(q.mean), 3.5, 0, 2 * Math.PI); ctx.fillStyle = col; ctx.fill();
        c.items.push({ x: x(q.x), y: y(q.mean), r: 5, tip: cv.label + "\n" + pointName(q.pid) + "\n" + metric + " mean = " + fmt(q.mean) +
          "\nCI [" + fmt(q.lo) + ", " + fmt(q.hi) + "], n = " + fmt(q.n) });
      }
    }
  }

  // ---------------------------------------------------------------- figure: over time (uPlot)
  const timePlots = [];

  /** Series of several pipelines on the union of their stamps (null where one has no sample). */
  function joinSeries(sets, field) {
    const ts = new Set();
    for (const s of sets) for (const t of arr(s.t)) if (isFinite(num(t))) ts.add(t);
    const t = Array.from(ts).sort((a, b) => a - b), index = new Map(t.map((v, i) => [v, i]));
    const cols = sets.map((s) => {
      const out = new Array(t.length).fill(null), src = arr(s[field]);
      arr(s.t).forEach((tv, i) => { const v = num(src[i]); if (index.has(tv) && isFinite(v)) out[index.get(tv)] = v; });
      return out;
    });
    return [t].concat(cols);
  }

  function buildSeries() {
    for (const u of timePlots) u.destroy();
    timePlots.length = 0;
    const box = $("cs-series");
    box.textContent = "";
    const pid = $("cs-point").value, sp = isObj(D.series[pid]) ? D.series[pid] : {};
    const pipes = D.pipelines.filter((p) => isObj(sp[p])).concat(Object.keys(sp).filter((p) => isObj(sp[p]) && !D.pipelines.includes(p)));
    if (!pipes.length) { box.append(el("div", { cls: "cs-empty", text: "no time series for this point" })); return; }
    if (typeof uPlot !== "function") { box.append(el("div", { cls: "cs-empty", text: "uPlot is not in this page: no plots." })); return; }
    const sets = pipes.map((p) => sp[p]);
    const axis = { stroke: "#8b919c", grid: { stroke: "rgba(255,255,255,0.06)" }, ticks: { stroke: "rgba(255,255,255,0.12)" }, font: "11px sans-serif", labelFont: "11px sans-serif" };
    const axes = (unit) => [Object.assign({ label: "time [s]", labelSize: 16, size: 34 }, axis), Object.assign({ label: unit, labelSize: 16, size: 52 }, axis)];
    const width = Math.max(box.clientWidth - 8, 240);
    const val = (u, v) => (v === null || v === undefined ? "–" : fmt(v));
    // position error: the mean over seeds (solid) and the mean 2-sigma (dashed)
    const err = joinSeries(sets, "error_rms"), sig = joinSeries(sets, "error_2sigma");
    box.append(el("div", { cls: "cs-plot-title" }, ["position error over seeds", el("small", { text: "solid: the error, dashed: its 2σ bound" })]));
    timePlots.push(new uPlot({
      width: width, height: 180, axes: axes("m"), scales: { x: { time: false } }, cursor: { sync: { key: "rep" } },
      series: [{ label: "t", value: val }].concat(pipes.map((p) => ({ label: p, stroke: colorOf.get(p) || "#ccc", width: 1.5, value: val })),
        pipes.map((p) => ({ label: p + " 2σ", stroke: colorOf.get(p) || "#ccc", width: 1, dash: [5, 4], value: val }))),
    }, [err[0]].concat(err.slice(1), sig.slice(1)), box));
    // NEES with its band (the first pipeline's band; every pipeline's when they differ)
    const nees = joinSeries(sets, "nees_mean");
    const bands = pipes.map((p) => arr(sp[p].nees_band).map(num)).filter((b) => b.length === 2 && b.every(isFinite));
    const uniq = bands.filter((b, i) => bands.findIndex((c) => c[0] === b[0] && c[1] === b[1]) === i);
    const varying = sets.find((s) => arr(s.nees_low).length && arr(s.nees_low).length === arr(s.t).length && arr(s.nees_high).length === arr(s.t).length) || null;
    box.append(el("div", { cls: "cs-plot-title" }, ["NEES, mean over seeds", uniq.length ? el("small", { text: "95 % band shaded" }) : null]));
    timePlots.push(new uPlot({
      width: width, height: 180, axes: axes("NEES"), cursor: { sync: { key: "rep" } },
      scales: { x: { time: false }, y: { range: (u, a, b) => {   // the data in view and the bands
        let lo = Math.min(...uniq.map((q) => q[0])), hi = Math.max(...uniq.map((q) => q[1]));
        if (a !== null && isFinite(a)) lo = uniq.length ? Math.min(lo, a) : a;
        if (b !== null && isFinite(b)) hi = uniq.length ? Math.max(hi, b) : b;
        return isFinite(lo) && isFinite(hi) ? uPlot.rangeNum(lo, hi, 0.1, true) : [0, 1];
      } } },
      series: [{ label: "t", value: val }].concat(pipes.map((p) => ({ label: p, stroke: colorOf.get(p) || "#ccc", width: 1.5, value: val }))),
      hooks: {
        drawClear: [(u) => {
          const ctx = u.ctx, { left, width: w } = u.bbox;
          if (varying) {   // the band over time (it narrows with the runs averaged)
            const t = arr(varying.t), loA = arr(varying.nees_low), hiA = arr(varying.nees_high), up = [], down = [];
            for (let i = 0; i < t.length; i++) {
              if (!isFinite(num(t[i])) || !isFinite(num(loA[i])) || !isFinite(num(hiA[i]))) continue;
              const px = u.valToPos(t[i], "x", true);
              up.push([px, u.valToPos(hiA[i], "y", true)]); down.push([px, u.valToPos(loA[i], "y", true)]);
            }
            if (up.length) {
              ctx.save(); ctx.beginPath(); ctx.rect(left, u.bbox.top, w, u.bbox.height); ctx.clip();
              ctx.beginPath(); up.forEach((p, i) => (i ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1])));
              for (let i = down.length - 1; i >= 0; i--) ctx.lineTo(down[i][0], down[i][1]);
              ctx.closePath(); ctx.fillStyle = "rgba(63, 185, 112, 0.14)"; ctx.fill(); ctx.restore();
            }
            return;
          }
          for (const b of uniq) {
            const y0 = u.valToPos(b[1], "y", true), y1 = u.valToPos(b[0], "y", true);
            ctx.fillStyle = "rgba(63, 185, 112, " + (0.14 / uniq.length) + ")"; ctx.fillRect(left, y0, w, y1 - y0);
          }
        }],
      },
    }, nees, box));
  }

  // ---------------------------------------------------------------- tables
  function buildRunsTable() {
    const box = $("cs-runs");
    box.textContent = "";
    if (!D.runs.length) { box.append(el("div", { cls: "cs-empty", text: "No runs." })); return; }
    const cols = [
      { label: "point", type: "text", get: (r) => r.point },
      { label: "sweep values", type: "text", get: (r) => pointById(r.point).label },
      { label: "seed", type: "num", get: (r) => num(r.seed), show: (r) => str(r.seed) },
      { label: "status", type: "text", get: (r) => r.status, cls: (r) => "cs-status-" + r.status.replace(/[^a-z]/gi, "") },
    ];
    const shown = $("cs-columns").value === "all" ? D.metrics : D.metrics.filter((m) => m.name === metric);
    for (const p of D.pipelines) for (const m of shown) {
      cols.push({ label: p + "\n" + m.name + (m.unit ? " [" + m.unit + "]" : ""), type: "num", get: (r) => runValue(r, p, m.name), pipe: p });
    }
    cols.push({ label: "reason", type: "text", get: (r) => r.reason || "" });
    cols.push({ label: "viewer", type: "link" });
    const table = el("table", { cls: "cs-table cs-runs" });
    const thead = el("thead"), tbody = el("tbody"), hr = el("tr");
    thead.append(hr); table.append(thead, tbody);
    let sortCol = -1, dir = 1;
    const rows = D.runs.map((r) => {
      const tr = el("tr", { "data-key": r.point + "/" + str(r.seed) });
      for (const c of cols) {
        if (c.type === "link") {
          tr.append(el("td", {}, [r.viewer ? el("a", { href: r.viewer, target: "_blank", text: "open" }) : el("span", { cls: "cs-hint", text: "–" })]));
          continue;
        }
        const v = c.get(r);
        const td = el("td", { cls: c.type === "num" ? "cs-num" : (c.cls ? c.cls(r) : null), text: c.type === "num" ? (c.show ? c.show(r) : isFinite(v) ? fmt(v) : "–") : v });
        if (c.type === "num") td.dataset.v = isFinite(v) ? String(v) : "";
        tr.append(td);
      }
      return { r: r, tr: tr };
    });
    cols.forEach((c, i) => {
      const th = el("th", { cls: c.type === "num" ? "cs-num" : null });
      const parts = c.label.split("\n");
      if (parts.length > 1) {
        th.append(el("span", { cls: "cs-swatch", style: "background:" + (colorOf.get(c.pipe) || "#ccc") }), parts[0], el("br"), el("span", { cls: "cs-hint", text: parts[1] }));
      } else th.textContent = c.label;
      if (c.type !== "link") {
        th.classList.add("cs-sortable"); th.dataset.type = c.type; th.title = "sort by " + c.label.replace("\n", " ");
        th.addEventListener("click", guard(() => {
          dir = sortCol === i ? -dir : 1; sortCol = i;
          for (const h of hr.children) h.removeAttribute("aria-sort");
          th.setAttribute("aria-sort", dir > 0 ? "ascending" : "descending");
          sortRows(c);
        }, "sort"));
      }
      hr.append(th);
    });
    function sortRows(c) {
      const key = (q) => c.get(q.r);
      const missing = (v) => (c.type === "num" ? !isFinite(v) : v === null || v === undefined || v === "");
      const sorted = rows.map((q, i) => ({ q: q, i: i, v: key(q) })).sort((a, b) => {
        const ma = missing(a.v), mb = missing(b.v);
        if (ma || mb) return ma === mb ? a.i - b.i : ma ? 1 : -1;   // empty cells last either way
        const d = c.type === "num" ? a.v - b.v : String(a.v).localeCompare(String(b.v), undefined, { numeric: true });
        return d ? d * dir : a.i - b.i;
      });
      for (const s of sorted) tbody.append(s.q.tr);
    }
    for (const q of rows) tbody.append(q.tr);
    box.append(table);
  }

  function buildFailed() {
    const box = $("cs-failed"), bad = D.runs.filter((r) => r.status !== "finished");
    if (!bad.length) { box.append(el("div", { cls: "cs-empty", text: "Every run finished." })); return; }
    const table = el("table", { cls: "cs-table" }, [el("tr", {}, ["run", "status", "reason", ""].map((t) => el("th", { text: t })))]);
    for (const r of bad) {
      table.append(el("tr", {}, [el("td", { text: pointName(r.point) + " · seed " + str(r.seed) }),
        el("td", { cls: "cs-status-" + r.status.replace(/[^a-z]/gi, ""), text: r.status }), el("td", { text: r.reason || "–" }),
        el("td", {}, [r.viewer ? el("a", { href: r.viewer, target: "_blank", text: "viewer" }) : null])]));
    }
    box.append(table);
  }

  function buildExpectations() {
    const box = $("cs-expectations"), list = D.expectations;
    if (!list.length) { box.append(el("div", { cls: "cs-empty", text: "This study states no expectations." })); return; }
    box.append(expectationsTable(el("table", { cls: "cs-table" }), list));
  }

  function buildSummary() {
    const box = $("cs-summary");
    if (!D.summary.length) { box.append(el("div", { cls: "cs-empty", text: "No summary." })); return; }
    const keys = ["n", "mean", "std", "median", "p95", "min", "max", "ci_low", "ci_high"];
    const table = el("table", { cls: "cs-table" }, [el("tr", {}, ["point", "pipeline", "metric"].map((t) => el("th", { text: t }))
      .concat(keys.map((k) => el("th", { cls: "cs-num", text: k }))))]);
    for (const s of D.summary) {
      table.append(el("tr", {}, [el("td", { text: pointName(str(s.point)) }), el("td", { text: str(s.pipeline) }), el("td", { text: str(s.metric) })]
        .concat(keys.map((k) => el("td", { cls: "cs-num", text: fmt(s[k]) })))));
    }
    box.append(table);
  }

  // ---------------------------------------------------------------- start
  const charts = [];

  function start() {
    D = load();
    pageHeader(D.title, [D.study ? "study " + D.study : "", D.points.length + " points", D.pipelines.length + " pipelines", D.runs.length + " runs"]);
    $("cs-command").textContent = D.command ? "$ " + D.command : "";
    const counts = {};
    for (const r of D.runs) counts[r.status] = (counts[r.status] || 0) + 1;
    const rb = $("cs-runs-badge");
    rb.textContent = Object.keys(counts).map((k) => counts[k] + " " + k).join(", ");
    rb.className = "cs-badge " + (D.runs.every((r) => r.status === "finished") ? "cs-pass" : "cs-warn");

    const sel = $("cs-metric");
    for (const m of D.metrics) sel.append(el("option", { value: m.name, text: withUnit(m.name) }));
    metric = D.metrics.some((m) => m.name === "ate_rmse_m") ? "ate_rmse_m" : D.metrics.length ? D.metrics[0].name : "";
    sel.value = metric;
    sel.addEventListener("change", guard(() => { metric = sel.value; for (const c of charts) c.render(); buildRunsTable(); }, "metric"));
    $("cs-columns").addEventListener("change", guard(buildRunsTable, "columns"));

    const psel = $("cs-point");
    const withSeries = D.points.filter((p) => isObj(D.series[p.id]));
    for (const p of withSeries) psel.append(el("option", { value: p.id, text: pointName(p.id) }));
    psel.addEventListener("change", guard(buildSeries, "series"));

    startParts([
      ["strip", () => charts.push(chart($("cs-strip"), 300, drawStrip))],
      ["paired", () => charts.push(chart($("cs-paired"), () => Math.max(140, 50 + pairedRows().length * 24), drawPaired))],
      ["series", buildSeries],
      ["sweep", () => {
        const keys = D.sweep ? arr(D.sweep.keys).map((k) => str(k)).filter(Boolean) : [];
        if (!keys.length) { $("cs-sweep-panel").hidden = true; return; }
        for (const k of keys.slice(0, 4)) {
          const wrap = el("div");
          $("cs-sweep").append(wrap);
          charts.push(chart(wrap, 260, (c) => drawSweep(c, k)));
        }
      }],
      ["expectations", buildExpectations], ["failed", buildFailed], ["runs", buildRunsTable], ["summary", buildSummary]]);
    api.ready = true;
  }

  whenReady(start);
})();
