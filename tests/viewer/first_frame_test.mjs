#!/usr/bin/env node
// viewer.html draws its plan in the first frame it paints (docs/viewer.md): what a headless
// `chromium --headless=new --screenshot` of the page shows, with no click and no wait after load.
//
//   node tests/viewer/first_frame_test.mjs --page RUN_DIR/viewer.html [--page ...]
//
// The plan's canvas is read back (no screenshot: taking one makes the browser draw frames of its
// own) at the moments the browser may paint it before anything else runs: right after every call
// of the page's ResizeObserver callbacks for the plan (they run between layout and paint; the
// first comes with the first frame) and at the load event. Each reading must show the drawn plan:
// its opaque background and at least MIN_DRAWN pixels of something else (walls, grid, paths,
// poses). A canvas cleared by a resize and redrawn only in a later animation frame reads as
// transparent there. Drives Debian's chromium (or $CORRIDORSIM_CHROMIUM) through playwright-core
// from viewer/node_modules. Exit 0: pass; 1: fail (one line per failure); 2: bad command line.

import { createRequire } from "node:module";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const TIMEOUT_S = Number(process.env.CORRIDORSIM_BROWSER_TEST_TIMEOUT_S || 120);
const MIN_OPAQUE = 0.9;   // the share of the canvas the drawn background covers
const MIN_DRAWN = 200;    // pixels, other than the background, of a drawn plan
// Window sizes the screenshots used and the test's own (px).
const SIZES = [[1600, 1000], [1280, 800], [1000, 900]];

const failures = [];
const fail = (m) => failures.push(m);

function usage(msg) {
  console.error("first_frame_test: " + msg + "\nusage: first_frame_test.mjs --page RUN_DIR/viewer.html [--page ...]");
  process.exit(2);
}

// Runs in the page before its scripts: wraps ResizeObserver so that the plan canvas is read right
// after the page's callback for it, and reads it at the load event. Readings go to
// window.__firstFrame as {when, w, h, opaque, drawn}.
function instrument() {
  const readings = (window.__firstFrame = []);
  const BACKGROUND = [0x10, 0x11, 0x15];
  function read(when) {
    const c = document.getElementById("cs-plan");
    if (!c) { readings.push({ when, missing: true }); return; }
    const w = c.width, h = c.height;
    if (!w || !h) { readings.push({ when, w, h, opaque: 0, drawn: 0 }); return; }
    const px = c.getContext("2d").getImageData(0, 0, w, h).data;
    let opaque = 0, drawn = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i + 3] === 0) continue;
      opaque++;
      if (Math.abs(px[i] - BACKGROUND[0]) + Math.abs(px[i + 1] - BACKGROUND[1]) + Math.abs(px[i + 2] - BACKGROUND[2]) > 12) drawn++;
    }
    readings.push({ when, w, h, opaque: opaque / (w * h), drawn });
  }
  const Original = window.ResizeObserver;
  window.ResizeObserver = class extends Original {
    constructor(callback) {
      super((entries, observer) => {
        callback(entries, observer);
        if (entries.some((e) => e.target && e.target.id === "cs-plan-wrap")) read("after the plan's resize callback");
      });
    }
  };
  window.addEventListener("load", () => read("at the load event"));
}

async function checkPage(browser, page, [width, height]) {
  const context = await browser.newContext({ viewport: { width, height }, deviceScaleFactor: 1 });
  const tab = await context.newPage();
  const log = [];
  tab.on("pageerror", (e) => log.push("page error: " + (e && e.message ? e.message : e)));
  await tab.addInitScript(instrument);
  await tab.goto(pathToFileURL(path.resolve(page)).href, { waitUntil: "load" });
  await tab.waitForFunction(() => window.corridorsimViewer && window.corridorsimViewer.ready === true, null, { timeout: 30000 });
  // The first ResizeObserver delivery may come after load: wait for it, not for anything drawn.
  await tab.waitForFunction(() => window.__firstFrame.some((r) => r.when !== "at the load event"), null, { timeout: 30000 });
  const readings = await tab.evaluate(() => window.__firstFrame.slice());
  const where = `${page} at ${width}x${height}`;
  for (const r of readings) {
    if (r.missing) { fail(`${where}: no #cs-plan canvas ${r.when}`); continue; }
    if (r.opaque < MIN_OPAQUE || r.drawn < MIN_DRAWN) {
      fail(`${where}: the plan is not drawn ${r.when}: ${(100 * r.opaque).toFixed(1)} % of its ${r.w}x${r.h} px opaque ` +
        `(drawn background: >= ${100 * MIN_OPAQUE} %), ${r.drawn} px besides the background (>= ${MIN_DRAWN})`);
    }
  }
  for (const e of await tab.evaluate(() => window.corridorsimViewer.errors.slice())) fail(`${where}: the page caught: ${e}`);
  for (const m of log) fail(`${where}: ${m}`);
  await context.close();
  return readings.length;
}

async function main() {
  const argv = process.argv.slice(2), pages = [];
  for (let i = 0; i < argv.length; i++) {
    if (argv[i] !== "--page" || i + 1 >= argv.length) usage("unexpected argument " + argv[i]);
    pages.push(argv[++i]);
  }
  if (!pages.length) usage("--page is required");
  for (const p of pages) if (!fs.existsSync(p)) usage("no such page: " + p);
  const timer = setTimeout(() => {
    console.error(`first_frame_test: FAIL: timed out after ${TIMEOUT_S} s`);
    for (const f of failures) console.error("first_frame_test: FAIL: " + f);
    process.exit(1);
  }, TIMEOUT_S * 1000);
  const require = createRequire(path.join(HERE, "..", "..", "viewer", "package.json"));
  const { chromium } = require("playwright-core");
  const exe = process.env.CORRIDORSIM_CHROMIUM || "/usr/bin/chromium";
  let browser = null, readings = 0;
  try {
    browser = await chromium.launch({ executablePath: exe, headless: true, args: ["--no-sandbox"], timeout: 60000 });
    for (const p of pages) for (const size of SIZES) readings += await checkPage(browser, p, size);
  } catch (e) {
    fail("the test stopped: " + (e && e.stack ? e.stack.split("\n").slice(0, 3).join(" | ") : e));
  } finally {
    if (browser) await browser.close().catch(() => {});
    clearTimeout(timer);
  }
  if (failures.length) {
    for (const f of failures) console.error("first_frame_test: FAIL: " + f);
    process.exit(1);
  }
  console.log(`first_frame_test: PASS (${pages.length} page(s), ${SIZES.length} window sizes, ${readings} readings of the plan)`);
  process.exit(0);
}

main();
