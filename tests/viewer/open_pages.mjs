#!/usr/bin/env node
// Opens pages that make_viewer.py / make_report.py wrote in headless chromium and checks that
// each loads: its API says ready, nothing is caught or logged as an error, and the header shows
// the text it was given (tests/harness/cli_outside_text_test.py: `<!--<script>` in every string
// that reaches a page).
//
//   node tests/viewer/open_pages.mjs PAGE EXPECTED_TITLE_TEXT [PAGE EXPECTED_TITLE_TEXT ...]
//
// Exit 0: every page passed; 1: a failure (one line each). A global timeout (90 s) fails.

import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const VIEWER = path.join(HERE, "..", "..", "viewer");
const failures = [];

async function main() {
  const args = process.argv.slice(2);
  if (args.length === 0 || args.length % 2 !== 0) {
    console.error("usage: open_pages.mjs PAGE EXPECTED_TITLE_TEXT [...]");
    process.exit(2);
  }
  const timer = setTimeout(() => { console.error("open_pages: FAIL: timed out after 90 s"); process.exit(1); }, 90000);
  const require = createRequire(path.join(VIEWER, "package.json"));
  const { chromium } = require("playwright-core");
  const browser = await chromium.launch({ executablePath: process.env.CORRIDORSIM_CHROMIUM || "/usr/bin/chromium", headless: true, args: ["--no-sandbox"] });
  try {
    for (let i = 0; i < args.length; i += 2) {
      const [file, expected] = [args[i], args[i + 1]];
      const page = await browser.newPage();
      const log = [];
      page.on("console", (m) => { if (m.type() === "error") log.push("console error: " + m.text()); });
      page.on("pageerror", (e) => log.push("page error: " + e.message));
      try {
        await page.goto(pathToFileURL(file).href);
        const api = await page.waitForFunction(() => (window.corridorsimViewer && window.corridorsimViewer.ready === true && "corridorsimViewer") ||
                                                      (window.corridorsimReport && window.corridorsimReport.ready === true && "corridorsimReport"), null, { timeout: 30000 });
        const name = await api.jsonValue();
        for (const e of await page.evaluate((a) => window[a].errors.slice(), name)) failures.push(`${file}: the page caught: ${e}`);
        const shown = await page.evaluate(() => document.getElementById("cs-title").textContent + " | " + document.title);
        if (!shown.includes(expected)) failures.push(`${file}: the header shows ${JSON.stringify(shown)}, not ${JSON.stringify(expected)}`);
        else console.log(`open_pages: ${path.basename(file)}: ready, header ${JSON.stringify(shown)}`);
      } catch (e) {
        failures.push(`${file}: ${e.message.split("\n")[0]}`);
      }
      for (const m of log) failures.push(`${file}: ${m}`);
      await page.close();
    }
  } finally {
    await browser.close();
    clearTimeout(timer);
  }
  if (failures.length) { for (const f of failures) console.error("open_pages: FAIL: " + f); process.exit(1); }
}

main().catch((e) => { console.error("open_pages: FAIL: " + (e && e.stack ? e.stack : e)); process.exit(1); });
