/* What the run viewer (viewer.js) and the study report (report.js) share (docs/viewer.md): the
 * error capture behind each page's test hook (it fills the enclosing page's `api.errors`), guard,
 * the small DOM and number helpers ($, isObj, num, arr, str, DEG, el, fmt), and the parts both
 * pages have: the page's data (pageData), the pipelines' colours (pipelineColors), the header
 * (pageHeader), the expectations' table with the verdict badge (expectationsTable) and the start
 * (startParts, whenReady). Not a script of its own: scripts/pages.py inlines it into each page's
 * closure where the page's script says CORRIDORSIM_INCLUDE page.js; this opening comment stays out
 * of the pages. */
  function report(err, where) {
    const msg = (where ? where + ": " : "") +
      (err && err.stack ? String(err.stack).split("\n").slice(0, 3).join(" | ") : String(err));
    api.errors.push(msg);
    const box = document.getElementById("cs-errors");
    if (box) { box.hidden = false; box.textContent = "The page caught errors:\n" + api.errors.join("\n"); }
  }
  window.addEventListener("error", (e) => {
    // Chromium's notice that a resize callback changed the layout again: benign, not an error.
    if (!e.error && /^ResizeObserver loop/.test(String(e.message))) return;
    report(e.error || e.message, "window.onerror");
  });
  window.addEventListener("unhandledrejection", (e) => report(e.reason, "unhandled rejection"));
  /** fn wrapped so that an exception is recorded instead of escaping. */
  function guard(fn, where) {
    return function () {
      try { return fn.apply(this, arguments); } catch (e) { report(e, where); return undefined; }
    };
  }

  // ---------------------------------------------------------------- small helpers
  const $ = (id) => document.getElementById(id);
  const isObj = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
  const num = (v) => (typeof v === "number" && isFinite(v) ? v : NaN);
  const arr = (v) => (Array.isArray(v) ? v : []);
  const str = (v, dflt) => (v === null || v === undefined ? (dflt === undefined ? "" : dflt) : String(v));
  const DEG = 180 / Math.PI;

  function el(tag, attrs, children) {
    const e = document.createElement(tag);
    if (attrs) for (const k in attrs) {
      if (k === "text") e.textContent = attrs[k];
      else if (k === "cls") e.className = attrs[k];
      else if (k.startsWith("on")) e.addEventListener(k.slice(2), guard(attrs[k], tag + " " + k));
      else e.setAttribute(k, attrs[k]);
    }
    for (const c of children || []) if (c !== null && c !== undefined) e.append(c);
    return e;
  }

  /** A number for a table: 4 significant digits, integers as they are. */
  function fmt(v) {
    if (typeof v !== "number") return v === null || v === undefined ? "–" : String(v);
    if (!isFinite(v)) return String(v);
    if (Number.isInteger(v)) return String(v);
    const a = Math.abs(v);
    if (a !== 0 && (a < 1e-3 || a >= 1e6)) return v.toExponential(3);
    return String(Number(v.toPrecision(4)));
  }

  // ---------------------------------------------------------------- what both pages have
  /** The page's data: the JSON in <script id="corridorsim-data"> ({} when there is none, it was
   * never filled in, it does not parse (recorded) or it is not an object). */
  function pageData() {
    let raw = {};
    const node = $("corridorsim-data");
    const text = node ? node.textContent.trim() : "";
    if (text && text !== "CORRIDORSIM_" + "DATA_JSON") {
      try { raw = JSON.parse(text); } catch (e) { report(e, "reading the page's data"); }
    }
    return isObj(raw) ? raw : {};
  }

  const PALETTE = ["#6ea8ff", "#ff9f43", "#2ed3b7", "#e86bd8", "#b5e853", "#ff6b6b", "#c9a0ff", "#ffd166"];
  /** The pipelines' colours, asked for in the page's order: odometry grey, the others the palette's in turn. */
  function pipelineColors() {
    let next = 0;
    return (name) => (name === "odometry" ? "#a7adb8" : PALETTE[next++ % PALETTE.length]);
  }

  /** The header's title (also the document's) and the line under it: `bits` joined, empty ones left out. */
  function pageHeader(title, bits) {
    document.title = title || document.title;
    $("cs-title").textContent = title;
    $("cs-sub").textContent = bits.filter(Boolean).join(" · ");
  }

  /** `table` (returned) with a row per expectation (PASS or FAIL, the text, the value measured),
   * and the verdict badge (#cs-verdict) saying whether all pass. */
  function expectationsTable(table, list) {
    table.append(el("tr", {}, [el("th"), el("th", { text: "expectation" }), el("th", { cls: "cs-num", text: "measured" })]));
    let pass = 0;
    for (const x of list) {
      const ok = x.passed === true;
      if (ok) pass++;
      table.append(el("tr", {}, [el("td", {}, [el("span", { cls: "cs-badge " + (ok ? "cs-pass" : "cs-fail"), text: ok ? "PASS" : "FAIL" })]),
        el("td", { text: str(x.text) }), el("td", { cls: "cs-num", text: fmt(x.measured) })]));
    }
    const v = $("cs-verdict");
    v.textContent = pass === list.length ? "expectations: all " + pass + " pass" : "expectations: " + (list.length - pass) + " of " + list.length + " FAIL";
    v.className = "cs-badge " + (pass === list.length ? "cs-pass" : "cs-fail");
    return table;
  }

  /** Each [name, f] of `parts` called on its own: one that fails is recorded and the others still work. */
  function startParts(parts) {
    for (const [name, f] of parts) {
      try { f(); } catch (e) { report(e, name); }
    }
  }

  /** start() once the document is parsed (now, when it already is), an exception recorded. */
  function whenReady(start) {
    if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", guard(start, "start"));
    else guard(start, "start")();
  }
