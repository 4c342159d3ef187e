#!/usr/bin/env node
// The viewer and report pages on odd data (docs/viewer.md): empty objects, failed pipelines,
// null and NaN values, unsorted and duplicated stamps, missing sections, a broken JPEG, sensors
// (IMUs, scanners) with malformed sweeps and series or only a problem line, 100,000 samples per
// series, and 2 IMUs and 2 scanners of 720 beams, each with the most make_viewer.py keeps of one. Each page is filled from viewer/ here (as scripts/make_viewer.py
// fills it), opened in headless chromium, driven a little; it must load, report no error and keep
// answering state(). Also prints how long the large page takes.
//
//   node tests/viewer/odd_data_test.mjs [--shots OUT_DIR] [--keep PAGES_DIR]
//
// Exit 0: pass; 1: fail (one line per failure). A global timeout (180 s) fails instead of hanging.

import { createRequire } from "node:module";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const VIEWER = path.join(HERE, "..", "..", "viewer");
const UPLOT = path.join(VIEWER, "node_modules", "uplot", "dist");
const failures = [];
const fail = (m) => failures.push(m);

function fill(template, js, data) {
  const read = (p) => fs.readFileSync(p, "utf8");
  const safe = (s) => s.replace(/<\//g, "<\\/");
  // as scripts/pages.py's with_parts: each CORRIDORSIM_INCLUDE line becomes the part it names,
  // without the part's opening comment
  const part = (name) => {
    const t = read(path.join(VIEWER, name));
    for (const [start, end] of [["/*", "*/\n"], ["<!--", "-->\n"]]) if (t.startsWith(start)) return t.slice(t.indexOf(end) + end.length);
    return t;
  };
  const withParts = (name) => read(path.join(VIEWER, name)).replace(/^[ \t]*(?:\/\*|<!--)CORRIDORSIM_INCLUDE ([A-Za-z0-9_.-]+)(?:\*\/|-->)\n/gm, (m, name) => part(name));
  const parts = {
    "/*CORRIDORSIM_UPLOT_CSS*/": read(path.join(UPLOT, "uPlot.min.css")),
    "/*CORRIDORSIM_VIEWER_CSS*/": read(path.join(VIEWER, "viewer.css")),
    "/*CORRIDORSIM_UPLOT_JS*/": safe(read(path.join(UPLOT, "uPlot.iife.min.js"))),
    "/*CORRIDORSIM_PAGE_JS*/": safe(withParts(js)),
    // as scripts/pages.py's json_in_script: no string can end the element or escape it
    CORRIDORSIM_DATA_JSON: JSON.stringify(data).replace(/</g, "\\u003c").replace(/>/g, "\\u003e").replace(/&/g, "\\u0026"),
    CORRIDORSIM_TITLE: "odd data",
  };
  // one pass, in the template's order, so nothing inserted is searched again
  let page = withParts(template);
  const found = Object.keys(parts).map((k) => [page.indexOf(k), k]).filter(([i]) => i >= 0).sort((a, b) => a[0] - b[0]);
  let out = "", at = 0;
  for (const [i, k] of found) { out += page.slice(at, i) + parts[k]; at = i + k.length; }
  return out + page.slice(at);
}

const range = (n, f) => Array.from({ length: n }, (_, i) => f(i));

function bigRun(n) {
  const t = range(n, (i) => Math.round(i * 0.01 * 1e4) / 1e4);
  const x = t.map((v) => Math.round(v * 0.3 * 1e4) / 1e4), y = t.map((v) => Math.round(Math.sin(v / 20) * 1e4) / 1e4);
  const yaw = t.map((v) => Math.round(Math.cos(v / 20) * 1e5) / 1e5);
  const cov = t.map((v) => 1e-4 * (1 + v / 100));
  const pipe = (name, k) => ({
    name: name, failed: null,
    path: { t: t, x: x.map((v) => v + k * 0.01), y: y, yaw: yaw, cxx: cov, cxy: cov.map((v) => v / 3), cyy: cov },
    truth_at: { x: x, y: y, yaw: yaw },
    errors: { t: t, ex: t.map((v) => 0.01 * Math.sin(v)), ey: t.map((v) => 0.01 * Math.cos(v)), eyaw: t.map(() => 0.001),
      sx: t.map(() => 0.02), sy: t.map(() => 0.02), syaw: t.map(() => 0.01), nees: t.map((v) => 1 + Math.abs(Math.sin(v))) },
    nees_band: [0.2158, 9.348],
    nis: { corner: { dof: 2, band: [0.0506, 7.378], t: t, nis: t.map((v) => 1 + Math.sin(v) ** 2), accepted: t.map((v, i) => (i % 50 ? 1 : 0)) } },
    frame_ms: { t: t, ms: t.map((v) => 5 + Math.sin(v)), landmarks: t.map((v, i) => i % 40) },
    landmarks: range(500, (i) => ({ id: i, type: "corner", status: "converged", label: "", x: i * 0.5, y: 1, cxx: 0.01, cxy: 0, cyy: 0.01, first_seen: i, truth: [i * 0.5, 1.1], wrong: i % 97 === 0 })),
    detections: [], metrics: { ate_rmse_m: 0.1 },
  });
  return {
    schema: 1, title: "big", duration_s: t[n - 1], world: { bounds: [-1, -2, t[n - 1] * 0.3 + 1, 2], walls: [[0, -1.5, 300, -1.5]], doors: [], plates: [], lamps: [], distractors: [] },
    truth: { t: t, x: x, y: y, yaw: yaw }, pipelines: [pipe("a", 0), pipe("b", 1)],
    events: range(2000, (i) => ({ t: i * 0.5, type: i % 2 ? "slip" : "collision", text: "e" + i })), expectations: [], frames: {},
  };
}

/** The sensors section at its largest (scripts/viewer_sensors.py: 6000 samples per IMU group,
 *  96,000 ranges per scanner) for `imus` IMUs and `lasers` scanners of `beams` beams. */
function bigSensors(imus, lasers, beams) {
  const n = 6000, t = range(n, (i) => Math.round(i * 0.05 * 1e4) / 1e4);
  const wave = (k) => t.map((v) => Math.round(Math.sin(v + k) * 1e5) / 1e5);
  const group = (names) => Object.assign({ t: t }, ...names.map((c, k) => ({ [c]: wave(k) })));
  const sweeps = Math.floor(96000 / beams);
  const pose = (i, dx) => [i * 0.3 + dx, 0.1, 0.3, 0, 0, Math.sin(i / 100) * 0.1, Math.sqrt(1 - (Math.sin(i / 100) * 0.1) ** 2)];
  return {
    imus: range(imus, (k) => ({ name: "imu" + k, file: "sensors/imu" + k + "_imu.csv", samples: 300000, problem: null,
      gyro: group(["x", "y", "z", "true_x", "true_y", "true_z"]), accel: group(["x", "y", "z", "true_x", "true_y", "true_z"]),
      bias: group(["wx", "wy", "wz", "ax", "ay", "az"]) })),
    lasers: range(lasers, (k) => ({ name: "scan" + k, file: "sensors/scan" + k + "_scans.csv", problem: null, sweeps: sweeps * 10, stride: 10,
      beams: beams, angle_min: -2.35619, angle_increment: 4.71239 / (beams - 1), time_increment: 3.5e-5, range_min: 0.1, range_max: 30,
      t: range(sweeps, (i) => i * 0.25), first: range(sweeps, (i) => pose(i, 0)), last: range(sweeps, (i) => pose(i, 0.004)),
      ranges: range(sweeps, (i) => range(beams, (j) => (j % 50 === 7 ? null : Math.round((1.5 + Math.abs(Math.sin(j / 40)) * 3) * 1e4) / 1e4))),
      exact: range(sweeps, (i) => range(beams, (j) => Math.round((1.5 + Math.abs(Math.sin(j / 40)) * 3) * 1e4) / 1e4)) })),
  };
}

const SMALL_RUN = { schema: 1, truth: { t: [0, 1, 2, 3], x: [0, 1, 2, 3], y: [0, 0, 0, 0], yaw: [0, 0, 0, 0] }, pipelines: [] };

const VIEWER_CASES = {
  empty: {},
  not_an_object: [1, 2, 3],
  no_pipelines: { schema: 1, truth: { t: [0, 1, 2], x: [0, 1, 2], y: [0, 0, 0], yaw: [0, 0, 0] }, pipelines: [] },
  failed_and_nulls: {
    schema: 1, title: "odd", scenario: null, seed: null, duration_s: null,
    world: { bounds: null, walls: [[0, 0, 1], [0, 0, "a", 1], [0, -1, 10, -1]], doors: [{ a: null, b: [1, 1], state: null }, { a: [2, 1], b: [3, 1], state: "weird", room: null }],
      plates: [{ center: [1, null] }, { center: [4, 1], normal: null, room: 12 }], lamps: [{ center: [1, 0], shape: "panel", extent: null, on: false }, { center: [2, 0], shape: "circular", extent: [1, 2], on: true }],
      distractors: [{ center: [3, 0] }] },
    truth: { t: [0, 0.5, 0.5, 1, 2, null, 3], x: [0, null, 1, 2, 3, 4], y: [0, 0, 0, 0, 0, 0, 0], yaw: [0, 0, 0, 0] },
    pipelines: [
      { name: "failed", failed: "threw", path: null, truth_at: null, errors: null, nees_band: null, nis: {}, frame_ms: null, landmarks: [], detections: [], metrics: null },
      { name: "gaps", failed: null,
        path: { t: [2, 0, 1], x: [1, 2, null], y: [0, 0, 0], yaw: [0, null, 0], cxx: [null, -1, 0.1], cxy: [0, 0, 0], cyy: [0.1, 0.1] },
        truth_at: { x: [0], y: [] },
        errors: { t: [0, 1, 2, 3], ex: [null, 0.1, null, 0.2], ey: [0, 0, 0, 0], eyaw: [], sx: [null, null, null, null], nees: [0, -1, null, 5] },
        nees_band: [1], nis: { lamp: { dof: null, band: null, t: [0, 1], nis: [null, 3] }, bad: null }, frame_ms: { t: [], ms: [] },
        landmarks: [{ id: 1, x: null, y: 1 }, { id: 2, x: 1, y: 1, first_seen: null, truth: [null, 1], wrong: true, cxx: null }, null],
        detections: [{ t: 0, camera: "front", box: [1, 2] }, { t: null }, { t: 1, camera: "front", u: 3, v: 4, landmark: 2, label: "L" }],
        metrics: { ate_rmse_m: null, nested: { a: [1, 2], b: { c: "x" } } } },
      { name: "gaps", failed: null },
    ],
    events: [{ t: null, type: "x" }, { t: 1, type: null, text: null }, { t: 99, type: "slip" }, "bad"],
    expectations: [{ text: null, measured: "a", passed: null }, null],
    frames: { front: { width: 4, height: 3, scale: null, t: [0, 1], jpeg: ["notbase64!!", null] }, rear: null, top: { t: null } },
  },
  big: bigRun(100000),
  sensors_odd: Object.assign({}, SMALL_RUN, { sensors: {
    imus: [null, "imu", { name: null, samples: "x", gyro: { t: [0, null, 1, 1, -3], x: [1], true_z: [null, NaN, "a", 2] }, accel: null, bias: "x" },
      { name: "broken", problem: "sensors/broken_imu.csv:3: not a number in the line" }, { name: "empty", gyro: {}, accel: { t: [] }, bias: { t: [0], wx: [1e300] } }],
    lasers: [null, { name: "s", t: [1, null, 0.5, "x", 2], first: [[0, 0, 0, 0, 0, 0, 1], null, [1, 1]], last: [[1, 0, 0, 0, 0, 0, 1]], ranges: [[1, null, 2], "x"], exact: null, angle_min: null },
      { name: "gone", problem: "sensors/gone_scans_truth.csv: is missing (the scanner's true poses are in it)" },
      { name: "zero_quaternion", t: [0, 2], first: [[0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 1]], last: [[0, 0, 0, 0, 0, 0, 0], [1, 1, 0, 0, 0, -1, 0]],
        ranges: [[1e9, -1, 3], [1, 2, 3, 4]], exact: [[1], []], angle_min: 0, angle_increment: 0.1 },
      { name: "one_beam", t: [1], first: [[0, 0, 0, 0, 0, 0, 1]], last: [[0, 0, 0, 0, 0, 0, 1]], ranges: [[2]], exact: [[2]], angle_min: 0, angle_increment: 0 }],
  } }),
  sensors_not_objects: Object.assign({}, SMALL_RUN, { sensors: { imus: "x", lasers: 3 } }),
  sensors_big: Object.assign({}, SMALL_RUN, { duration_s: 300, sensors: bigSensors(2, 2, 720) }),
};

const REPORT_CASES = {
  empty: {},
  odd: {
    schema: 1, title: null, pipelines: null, metrics: [{ name: null }, "x"],
    points: [{ id: "p0", label: null, values: null }, null],
    runs: [{ point: "p0", seed: 1, status: "failed", reason: null, viewer: "javascript:alert(1)", metrics: null },
      { point: "p9", seed: null, status: null, viewer: null, metrics: { a: { ate_rmse_m: "x", nees_mean: 2 } } },
      { point: "p0", seed: 2, status: "finished", viewer: "/abs/path.html", metrics: { a: { ate_rmse_m: 0.1 }, b: null } }],
    summary: [{ point: "p0", pipeline: "a", metric: "ate_rmse_m", mean: null }, null],
    paired: [{ point: "p0", a: "a", b: "b", metric: "nees_mean", diff: 1, diff_ci_low: null }, { metric: "ate_rmse_m", diff: "x" }],
    series: { p0: { a: { t: [0, 1, 2], error_mean: [null, 1], nees_mean: [1, 2, 3], nees_band: [null, 4], nees_low: [1, 1], nees_high: [3] }, b: null }, p9: null },
    sweep: { keys: ["k", null] }, expectations: [null, { text: "t", passed: true }],
  },
};

async function main() {
  const shotsIdx = process.argv.indexOf("--shots");
  const shots = shotsIdx > 0 ? process.argv[shotsIdx + 1] : null;
  const timer = setTimeout(() => { console.error("odd_data_test: FAIL: timed out after 180 s"); process.exit(1); }, 180000);
  const require = createRequire(path.join(VIEWER, "package.json"));
  const { chromium } = require("playwright-core");
  const keepIdx = process.argv.indexOf("--keep");   // --keep DIR: leave the pages there
  const keep = keepIdx > 0 ? process.argv[keepIdx + 1] : null;
  if (keep) fs.mkdirSync(keep, { recursive: true });
  const dir = keep || fs.mkdtempSync(path.join(os.tmpdir(), "corridorsim-odd-"));
  const browser = await chromium.launch({ executablePath: process.env.CORRIDORSIM_CHROMIUM || "/usr/bin/chromium", headless: true, args: ["--no-sandbox"] });
  try {
    const context = await browser.newContext({ viewport: { width: 1400, height: 900 } });
    const cases = Object.entries(VIEWER_CASES).map(([k, v]) => ["viewer", k, v]).concat(Object.entries(REPORT_CASES).map(([k, v]) => ["report", k, v]));
    for (const [kind, name, data] of cases) {
      const file = path.join(dir, `${kind}_${name}.html`);
      fs.writeFileSync(file, fill(kind + ".html", kind + ".js", data));
      const page = await context.newPage();
      const log = [];
      page.on("console", (m) => { if (m.type() === "error") log.push("console error: " + m.text()); });
      page.on("pageerror", (e) => log.push("page error: " + e.message));
      const api = kind === "viewer" ? "corridorsimViewer" : "corridorsimReport";
      const t0 = Date.now();
      try {
        await page.goto(pathToFileURL(file).href);
        await page.waitForFunction((a) => window[a] && window[a].ready === true, api, { timeout: 30000 });
        const ms = Date.now() - t0;
        if (kind === "viewer") {
          const r = await page.evaluate(() => {
            const v = window.corridorsimViewer, out = [];
            for (const t of [-1e9, 0, 0.5, 1, 1.7, 50, 1e9, NaN, "x", null]) { v.setTime(t); out.push(v.state()); }
            const t1 = performance.now();
            for (let i = 0; i < 50; i++) v.setTime(i * 20);
            return { states: out, setTimeMs: (performance.now() - t1) / 50 };
          });
          if (r.states.some((s) => !s || typeof s.t !== "number")) fail(`viewer ${name}: state() without a numeric t`);
          await page.keyboard.press("ArrowRight"); await page.keyboard.press("Shift+ArrowLeft"); await page.keyboard.press("Space");
          await page.waitForTimeout(300); await page.keyboard.press("Space");
          const sel = await page.$("#cs-focus option:nth-child(2)");
          if (sel) await page.selectOption("#cs-focus", { index: 1 });
          if (name === "big") console.log(`odd_data_test: big page (2 pipelines x 100,000 samples, 2,000 events): ready in ${ms} ms, setTime + draw ${r.setTimeMs.toFixed(1)} ms`);
          if (name.startsWith("sensors")) {
            // every scanner answers in state(), and every IMU that has data has its three plots
            // (a plot without samples says so in place of its chart: the titles are the DOM's)
            const s = r.states[3], plots = await page.$$eval(".cs-plot > .cs-plot-title", (e) => e.map((x) => x.firstChild.textContent));
            const lasers = Array.isArray(data.sensors.lasers) ? data.sensors.lasers.filter((q) => q && typeof q === "object") : [];
            const scans = s.scans ? Object.keys(s.scans).length : 0;
            if (scans !== lasers.length) fail(`viewer ${name}: state() has ${scans} scans for ${lasers.length} scanners`);
            const imus = Array.isArray(data.sensors.imus) ? data.sensors.imus.filter((q) => q && typeof q === "object" && !q.problem) : [];
            if (plots.filter((t) => t.startsWith("IMU ")).length !== 3 * imus.length) fail(`viewer ${name}: ${plots.filter((t) => t.startsWith("IMU ")).length} IMU plots for ${imus.length} IMUs`);
            const shown = await page.$$eval(".cs-sensor-problem", (e) => e.map((x) => x.textContent));
            for (const q of [].concat(data.sensors.imus, data.sensors.lasers)) {
              if (q && q.problem && !shown.includes(`${q.name} not shown: ${q.problem}`)) fail(`viewer ${name}: ${q.name}'s problem is not shown`);
            }
            if (name === "sensors_big") {
              const size = fs.statSync(file).size;
              console.log(`odd_data_test: sensors_big page (2 IMUs x 3 x 6000 samples, 2 scanners x ${lasers[0].t.length} sweeps of 720 beams, ${(size / 1e6).toFixed(1)} MB): ready in ${ms} ms, setTime + draw ${r.setTimeMs.toFixed(1)} ms`);
            }
          }
        } else {
          for (const th of await page.$$("th.cs-sortable")) await th.click();
          if (await page.$("#cs-metric option:nth-child(2)")) await page.selectOption("#cs-metric", { index: 1 });
          if (await page.$("#cs-columns")) await page.selectOption("#cs-columns", "all");
          const bad = await page.$$eval("a[href]", (as) => as.map((a) => a.getAttribute("href")).filter((h) => /^(javascript:|\/)/i.test(h)));
          for (const h of bad) fail(`report ${name}: a link to ${h} (not a relative path)`);
        }
        if (shots) { fs.mkdirSync(shots, { recursive: true }); await page.screenshot({ path: path.join(shots, `odd_${kind}_${name}.png`) }); }
        for (const e of await page.evaluate((a) => window[a].errors.slice(), api)) fail(`${kind} ${name}: the page caught: ${e}`);
      } catch (e) {
        fail(`${kind} ${name}: ${e.message.split("\n")[0]}`);
      }
      for (const m of log) fail(`${kind} ${name}: ${m}`);
      await page.close();
    }
  } finally {
    await browser.close();
    if (!keep) fs.rmSync(dir, { recursive: true, force: true });
    clearTimeout(timer);
  }
  if (failures.length) { for (const f of failures) console.error("odd_data_test: FAIL: " + f); process.exit(1); }
  console.log("odd_data_test: PASS");
}

main().catch((e) => { console.error("odd_data_test: FAIL: " + (e && e.stack ? e.stack : e)); process.exit(1); });
