/* The run viewer's tables (docs/viewer.md): the events (click one to move the cursor there), the
 * expectations with the verdict badge, and every pipeline's metrics. Part of viewer.js's closure
 * (scripts/pages.py inlines it where viewer.js says CORRIDORSIM_INCLUDE viewer_tables.js); this
 * opening comment stays out of the page. */
  // ---------------------------------------------------------------- events, expectations, metrics
  function eventColor(type) {
    const t = type.toLowerCase();
    if (t.includes("collision")) return "#f0524f";
    if (t.includes("slip")) return "#e8a33d";
    if (t.includes("drop")) return "#b48cff";
    if (t.includes("fail")) return "#ff4fd8";
    return "#8b919c";
  }

  let eventRows = [], eventCurrent = -1;

  function initEvents() {
    const marks = $("cs-marks"), span = T1() - T0();
    // one mark per event; more than a mark per pixel would only slow the page, so cap them
    const seen = new Set();
    for (const e of D.events) {
      const f = span > 0 ? (e.t - T0()) / span : 0;
      const key = Math.round(f * 1500) + e.type;
      if (seen.has(key)) continue;
      seen.add(key);
      const m = el("button", { cls: "cs-mark", type: "button", title: e.t.toFixed(3) + " s · " + e.type + (e.text ? ": " + e.text : ""),
        onclick: () => { stop(); setIndex(Math.max(lastAtOrBefore(stamps, e.t), 0), { url: "now" }); } });
      m.style.left = (Math.min(Math.max(f, 0), 1) * 100).toFixed(3) + "%";
      m.style.background = eventColor(e.type);
      m.dataset.t = e.t;
      marks.append(m);
    }
    const table = $("cs-events");
    if (!D.events.length) { table.replaceWith(el("div", { cls: "cs-empty", text: "No events." })); return; }
    const counts = {};
    for (const e of D.events) counts[e.type] = (counts[e.type] || 0) + 1;
    $("cs-events-hint").textContent = Object.keys(counts).map((k) => counts[k] + " " + k).join(" · ");
    table.append(el("tr", {}, [el("th", { text: "t [s]" }), el("th", { text: "type" }), el("th", { text: "what" })]));
    const LIMIT = 3000;
    D.events.slice(0, LIMIT).forEach((e) => {
      const tag = el("span", { cls: "cs-type", text: e.type });
      tag.style.background = eventColor(e.type);
      const row = el("tr", { cls: "cs-clickable", onclick: () => { stop(); setIndex(Math.max(lastAtOrBefore(stamps, e.t), 0), { url: "now" }); } },
        [el("td", { text: e.t.toFixed(3) }), el("td", {}, [tag]), el("td", { text: e.text })]);
      eventRows.push(row);
      table.append(row);
    });
    if (D.events.length > LIMIT) table.append(el("tr", {}, [el("td", { colspan: "3", cls: "cs-empty", text: (D.events.length - LIMIT) + " more events not listed" })]));
    const times = Float64Array.from(D.events.slice(0, LIMIT), (e) => e.t);
    listeners.push((s) => {   // highlight the last event at or before the cursor
      const i = lastAtOrBefore(times, s.t);
      if (i === eventCurrent) return;
      if (eventRows[eventCurrent]) eventRows[eventCurrent].classList.remove("cs-current");
      if (eventRows[i]) eventRows[i].classList.add("cs-current");
      eventCurrent = i;
    });
  }

  function initExpectations() {
    const table = $("cs-expectations"), list = D.expectations;
    if (!list.length) { table.replaceWith(el("div", { cls: "cs-empty", text: "This run states no expectations." })); return; }
    expectationsTable(table, list);
  }

  const MAIN_METRICS = ["ate_rmse_m", "ate_aligned_rmse_m", "rpe_1m_trans_rmse_m", "final_position_error_m", "nees_mean", "nees_in_band_fraction"];

  /** Nested metrics as dotted keys: {"a": {"b": 1}} -> {"a.b": 1}. */
  function flatten(obj, prefix, out) {
    for (const k of Object.keys(obj)) {
      const v = obj[k], key = prefix ? prefix + "." + k : k;
      if (isObj(v)) flatten(v, key, out); else out[key] = v;
    }
    return out;
  }

  function initMetrics() {
    const box = $("cs-metrics"), P = D.pipelines;
    if (!P.length) { box.append(el("div", { cls: "cs-empty", text: "No pipelines." })); return; }
    const flat = P.map((p) => flatten(p.metrics, "", {}));
    const head = () => el("tr", {}, [el("th", { text: "metric" })].concat(P.map((p) => {
      const th = el("th", { cls: "cs-num" }, [el("span", { cls: "cs-swatch", style: "background:" + p.color }), p.name]);
      if (p.failed) th.title = "failed: " + p.failed;
      return th;
    })));
    const row = (key, bestLow) => {
      const vals = flat.map((f) => f[key]);
      const nums = vals.filter((v) => typeof v === "number" && isFinite(v));
      const best = bestLow && nums.length > 1 ? Math.min.apply(null, nums) : null;
      return el("tr", {}, [el("td", { text: key })].concat(vals.map((v) => {
        const td = el("td", { cls: "cs-num", text: Array.isArray(v) ? JSON.stringify(v) : fmt(v) });
        if (best !== null && v === best) td.style.fontWeight = "700";
        return td;
      })));
    };
    const main = el("table", { cls: "cs-table" }, [head()].concat(MAIN_METRICS.map((k) => row(k, /_m$/.test(k)))));
    const failedRow = P.some((p) => p.failed) ? el("tr", {}, [el("td", { text: "failed" })].concat(P.map((p) =>
      el("td", { cls: "cs-num" }, [p.failed ? el("span", { cls: "cs-badge cs-fail", text: "failed", title: p.failed }) : "–"])))) : null;
    if (failedRow) main.append(failedRow);
    box.append(main);
    const rest = [];
    for (const f of flat) for (const k of Object.keys(f)) if (!MAIN_METRICS.includes(k) && !rest.includes(k)) rest.push(k);
    if (rest.length) {
      box.append(el("details", {}, [el("summary", { text: "all metrics (" + rest.length + " more)" }),
        el("table", { cls: "cs-table" }, [head()].concat(rest.map((k) => row(k, false))))]));
    }
  }

