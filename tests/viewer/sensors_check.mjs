// browser_test.mjs's `sensors` mode (docs/viewer.md, "Sensors"): a run's viewer.html with IMUs
// and laser scanners, checked against the run folder's sensors/ files (docs/sensors.md) with
// code of its own:
//  - the scan layer: at several cursor times, each scanner's drawn sweep is the one of the page's
//    sweeps nearest the cursor, a sweep of <laser>_scans.csv; its points are the beams with a
//    finite range, each placed from the scanner's pose interpolated between the first and the
//    last beam's (<laser>_scans_truth.csv; here by normalised linear interpolation of the
//    quaternions and a rotation matrix, the page uses slerp) within 5e-4 m, the exact ranges'
//    points too; the layer's pixels are on the plan, and go when its toggle is off;
//  - the IMU plots: per IMU a gyroscope, an accelerometer and a bias plot, each series as long as
//    the plot's stamps, every plotted sample a row of <imu>_imu.csv (values within the page's 5
//    significant digits), the file's extremes among them, fewer samples than the file's when it
//    has more than the page keeps;
//  - a sensor whose file could not be read: the page says so, naming it.

import fs from "node:fs";
import path from "node:path";

const POINT_TOL = 5e-4;   // m: the page rounds ranges and positions to 1e-4 m, quaternions to 1e-6
const T_TOL = 6e-5;

/** A sensors/ CSV file: {header, rows (arrays of numbers; inf, -inf and nan as in REP 117)}. */
function readCsv(file) {
  const lines = fs.readFileSync(file, "utf8").split("\n").filter((l) => l.trim());
  const value = (s) => (s === "inf" ? Infinity : s === "-inf" ? -Infinity : s === "nan" ? NaN : Number(s));
  return { header: lines[0].split(","), rows: lines.slice(1).map((l) => l.split(",").map(value)) };
}

/** R(q) for q = (x, y, z, w), normalised first. */
function matrix(q) {
  const n = Math.hypot(...q), [x, y, z, w] = q.map((v) => v / n);
  return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]];
}

/** The end points (x, y) of a sweep's finite ranges: beam j from the pose j / (beams - 1) of the
 *  way from the first beam's to the last's. */
function expectedPoints(scan, truth, ranges) {
  const [angleMin, inc] = [scan[1], scan[2]];
  const first = truth.slice(1, 8), last = truth.slice(8, 15);
  const sign = first[3] * last[3] + first[4] * last[4] + first[5] * last[5] + first[6] * last[6] < 0 ? -1 : 1;
  const out = [];
  ranges.forEach((r, j) => {
    if (!Number.isFinite(r)) return;
    const s = ranges.length > 1 ? j / (ranges.length - 1) : 0;
    const p = [0, 1, 2].map((k) => first[k] + (last[k] - first[k]) * s);
    const R = matrix([3, 4, 5, 6].map((k) => first[k] * (1 - s) + sign * last[k] * s));
    const a = angleMin + j * inc, b = [r * Math.cos(a), r * Math.sin(a), 0];
    out.push([p[0] + R[0][0] * b[0] + R[0][1] * b[1], p[1] + R[1][0] * b[0] + R[1][1] * b[1]]);
  });
  return out;
}

/** Pixels of the plan's canvas within 12 of the colour `hex` on each channel. */
async function planPixels(page, hex) {
  return page.evaluate((hex) => {
    const c = document.getElementById("cs-plan"), d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    const want = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - want[0]) <= 12 && Math.abs(d[i + 1] - want[1]) <= 12 && Math.abs(d[i + 2] - want[2]) <= 12) n++;
    return n;
  }, hex);
}

async function checkScanner(page, L, folder, t) {
  const { check, notes } = t;
  const scans = readCsv(path.join(folder, `${L.name}_scans.csv`));
  const truth = readCsv(path.join(folder, `${L.name}_scans_truth.csv`));
  check(L.sweeps === scans.rows.length, `scanner ${L.name}: the page says ${L.sweeps} sweeps, the file has ${scans.rows.length}`);
  const times = [0.1, 0.45, 0.8].map((f) => L.t[0] + f * (L.t[L.t.length - 1] - L.t[0]) + 0.013);
  for (const want of times) {
    const st = await page.evaluate((x) => { window.corridorsimViewer.setTime(x); return window.corridorsimViewer.state(); }, want);
    const q = st.scans && st.scans[L.name];
    if (!check(q, `scanner ${L.name}: no scan drawn at t = ${st.t}`)) continue;
    // the page's sweep nearest the cursor
    const nearest = L.t.reduce((b, s) => (Math.abs(s - st.t) < Math.abs(b - st.t) ? s : b), L.t[0]);
    check(Math.abs(q.t - nearest) <= 1e-9, `scanner ${L.name}: at t = ${st.t} the page draws the sweep of t = ${q.t}, its nearest is ${nearest}`);
    const row = scans.rows.findIndex((r) => Math.abs(r[0] - q.t) <= T_TOL);
    if (!check(row >= 0, `scanner ${L.name}: the drawn sweep t = ${q.t} is no sweep of ${L.name}_scans.csv`)) continue;
    for (const [what, ranges, got] of [["measured", scans.rows[row].slice(7), q], ["exact", truth.rows[row].slice(15), q.exact]]) {
      const pts = expectedPoints(scans.rows[row], truth.rows[row], ranges);
      if (!check(got.points === pts.length && got.x.length === pts.length,
        `scanner ${L.name}, sweep t = ${q.t}: ${got.points} ${what} points drawn, the file has ${pts.length} finite ranges of ${ranges.length}`)) continue;
      let worst = 0;
      pts.forEach(([x, y], k) => { worst = Math.max(worst, Math.hypot(got.x[k] - x, got.y[k] - y)); });
      check(worst <= POINT_TOL, `scanner ${L.name}, sweep t = ${q.t}: a ${what} point is ${worst.toExponential(2)} m from where the files put it`);
      if (what === "measured") {
        const k = Math.floor(pts.length / 2);
        notes.push(`scanner ${L.name} at t = ${st.t}: sweep t = ${q.t} (row ${row + 2}), ${pts.length} points of ${ranges.length} beams, ` +
          `point ${k} at (${got.x[k].toFixed(4)}, ${got.y[k].toFixed(4)}), the files' (${pts[k][0].toFixed(4)}, ${pts[k][1].toFixed(4)}); worst ${worst.toExponential(2)} m`);
        check(pts.length > ranges.length / 4, `scanner ${L.name}: only ${pts.length} of ${ranges.length} beams have a range: a weak check`);
      }
    }
  }
  // the layer is on the canvas: the scanner's colour, gone when its toggle is off
  const toggle = page.locator(`input[data-scanner="${L.name}"]`);
  const on = await planPixels(page, L.color);
  await toggle.uncheck();
  await page.waitForTimeout(100);
  const off = await planPixels(page, L.color);
  await toggle.check();
  await page.waitForTimeout(100);
  check(on >= 30 && off <= on / 10, `scanner ${L.name}: ${on} pixels of its colour ${L.color} on the plan with the scan shown, ${off} hidden`);
  const before = await planPixels(page, "#ffd54f");
  await page.locator("#cs-show-exact-scan").check();
  await page.waitForTimeout(100);
  const exact = await planPixels(page, "#ffd54f");
  await page.locator("#cs-show-exact-scan").uncheck();
  check(exact - before >= 30, `scanner ${L.name}: the exact ranges add ${exact - before} pixels of their colour`);
  notes.push(`scanner ${L.name}: ${on} pixels drawn, ${off} with its toggle off; exact ranges ${exact - before} pixels`);
}

function checkImu(plots, imu, folder, t) {
  const { check, notes } = t;
  const file = readCsv(path.join(folder, `${imu.name}_imu.csv`));
  const col = (name) => file.header.indexOf(name);
  const byT = new Map(file.rows.map((r) => [Math.round(r[0] * 1e4), r]));
  const groups = [["gyroscope", [["x", "wx_rad_s"], ["y", "wy_rad_s"], ["z", "wz_rad_s"], ["exact x", "true_wx_rad_s"], ["exact y", "true_wy_rad_s"], ["exact z", "true_wz_rad_s"]], 5],
    ["accelerometer", [["x", "ax_m_s2"], ["y", "ay_m_s2"], ["z", "az_m_s2"], ["exact x", "true_ax_m_s2"], ["exact y", "true_ay_m_s2"], ["exact z", "true_az_m_s2"]], 5],
    ["true biases", [["wx", "bias_wx_rad_s"], ["wy", "bias_wy_rad_s"], ["wz", "bias_wz_rad_s"], ["ax", "bias_ax_m_s2"], ["ay", "bias_ay_m_s2"], ["az", "bias_az_m_s2"]], 4]];
  check(imu.samples === file.rows.length, `IMU ${imu.name}: the page says ${imu.samples} samples, the file has ${file.rows.length}`);
  for (const [title, series, digits] of groups) {
    const p = plots.find((q) => q.title === `IMU ${imu.name} · ${title}`);
    if (!check(p, `IMU ${imu.name}: no plot "${title}" (plots: ${plots.map((q) => q.title).join("; ")})`)) continue;
    check(p.series.length === 6 && p.series.every((s) => s.n === p.n),
      `IMU ${imu.name} ${title}: series ${p.series.map((s) => s.label + " " + s.n).join(", ")} for ${p.n} stamps`);
    check(p.n > 100 && (file.rows.length <= 6000 ? p.n === file.rows.length : p.n < file.rows.length && p.n <= 6000),
      `IMU ${imu.name} ${title}: ${p.n} samples plotted of the file's ${file.rows.length}`);
    let bad = 0;
    series.forEach(([label, column], k) => {
      const s = p.series[k], c = col(column);
      check(s && s.label === label, `IMU ${imu.name} ${title}: series ${k + 1} is ${s && s.label}, not ${label}`);
      p.data[0].forEach((tt, i) => {
        const r = byT.get(Math.round(tt * 1e4)), v = p.data[k + 1][i];
        if (!r || Math.abs(v - r[c]) > Math.abs(r[c]) * Math.pow(10, 1 - digits) + 1e-12) bad++;
      });
      // the file's extremes are plotted
      const values = file.rows.map((r) => r[c]);
      for (const x of [Math.min(...values), Math.max(...values)]) {
        check(p.data[k + 1].some((v) => Math.abs(v - x) <= Math.abs(x) * Math.pow(10, 1 - digits) + 1e-12),
          `IMU ${imu.name} ${title} ${label}: the file's extreme ${x} is not plotted`);
      }
    });
    check(bad === 0, `IMU ${imu.name} ${title}: ${bad} plotted values are no row of ${imu.name}_imu.csv`);
    notes.push(`IMU ${imu.name} ${title}: ${p.n} of ${file.rows.length} samples plotted, 6 series, every one a row of the file, extremes kept`);
  }
}

/** The `sensors` mode: opts {page, run, shots}; t: browser_test's {fail, check, notes, openPage, shot}. */
export async function testSensors(opts, browser, t) {
  const { fail, check, openPage, shot } = t;
  const context = await browser.newContext({ viewport: { width: 1600, height: 1000 }, deviceScaleFactor: 1 });
  const log = [];
  const page = await openPage(context, new URL("file://" + path.resolve(opts.page)).href, log);
  await page.waitForFunction(() => window.corridorsimViewer && window.corridorsimViewer.ready === true, null, { timeout: 30000 });
  const data = await page.evaluate(() => JSON.parse(document.getElementById("corridorsim-data").textContent).sensors);
  if (!check(data && Array.isArray(data.imus) && Array.isArray(data.lasers), "the page's data has no sensors section")) return context.close();
  const folder = path.join(opts.run, "sensors");
  const shown = await page.evaluate(() => Array.from(document.querySelectorAll(".cs-sensor-problem")).map((e) => e.textContent));
  for (const q of data.imus.concat(data.lasers)) {
    if (q.problem) check(shown.includes(`${q.name} not shown: ${q.problem}`), `${q.name}: the page does not show its problem (${q.problem}); it shows ${JSON.stringify(shown)}`);
  }
  check(shown.length === data.imus.concat(data.lasers).filter((q) => q.problem).length, `the page shows ${shown.length} sensor problems: ${JSON.stringify(shown)}`);
  await page.evaluate(() => document.getElementById("cs-fit").click());
  for (const L of data.lasers.filter((q) => !q.problem)) {
    L.color = await page.evaluate((name) => document.querySelector(`input[data-scanner="${name}"]`).nextElementSibling.style.background, L.name);
    const rgb = /rgb\((\d+), (\d+), (\d+)\)/.exec(L.color);
    if (rgb) L.color = "#" + rgb.slice(1).map((v) => Number(v).toString(16).padStart(2, "0")).join("");
    await checkScanner(page, L, folder, t);
  }
  const plots = await page.evaluate(() => window.corridorsimViewer.plots());
  for (const imu of data.imus.filter((q) => !q.problem)) checkImu(plots, imu, folder, t);
  fs.mkdirSync(opts.shots, { recursive: true });
  await page.locator("#cs-show-exact-scan").check().catch(() => {});
  await shot(page, opts.shots, `sensors_${path.basename(opts.run)}.png`);
  for (const e of await page.evaluate(() => window.corridorsimViewer.errors.slice())) fail("the page caught: " + e);
  for (const m of log) fail(m);
  await context.close();
}
