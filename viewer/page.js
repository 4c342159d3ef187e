/* What the run viewer (viewer.js) and the study report (report.js) share (docs/viewer.md): the
 * error capture behind each page's test hook (it fills the enclosing page's `api.errors`), guard,
 * and the small DOM and number helpers ($, isObj, num, arr, str, DEG, el, fmt). Not a script of
 * its own: scripts/pages.py inlines it into each page's closure where the page's script says
 * CORRIDORSIM_INCLUDE page.js; this opening comment stays out of the pages. */
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
