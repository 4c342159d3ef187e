/* The run viewer's IMUs and laser scanners (docs/viewer.md, "Sensors"): for each scanner the sweep
 * nearest the cursor drawn on the plan, each beam's end point placed with the scanner's true pose
 * at that beam (docs/sensors.md, "Timing and motion"), a toggle per scanner and one for the exact
 * ranges; for each IMU the gyroscope, the accelerometer (measured and exact) and the true biases
 * as time plots. The data's `problem` lines are shown in the plots panel. Part of viewer.js's
 * closure (scripts/pages.py inlines it where viewer.js says CORRIDORSIM_INCLUDE
 * viewer_sensors.js); this opening comment stays out of the page. */
  // ---------------------------------------------------------------- sensors: the data
  const SCAN_COLORS = ["#3ddc84", "#ff6ec7", "#00e5ff", "#ffab40", "#b388ff", "#eeff41", "#ff8a80", "#84ffff"];
  const EXACT_COLOR = "#ffd54f";
  const AXIS_COLORS = ["#ff6b6b", "#69db7c", "#74c0fc"];   // x, y, z

  /** data.sensors normalised: {imus: [{name, problem, samples, gyro, accel, bias}], lasers: [...]},
   *  every series a `columns` object, every sweep checked where it is drawn. */
  function loadSensors(raw) {
    const s = isObj(raw) ? raw : {};
    const problem = (q) => (q.problem === null || q.problem === undefined ? null : str(q.problem));
    const imus = arr(s.imus).filter(isObj).map((q, k) => ({
      name: str(q.name, "imu_" + k), problem: problem(q), samples: num(q.samples),
      gyro: columns(q.gyro, ["x", "y", "z", "true_x", "true_y", "true_z"]),
      accel: columns(q.accel, ["x", "y", "z", "true_x", "true_y", "true_z"]),
      bias: columns(q.bias, ["wx", "wy", "wz", "ax", "ay", "az"]),
    }));
    const lasers = arr(s.lasers).filter(isObj).map((q, k) => {
      // the sweeps in time order (a stamp that is not a number drops its sweep)
      const t = arr(q.t).map(num);
      const order = t.map((v, i) => i).filter((i) => isFinite(t[i])).sort((i, j) => t[i] - t[j] || i - j);
      const pickRow = (a) => order.map((i) => arr(arr(a)[i]));
      return {
        name: str(q.name, "scanner_" + k), problem: problem(q), color: SCAN_COLORS[k % SCAN_COLORS.length],
        visible: true, sweeps: num(q.sweeps), stride: num(q.stride),
        angleMin: num(q.angle_min), angleInc: num(q.angle_increment),
        t: Float64Array.from(order, (i) => t[i]),
        first: pickRow(q.first), last: pickRow(q.last), ranges: pickRow(q.ranges), exact: pickRow(q.exact),
        cache: new Map(),   // sweep index -> its end points
      };
    });
    return { imus: imus, lasers: lasers };
  }

  // ---------------------------------------------------------------- sensors: the scans
  /** q0 to q1 (x, y, z, w) at s in [0, 1]: spherical interpolation along the shorter arc. */
  function slerp(q0, q1, s) {
    let d = q0[0] * q1[0] + q0[1] * q1[1] + q0[2] * q1[2] + q0[3] * q1[3];
    const b = d < 0 ? q1.map((v) => -v) : q1;
    d = Math.abs(d);
    let k0 = 1 - s, k1 = s;
    if (d < 0.9999995) {
      const th = Math.acos(Math.min(d, 1)), sn = Math.sin(th);
      k0 = Math.sin((1 - s) * th) / sn; k1 = Math.sin(s * th) / sn;
    }
    const q = [0, 1, 2, 3].map((i) => k0 * q0[i] + k1 * b[i]);
    const n = Math.hypot(q[0], q[1], q[2], q[3]) || 1;
    return q.map((v) => v / n);
  }

  /** The world (x, y) of the point (px, py, 0) of a body at p with orientation q (x, y, z, w). */
  function bodyToWorld(p, q, px, py) {
    const [x, y, z, w] = q;
    return [p[0] + (1 - 2 * (y * y + z * z)) * px + 2 * (x * y - z * w) * py,
      p[1] + 2 * (x * y + z * w) * px + (1 - 2 * (x * x + z * z)) * py];
  }

  /** Sweep i's beam end points, {x, y} (Float64Arrays) of the measured ranges and of the exact
   *  ones: beam j at angle_min + j * angle_increment about the scanner's z axis, from the pose at
   *  its own instant, interpolated between the first and the last beam's (position linearly,
   *  orientation by slerp; beam j fires j / (beams - 1) of the way). Ranges that are not finite
   *  (REP 117: +inf nothing in range, -inf too near, NaN no return) are skipped. */
  function sweepPoints(L, i) {
    if (L.cache.has(i)) return L.cache.get(i);
    const f = L.first[i].map(num), l = L.last[i].map(num);
    const ok = f.length >= 7 && l.length >= 7 && f.slice(0, 7).every(isFinite) && l.slice(0, 7).every(isFinite) &&
      isFinite(L.angleMin) && isFinite(L.angleInc);
    const out = { measured: { x: [], y: [] }, exact: { x: [], y: [] } };
    if (ok) {
      const beams = Math.max(L.ranges[i].length, L.exact[i].length);
      for (const [key, list] of [["measured", L.ranges[i]], ["exact", L.exact[i]]]) {
        const o = out[key];
        for (let j = 0; j < list.length; j++) {
          const r = num(list[j]);
          if (!isFinite(r)) continue;
          const s = beams > 1 ? j / (beams - 1) : 0;
          const p = [0, 1, 2].map((k) => f[k] + (l[k] - f[k]) * s);
          const q = slerp(f.slice(3, 7), l.slice(3, 7), s);
          const a = L.angleMin + j * L.angleInc;
          const [x, y] = bodyToWorld(p, q, r * Math.cos(a), r * Math.sin(a));
          o.x.push(x); o.y.push(y);
        }
      }
    }
    const pts = { origin: ok ? [f[0], f[1]] : null, measured: { x: Float64Array.from(out.measured.x), y: Float64Array.from(out.measured.y) },
      exact: { x: Float64Array.from(out.exact.x), y: Float64Array.from(out.exact.y) } };
    L.cache.set(i, pts);
    return pts;
  }

  /** The index of the sweep whose stamp is nearest t (-1 when the scanner has none). */
  function nearestSweep(L, t) {
    if (!L.t.length) return -1;
    const i = Math.max(lastAtOrBefore(L.t, t), 0);
    return i + 1 < L.t.length && Math.abs(L.t[i + 1] - t) < Math.abs(L.t[i] - t) ? i + 1 : i;
  }

  /** What the scan layer draws at t: {name: {t, sweep, points, x, y, exact: {points, x, y}}}. */
  function scanSnapshot(t) {
    const out = {};
    for (const L of D.sensors.lasers) {
      const i = nearestSweep(L, t);
      if (i < 0) { out[L.name] = null; continue; }
      const p = sweepPoints(L, i);
      out[L.name] = { t: L.t[i], sweep: i, origin: p.origin, points: p.measured.x.length, x: Array.from(p.measured.x), y: Array.from(p.measured.y),
        exact: { points: p.exact.x.length, x: Array.from(p.exact.x), y: Array.from(p.exact.y) } };
    }
    return out;
  }

  const showExact = () => { const c = $("cs-show-exact-scan"); return !!(c && c.checked); };

  /** The scan layer: each shown scanner's sweep nearest the cursor, its end points as dots (the
   *  exact ones under them when asked for) and the scanner where its sweep began. */
  function drawScans(ctx, t) {
    screenTransform(ctx);
    for (const L of D.sensors.lasers) {
      if (!L.visible) continue;
      const i = nearestSweep(L, t);
      if (i < 0) continue;
      const p = sweepPoints(L, i);
      const dots = (c, color, r) => {
        ctx.beginPath();
        for (let j = 0; j < c.x.length; j++) { const [sx, sy] = toScreen(c.x[j], c.y[j]); ctx.rect(sx - r, sy - r, 2 * r, 2 * r); }
        ctx.fillStyle = color; ctx.fill();
      };
      if (showExact()) dots(p.exact, EXACT_COLOR, 2.2);
      dots(p.measured, L.color, 1.2);
      if (p.origin) {
        const [sx, sy] = toScreen(p.origin[0], p.origin[1]);
        ctx.beginPath(); ctx.arc(sx, sy, 4, 0, 2 * Math.PI); ctx.strokeStyle = L.color; ctx.lineWidth = 1.5; ctx.stroke();
      }
    }
  }

  /** The legend's scanners (a toggle each, and the exact ranges) and what the sensors could not show. */
  function initSensors() {
    const S = D.sensors, box = $("cs-legend");
    if (S.lasers.length) {
      const exact = el("input", { type: "checkbox", id: "cs-show-exact-scan" });
      exact.addEventListener("change", requestDraw);
      box.append(el("span", { cls: "cs-hint", text: "scans:" }));
      for (const L of S.lasers) {
        const cb = el("input", { type: "checkbox", "data-scanner": L.name });
        cb.checked = true;
        cb.addEventListener("change", () => { L.visible = cb.checked; requestDraw(); });
        box.append(el("label", { title: L.problem ? L.problem : "show / hide the sweep of " + L.name + " nearest the cursor" }, [
          cb, el("span", { cls: "cs-swatch", style: "background:" + L.color }), L.name,
          L.problem ? el("span", { cls: "cs-failed", text: "not readable" }) : null]));
      }
      box.append(el("label", { title: "the exact ranges of the same beams" }, [exact,
        el("span", { cls: "cs-swatch", style: "background:" + EXACT_COLOR }), "exact ranges"]));
    }
  }

  // ---------------------------------------------------------------- sensors: the IMU plots
  /** Each IMU's plots, after the pipeline's: gyroscope and accelerometer (measured solid, exact
   *  dashed) and the true biases (gyroscope's on the left axis, accelerometer's on the right);
   *  first, one line for every sensor whose file could not be read. */
  function sensorPlots(box) {
    const S = D.sensors;
    if (!S.imus.length && !S.lasers.length) return;
    box.append(el("div", { cls: "cs-plot-title cs-sensors-title", text: "sensors" }));
    for (const q of S.imus.concat(S.lasers)) {
      if (q.problem) box.append(el("div", { cls: "cs-plot-empty cs-sensor-problem", text: q.name + " not shown: " + q.problem }));
    }
    for (const q of S.imus) {
      if (q.problem) continue;
      const kept = (c) => c.n + (isFinite(q.samples) && q.samples > c.n ? " of " + q.samples + " samples, decimated (extremes kept)" : c.n === 1 ? " sample" : " samples");
      const reading = (title, c, unit) => addPlot(box, {
        title: "IMU " + q.name + " · " + title, unit: unit, t: c.t, note: kept(c) + "; exact dashed",
        series: ["x", "y", "z"].map((a, k) => ({ label: a, data: gaps(c[a]), color: AXIS_COLORS[k], width: 1 }))
          .concat(["x", "y", "z"].map((a, k) => ({ label: "exact " + a, data: gaps(c["true_" + a]), color: AXIS_COLORS[k], width: 1, dash: [4, 3] }))),
      });
      reading("gyroscope", q.gyro, "rad/s");
      reading("accelerometer", q.accel, "m/s²");
      addPlot(box, {
        title: "IMU " + q.name + " · true biases", unit: "gyroscope rad/s", t: q.bias.t, y2: { label: "accel. m/s²" },
        note: kept(q.bias) + "; accelerometer dashed, right axis",
        series: ["wx", "wy", "wz"].map((a, k) => ({ label: a, data: gaps(q.bias[a]), color: AXIS_COLORS[k], width: 1 }))
          .concat(["ax", "ay", "az"].map((a, k) => ({ label: a, data: gaps(q.bias[a]), color: AXIS_COLORS[k], width: 1, dash: [4, 3], scale: "y2" }))),
      });
    }
  }

  /** The plots as drawn, for tests: [{title, n, series: [{label, n (finite values)}]}]. */
  function plotsApi() {
    return plots.map((p) => ({
      title: p.wrap.querySelector(".cs-plot-title").firstChild.textContent,
      n: p.u.data[0].length,
      series: p.u.series.slice(1).map((s, k) => ({ label: s.label, n: p.u.data[k + 1].filter((v) => v !== null).length })),
      data: p.u.data.map((a) => Array.from(a)),
    }));
  }

