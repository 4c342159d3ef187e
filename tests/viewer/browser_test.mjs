#!/usr/bin/env node
// Headless browser test of a run's viewer.html and a study's report.html (docs/viewer.md).
//
//   node tests/viewer/browser_test.mjs viewer --page RUN_DIR/viewer.html --run RUN_DIR --shots OUT_DIR
//   node tests/viewer/browser_test.mjs report --page STUDY_DIR/report.html --shots OUT_DIR
//   node tests/viewer/browser_test.mjs sensors --page RUN_DIR/viewer.html --run RUN_DIR --shots OUT_DIR
//
// Drives Debian's chromium (or $CORRIDORSIM_CHROMIUM) through playwright-core from
// viewer/node_modules. Viewer: no console or page errors; the drawn poses at several cursor times
// are the poses of RUN_DIR's TUM files and the drawn 2-sigma ellipses those of its _cov.txt files;
// the cursor snaps to the page's stamps; the URL fragment, plot clicks and keys move it. Report:
// no errors, every relative link resolves to a file, a header click sorts the runs table. Sensors
// (a run with IMUs and laser scanners): the scan layer and the IMU plots against RUN_DIR/sensors/
// (sensors_check.mjs).
// Screenshots go to OUT_DIR. Exit 0: pass; 1: fail (one line per failure); 2: bad command line.
// A global timeout (CORRIDORSIM_BROWSER_TEST_TIMEOUT_S, default 120 s) fails instead of hanging.

import { createRequire } from "node:module";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";
import { testSensors } from "./sensors_check.mjs";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const TIMEOUT_S = Number(process.env.CORRIDORSIM_BROWSER_TEST_TIMEOUT_S || 120);
const POS_TOL = 2e-4, YAW_TOL = 2e-4;   // the page rounds to 1e-4 m and 1e-5 rad
const T_TOL = 6e-5;                     // the page rounds stamps to 1e-4 s

const failures = [];
const notes = [];
function fail(msg) { failures.push(msg); }
function check(ok, msg) { if (!ok) fail(msg); return ok; }

function usage(msg) {
  if (msg) console.error("browser_test: " + msg);
  console.error("usage: browser_test.mjs viewer --page RUN_DIR/viewer.html --run RUN_DIR --shots OUT_DIR\n" +
    "       browser_test.mjs report --page STUDY_DIR/report.html --shots OUT_DIR\n" +
    "       browser_test.mjs sensors --page RUN_DIR/viewer.html --run RUN_DIR --shots OUT_DIR");
  process.exit(2);
}

function parseArgs(argv) {
  const mode = argv[0];
  if (!["viewer", "report", "sensors"].includes(mode)) usage("the first argument is viewer, report or sensors");
  const o = { mode };
  for (let i = 1; i < argv.length; i++) {
    const k = argv[i];
    if (!["--page", "--run", "--shots"].includes(k) || i + 1 >= argv.length) usage("unexpected argument " + k);
    o[k.slice(2)] = argv[++i];
  }
  if (!o.page) usage("--page is required");
  if (!o.shots) usage("--shots is required");
  if (mode !== "report" && !o.run) usage(mode + " mode needs --run");
  if (!fs.existsSync(o.page)) usage("no such page: " + o.page);
  return o;
}

// ------------------------------------------------------------------ the run's files
/** TUM (8 columns) or ov_eval (20 columns) lines as {t, x, y, yaw[, cxx, cxy, cyy]}. */
function readPoses(file) {
  const out = [];
  const lines = fs.readFileSync(file, "utf8").split(/\r?\n/);
  lines.forEach((line, n) => {
    const s = line.trim();
    if (!s || s.startsWith("#")) return;
    const v = s.split(/[\s,]+/).map(Number);
    if (v.length < 8 || v.some((x) => !Number.isFinite(x))) throw new Error(`${file}:${n + 1}: not a pose line`);
    const p = { t: v[0], x: v[1], y: v[2], yaw: 2 * Math.atan2(v[6], v[7]) };
    if (v.length >= 20) { p.cxx = v[14]; p.cxy = v[15]; p.cyy = v[17]; }
    out.push(p);
  });
  return out;
}

/** Index of the last pose with t <= t0 (+ tolerance), -1 when none. */
function lastAtOrBefore(poses, t0) {
  let lo = 0, hi = poses.length - 1, r = -1;
  while (lo <= hi) { const m = (lo + hi) >> 1; if (poses[m].t <= t0 + T_TOL) { r = m; lo = m + 1; } else hi = m - 1; }
  return r;
}

/** The last of the ascending stamps at or before t (the first when t is before them all). */
function lastStamp(stamps, t) {
  let lo = 0, hi = stamps.length - 1, r = 0;
  while (lo <= hi) { const m = (lo + hi) >> 1; if (stamps[m] <= t) { r = m; lo = m + 1; } else hi = m - 1; }
  return stamps[r];
}

const wrapAngle = (a) => Math.atan2(Math.sin(a), Math.cos(a));

function ellipseOf(cxx, cxy, cyy) {
  const m = (cxx + cyy) / 2, r = Math.hypot((cxx - cyy) / 2, cxy);
  return { a: 2 * Math.sqrt(Math.max(m + r, 0)), b: 2 * Math.sqrt(Math.max(m - r, 0)), angle: 0.5 * Math.atan2(2 * cxy, cxx - cyy) };
}

function fmtPose(p) { return p ? `(t ${p.t}, x ${p.x}, y ${p.y}, yaw ${p.yaw})` : "none"; }

/** The page's pose against the file's latest pose at or before the cursor. */
function comparePose(what, q, poses, cursorT, keptStamps) {
  const i = lastAtOrBefore(poses, cursorT);
  if (!check(q, `${what}: nothing drawn at t = ${cursorT}`) || i < 0) {
    if (q) fail(`${what}: the page draws a pose at t = ${cursorT} but its file has none at or before it`);
    return null;
  }
  let f = poses[i];
  if (typeof q.t === "number" && Math.abs(q.t - f.t) > T_TOL) {
    // The page drew an older sample. Right only if its data dropped the file's newer one.
    const kept = keptStamps && keptStamps.some((s) => Math.abs(s - f.t) <= T_TOL);
    if (kept) {
      fail(`${what}: at t = ${cursorT} the page draws the sample of t = ${q.t} though it keeps the file's later one at t = ${f.t}`);
      return null;
    }
    notes.push(`${what}: the file's pose at t = ${f.t} is not in the page's data (decimated); compared the drawn one at t = ${q.t}`);
    const j = lastAtOrBefore(poses, q.t);
    if (!check(j >= 0 && Math.abs(poses[j].t - q.t) <= T_TOL, `${what}: the page's sample t = ${q.t} is no stamp of its file`)) return null;
    f = poses[j];
  }
  const dx = Math.abs(q.x - f.x), dy = Math.abs(q.y - f.y), dyaw = Math.abs(wrapAngle(q.yaw - f.yaw));
  check(dx <= POS_TOL && dy <= POS_TOL && dyaw <= YAW_TOL,
    `${what}: at t = ${cursorT} the page draws ${fmtPose(q)}, the file has ${fmtPose(f)} (|dx| ${dx.toExponential(2)}, |dy| ${dy.toExponential(2)}, |dyaw| ${dyaw.toExponential(2)})`);
  return f;
}

function compareEllipse(what, e, f, q) {
  if (f.cxx === undefined) return;
  const want = ellipseOf(f.cxx, f.cxy, f.cyy);
  if (!check(e && typeof e === "object", `${what}: no ellipse drawn at t = ${f.t} (the file has a covariance)`)) return;
  const tol = (v) => 0.01 * v + 1e-4;
  check(Math.abs(e.a - want.a) <= tol(want.a) && Math.abs(e.b - want.b) <= tol(want.b),
    `${what}: at t = ${f.t} the ellipse's semi-axes are ${e.a}, ${e.b} m; the file's 2-sigma ones ${want.a}, ${want.b} m`);
  check(Math.abs(e.cx - q.x) <= 1e-9 && Math.abs(e.cy - q.y) <= 1e-9, `${what}: the ellipse is not centred on the drawn pose at t = ${f.t}`);
  if (want.a - want.b > 0.05 * want.a) {  // the axis direction is defined (not a circle)
    let d = Math.abs(e.angle - want.angle) % Math.PI;
    d = Math.min(d, Math.PI - d);
    check(d <= 0.01, `${what}: at t = ${f.t} the ellipse's angle is ${e.angle} rad, the file's ${want.angle} rad`);
  }
}

// ------------------------------------------------------------------ browser
async function launch() {
  const require = createRequire(path.join(HERE, "..", "..", "viewer", "package.json"));
  let chromium;
  try { ({ chromium } = require("playwright-core")); } catch (e) {
    throw new Error("playwright-core is not installed in viewer/node_modules (run npm ci in viewer/): " + e.message);
  }
  const exe = process.env.CORRIDORSIM_CHROMIUM || "/usr/bin/chromium";
  if (!fs.existsSync(exe)) throw new Error("no chromium at " + exe + " (set CORRIDORSIM_CHROMIUM)");
  return chromium.launch({ executablePath: exe, headless: true, args: ["--no-sandbox"], timeout: 60000 });
}

/** A page that records console errors and page errors. */
async function openPage(context, url, log) {
  const page = await context.newPage();
  page.on("console", (m) => { if (m.type() === "error") log.push("console error: " + m.text()); });
  page.on("pageerror", (e) => log.push("page error: " + (e && e.message ? e.message : e)));
  page.setDefaultTimeout(20000);
  await page.goto(url, { waitUntil: "load" });
  return page;
}

async function shot(page, dir, name) {
  const file = path.join(dir, name);
  await page.screenshot({ path: file, fullPage: false });
  return file;
}

// ------------------------------------------------------------------ viewer mode
async function testViewer(opts, browser) {
  const runDir = opts.run;
  const url = pathToFileURL(path.resolve(opts.page)).href;
  const context = await browser.newContext({ viewport: { width: 1600, height: 1000 }, deviceScaleFactor: 1 });
  const log = [];
  const page = await openPage(context, url, log);
  await page.waitForFunction(() => window.corridorsimViewer && window.corridorsimViewer.ready === true, null, { timeout: 30000 });
  const pageErrors = await page.evaluate(() => window.corridorsimViewer.errors.slice());
  for (const e of pageErrors) fail("the page caught: " + e);

  // the page's own data: pipelines and stamps
  const info = await page.evaluate(() => {
    const d = JSON.parse(document.getElementById("corridorsim-data").textContent);
    const nums = (a) => (Array.isArray(a) ? a.filter((v) => typeof v === "number" && isFinite(v)) : []);
    return {
      truth: nums(d.truth && d.truth.t),
      pipelines: (d.pipelines || []).map((p) => ({ name: p.name, failed: p.failed, t: nums(p.path && p.path.t) })),
    };
  });
  const union = Array.from(new Set([].concat(info.truth, ...info.pipelines.map((p) => p.t)))).sort((a, b) => a - b);
  const stampSet = new Set(union);
  if (!check(union.length >= 2, "the page carries fewer than two stamps")) return context.close();

  const truth = readPoses(path.join(runDir, "ground_truth.tum"));
  const files = {};
  for (const p of info.pipelines) {
    if (p.failed !== null && p.failed !== undefined) continue;
    const tum = path.join(runDir, p.name + ".tum"), cov = path.join(runDir, p.name + "_cov.txt");
    if (!check(fs.existsSync(tum), `pipeline ${p.name}: no ${tum}`)) continue;
    files[p.name] = { poses: readPoses(tum), cov: fs.existsSync(cov) ? readPoses(cov) : null, kept: p.t };
    if (!files[p.name].cov) notes.push(`pipeline ${p.name}: no ${p.name}_cov.txt, its ellipses not checked`);
  }
  const names = Object.keys(files);
  fs.mkdirSync(opts.shots, { recursive: true });

  // cursor times spread over the run: stamps of the first checked pipeline when there is one
  const ref = names.length && files[names[0]].kept.length ? files[names[0]].kept : union;
  const times = [0.04, 0.27, 0.5, 0.73, 0.97].map((f) => ref[Math.min(Math.floor(f * ref.length), ref.length - 1)]);
  const states = [];
  for (let k = 0; k < times.length; k++) {
    const st = await page.evaluate((t) => { window.corridorsimViewer.setTime(t); return window.corridorsimViewer.state(); }, times[k]);
    states.push(st);
    await shot(page, opts.shots, `viewer_${k + 1}_t${times[k].toFixed(2)}.png`);
    if (!check(st && typeof st.t === "number", `setTime(${times[k]}): state() has no t`)) continue;
    check(stampSet.has(st.t), `setTime(${times[k]}): the cursor t = ${st.t} is not one of the page's stamps`);
    const want = lastStamp(union, times[k]);
    check(st.t === want, `setTime(${times[k]}): the cursor went to t = ${st.t}, not to the last stamp at or before it (${want})`);
    comparePose("truth", st.truth, truth, st.t, info.truth);
    for (const name of names) {
      const q = st.pipelines && st.pipelines[name];
      const f = comparePose(`pipeline ${name}`, q, files[name].poses, st.t, files[name].kept);
      if (f && q && files[name].cov) {
        const fc = files[name].cov[lastAtOrBefore(files[name].cov, f.t)];
        if (check(fc && Math.abs(fc.t - f.t) <= T_TOL, `pipeline ${name}: ${name}_cov.txt has no line at t = ${f.t}`)) compareEllipse(`pipeline ${name}`, q.ellipse, fc, q);
      }
    }
  }

  // every plot's cursor line sits at the cursor's time, also after the window is resized
  for (const width of [1600, 1150]) {
    await page.setViewportSize({ width: width, height: 1000 });
    await page.waitForTimeout(300);
    const lines = await page.evaluate(() => {
      const t = window.corridorsimViewer.state().t;
      return Array.from(document.querySelectorAll(".cs-plot")).filter((w) => w.querySelector(".u-over") && w.dataset.xmin !== undefined).map((w) => {
        const over = w.querySelector(".u-over"), line = over.querySelector(".cs-cursor-line");
        const xmin = Number(w.dataset.xmin), xmax = Number(w.dataset.xmax);
        return { title: w.firstChild.textContent, want: ((t - xmin) / (xmax - xmin)) * over.getBoundingClientRect().width,
          got: line && line.style.display !== "none" ? line.getBoundingClientRect().left - over.getBoundingClientRect().left : null };
      });
    });
    for (const l of lines) {
      check(l.got !== null && Math.abs(l.got - l.want) <= 2,
        `at ${width} px wide the cursor line of plot "${l.title}" is at ${l.got} px, the cursor's time at ${l.want.toFixed(1)} px`);
    }
  }
  await page.setViewportSize({ width: 1600, height: 1000 });

  // a close look at the robot (for whoever reads the screenshots): follow it, zoom in with the wheel
  await page.evaluate((t) => window.corridorsimViewer.setTime(t), times[2]);
  await page.locator("#cs-follow").check();
  const plan = await page.locator("#cs-plan").boundingBox();
  await page.mouse.move(plan.x + plan.width / 2, plan.y + plan.height / 2);
  for (let k = 0; k < 6; k++) await page.mouse.wheel(0, -300);
  await page.waitForTimeout(100);
  await shot(page, opts.shots, "viewer_zoom.png");
  await page.locator("#cs-fit").click();

  // between two stamps the cursor snaps to the earlier one
  const mid = Math.floor(union.length / 3);
  const between = (union[mid] + union[mid + 1]) / 2;
  const snapped = await page.evaluate((t) => { window.corridorsimViewer.setTime(t); return window.corridorsimViewer.state().t; }, between);
  check(snapped === union[mid], `setTime(${between}) (between two stamps) went to ${snapped}, not to ${union[mid]}`);

  // the drawn robot moves with the cursor
  const [sa, sb] = [states[1], states[3]];
  if (sa && sb && sa.truth && sb.truth) {
    check(Math.hypot(sa.truth.x - sb.truth.x, sa.truth.y - sb.truth.y) > 1e-3, `the truth pose is the same at t = ${sa.t} and t = ${sb.t}`);
    for (const name of names) {
      const a = sa.pipelines[name], b = sb.pipelines[name];
      if (a && b) check(a.x !== b.x || a.y !== b.y, `pipeline ${name}: the drawn pose is the same at t = ${sa.t} and t = ${sb.t}`);
    }
  }

  // the URL fragment follows the cursor ...
  const hashT = await page.evaluate(() => { const m = /t=([-+0-9.eE]+)/.exec(location.hash); return m ? parseFloat(m[1]) : null; });
  check(hashT === snapped, `after setTime the URL fragment is ${hashT === null ? "missing" : "#t=" + hashT}, the cursor at ${snapped}`);

  // ... and a keyboard step moves it to the next stamp
  await page.locator("#cs-plan").click({ position: { x: 5, y: 5 } });
  await page.keyboard.press("ArrowRight");
  const afterKey = await page.evaluate(() => window.corridorsimViewer.state().t);
  check(afterKey === union[mid + 1], `ArrowRight from t = ${snapped} went to ${afterKey}, not to the next stamp ${union[mid + 1]}`);

  // a click on a plot moves the cursor to that time
  const over = page.locator(".cs-plot .u-over").first();
  if (await over.count()) {
    const box = await over.boundingBox();
    const plotWrap = page.locator(".cs-plot:has(.u-over)").first();
    const got = [];
    for (const f of [0.3, 0.7]) {
      await over.click({ position: { x: box.width * f, y: box.height / 2 } });
      const st = await page.evaluate(() => window.corridorsimViewer.state());
      const xmin = Number(await plotWrap.getAttribute("data-xmin")), xmax = Number(await plotWrap.getAttribute("data-xmax"));
      got.push(st.t);
      if (Number.isFinite(xmin) && Number.isFinite(xmax) && xmax > xmin) {
        const want = xmin + f * (xmax - xmin), px = (xmax - xmin) / box.width;
        const i = union.findIndex((s) => s > want + 2 * px);
        const gap = i > 0 ? union[i] - union[i - 1] : 0;
        check(st.t <= want + 2 * px && st.t >= want - 2 * px - gap,
          `a click at ${(f * 100).toFixed(0)} % of a plot (t ~ ${want.toFixed(3)} s) put the cursor at ${st.t}`);
      }
      await shot(page, opts.shots, `viewer_plot_click_${Math.round(f * 100)}.png`);
    }
    check(got[1] > got[0], `clicks at 30 % and 70 % of a plot gave cursor times ${got[0]} and ${got[1]}`);
  } else fail("no plot on the page (.cs-plot .u-over)");

  // play moves the cursor forward
  await page.evaluate(() => window.corridorsimViewer.setTime(0));
  const t0 = await page.evaluate(() => window.corridorsimViewer.state().t);
  await page.locator("#cs-play").click();
  await page.waitForTimeout(600);
  await page.locator("#cs-play").click();
  const t1 = await page.evaluate(() => window.corridorsimViewer.state().t);
  check(t1 > t0, `play for 0.6 s did not move the cursor (t = ${t0} -> ${t1})`);

  await page.locator(".cs-lower").scrollIntoViewIfNeeded();
  await shot(page, opts.shots, "viewer_lower.png");
  const errorsEnd = await page.evaluate(() => window.corridorsimViewer.errors.slice());
  for (const e of errorsEnd.slice(pageErrors.length)) fail("the page caught: " + e);

  // the URL fragment opens the page at that moment
  const target = union[Math.floor(union.length * 0.6)];
  const ask = target + (union[Math.floor(union.length * 0.6) + 1] - target) / 3;
  const page2 = await openPage(context, url + "#t=" + ask, log);
  await page2.waitForFunction(() => window.corridorsimViewer && window.corridorsimViewer.ready === true, null, { timeout: 30000 });
  const st2 = await page2.evaluate(() => window.corridorsimViewer.state());
  check(st2 && st2.t === target, `opened with #t=${ask} the cursor is at ${st2 && st2.t}, not at ${target}`);
  await shot(page2, opts.shots, "viewer_fragment.png");
  for (const e of await page2.evaluate(() => window.corridorsimViewer.errors.slice())) fail("the page (opened with #t=) caught: " + e);

  for (const m of log) fail(m);
  await context.close();
}

// ------------------------------------------------------------------ report mode
async function testReport(opts, browser) {
  const pagePath = path.resolve(opts.page);
  const url = pathToFileURL(pagePath).href;
  const context = await browser.newContext({ viewport: { width: 1500, height: 1000 }, deviceScaleFactor: 1 });
  const log = [];
  const page = await openPage(context, url, log);
  await page.waitForFunction(() => !window.corridorsimReport || window.corridorsimReport.ready === true, null, { timeout: 30000 });
  fs.mkdirSync(opts.shots, { recursive: true });
  const caught = await page.evaluate(() => (window.corridorsimReport ? window.corridorsimReport.errors.slice() : []));
  for (const e of caught) fail("the page caught: " + e);
  await shot(page, opts.shots, "report.png");
  await page.screenshot({ path: path.join(opts.shots, "report_full.png"), fullPage: true });

  // every relative link is a file next to the page
  const hrefs = await page.$$eval("a[href]", (as) => as.map((a) => a.getAttribute("href")));
  let checked = 0;
  for (const h of hrefs) {
    if (/^(#|https?:|mailto:|data:|javascript:)/i.test(h)) continue;
    if (/^(file:|\/)/i.test(h) || /^[a-z]:[\\/]/i.test(h)) { fail(`link ${h} is not relative`); continue; }
    const rel = decodeURIComponent(h.split(/[?#]/)[0]);
    const target = path.resolve(path.dirname(pagePath), rel);
    checked++;
    check(fs.existsSync(target) && fs.statSync(target).isFile(), `link ${h} points to ${target}, which is not a file`);
  }
  notes.push(`${checked} relative links checked`);

  // a click on a sortable header sorts the runs table
  const table = page.locator("table.cs-runs").first();
  if (await table.count()) {
    const headers = table.locator("thead th.cs-sortable[data-type=num]");
    const n = await headers.count();
    if (check(n > 0, "the runs table has no numeric sortable header")) {
      const keys = () => table.locator("tbody tr").evaluateAll((rows) => rows.map((r) => r.dataset.key || r.textContent));
      const before = await keys();
      let sortedOk = false, changed = false, which = "";
      for (let h = n - 1; h >= 0 && !(sortedOk && changed); h--) {  // the last numeric column: a metric
        const th = headers.nth(h);
        which = (await th.textContent()).trim();
        const col = await th.evaluate((e) => Array.from(e.parentElement.children).indexOf(e));
        for (let click = 0; click < 2 && !(sortedOk && changed); click++) {
          await th.click();
          const vals = await table.locator("tbody tr").evaluateAll((rows, c) => rows.map((r) => {
            const td = r.children[c];
            const v = td && td.dataset.v !== undefined ? td.dataset.v : td ? td.textContent : "";
            const x = parseFloat(v);
            return Number.isFinite(x) ? x : null;
          }), col);
          const after = await keys();
          check(after.length === before.length && [...after].sort().join("\n") === [...before].sort().join("\n"),
            `sorting by "${which}" changed the set of rows`);
          const present = vals.filter((v) => v !== null);
          const firstNull = vals.indexOf(null);
          const nullsLast = firstNull === -1 || vals.slice(firstNull).every((v) => v === null);
          const asc = present.every((v, i) => i === 0 || present[i - 1] <= v);
          const desc = present.every((v, i) => i === 0 || present[i - 1] >= v);
          sortedOk = nullsLast && (asc || desc);
          changed = after.join("\n") !== before.join("\n");
          check(nullsLast && (asc || desc), `after a click on "${which}" the column is not sorted with empty cells last: ${vals.slice(0, 12).join(", ")} ...`);
        }
      }
      check(changed, `clicking the numeric headers of the runs table never reordered its rows (last: "${which}")`);
      await table.scrollIntoViewIfNeeded();
      await shot(page, opts.shots, "report_sorted.png");
    }
  } else fail("no runs table (table.cs-runs) on the page");

  const caughtEnd = await page.evaluate(() => (window.corridorsimReport ? window.corridorsimReport.errors.slice() : []));
  for (const e of caughtEnd.slice(caught.length)) fail("the page caught: " + e);
  for (const m of log) fail(m);
  await context.close();
}

// ------------------------------------------------------------------ main
async function main() {
  const opts = parseArgs(process.argv.slice(2));
  const timer = setTimeout(() => {
    console.error(`browser_test: FAIL: timed out after ${TIMEOUT_S} s`);
    for (const f of failures) console.error("browser_test: FAIL: " + f);
    process.exit(1);
  }, TIMEOUT_S * 1000);
  let browser = null;
  try {
    browser = await launch();
    if (opts.mode === "viewer") await testViewer(opts, browser);
    else if (opts.mode === "sensors") await testSensors(opts, browser, { fail, check, notes, openPage, shot });
    else await testReport(opts, browser);
  } catch (e) {
    fail("the test stopped: " + (e && e.stack ? e.stack.split("\n").slice(0, 3).join(" | ") : e));
  } finally {
    if (browser) await browser.close().catch(() => {});
    clearTimeout(timer);
  }
  for (const n of notes) console.log("browser_test: note: " + n);
  if (failures.length) {
    for (const f of failures) console.error("browser_test: FAIL: " + f);
    process.exit(1);
  }
  console.log(`browser_test: ${opts.mode}: PASS (screenshots in ${opts.shots})`);
  process.exit(0);
}

main();
