#!/usr/bin/python3
"""Text from outside never costs a result or changes a file's structure (docs/frames.md, "Text
from outside"; docs/ci.md; docs/viewer.md):

- a run whose external program fails printing Latin-1 (`error: caf\\xe9`) and whose plugin throws a
  message ending in a Latin-1 byte and `<!--<script>` still writes its run folder: exit 5, the
  healthy pipeline scored, every JSON file strict UTF-8 with U+FFFD for the bad bytes, every
  number in events.json and timing.json rounded, viewer.html's data free of `<`;
- `corridorsim test --junit` of that scenario and of one named
  `x]] [[ATTACHMENT|secrets.txt]] [[y.yaml`: the healthy pipeline's expectation reported, the
  failed pipeline's with its exception text, exactly one attachment per case, each an existing
  page under --out;
- a scenario path and --out that are not UTF-8 work (exit 0, provenance.json valid);
- `evaluate` of an estimate whose file name is not UTF-8 works (evaluation.json valid);
- `<!--<script>` in a scenario's name, a landmark label, a failure reason and a study folder's
  name: the pages' embedded JSON holds no `<`, and reads back as the original text.

With NODE given, the pages are also opened in headless chromium (tests/viewer/open_pages.mjs):
each loads without an error and its header shows the hostile text.

usage: cli_outside_text_test.py CORRIDORSIM PLUGIN_DIR SOURCE_DIR WORK_DIR [NODE]
"""
import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

FAILURES = []
HOSTILE = "<!--<script>"
PAGES = []  # (page, the text its header must show) for the browser


def fail(message):
    FAILURES.append(message)
    print("FAIL: " + message, flush=True)


def run(args, cwd=None):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd, timeout=300)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def scenario_text(name, pipelines, expectations, plugin=None):
    """A short scenario without cameras (a second of simulation costs little)."""
    return ("name: %s\nseed: 1\nduration_s: 8\n" % json.dumps(name) +
            ("plugins: [%s]\n" % json.dumps(plugin) if plugin else "") +
            "world:\n  layout: straight\n  length_m: 12.0\n  doors: {count: 2}\n"
            "  plates: {count: 2}\n"
            "path:\n  kind: round_trip\n  speed_mps: 0.5\n"
            "sensors:\n  front: {enabled: false}\n  lateral: {enabled: false}\n"
            "  upward: {enabled: false}\n"
            "pipelines:\n" + pipelines +
            "expectations: [%s]\n" % ", ".join(expectations))


def strict_json(path):
    """The file parsed as strict UTF-8 JSON (a byte that is not UTF-8 raises)."""
    with open(path, "rb") as f:
        return json.loads(f.read().decode("utf-8"))


def unrounded(value, where=""):
    """The numbers of a JSON value that are not a multiple of 1e-12 in their shortest form
    (30.000000000000004 is not; every step of common/io/stable_json.h is)."""
    out = []
    if isinstance(value, float):
        if float("%.12f" % value) != value and abs(value) < 1e6:
            out.append("%s = %r" % (where, value))
    elif isinstance(value, dict):
        for k, v in value.items():
            out += unrounded(v, "%s.%s" % (where, k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            out += unrounded(v, "%s[%d]" % (where, i))
    return out


def check_rounded(folder):
    """Every number of every JSON file of `folder` (not its subfolders) is rounded."""
    for name in sorted(os.listdir(folder)):
        if name.endswith(b".json" if isinstance(name, bytes) else ".json"):
            bad = unrounded(strict_json(os.path.join(folder, name)))
            if bad:
                fail("%s: unrounded numbers: %s" % (os.path.join(folder, name), bad[:5]))


def page_data(page_path):
    """The JSON of a page's <script id="corridorsim-data">, checked to hold no `<`."""
    with open(page_path, "rb") as f:
        page = f.read().decode("utf-8")
    m = re.search(r'<script id="corridorsim-data" type="application/json">(.*?)</script>', page,
                  re.S)
    if not m:
        fail("%s: no data element" % page_path)
        return {}
    if "<" in m.group(1):
        at = m.group(1).index("<")
        fail("%s: the embedded JSON holds '<': ...%s..." % (page_path, m.group(1)[at - 60:at + 20]))
    if "<!--" in page or page.count("</script>") != 3:
        fail("%s: %d '<!--' and %d </script> (expected none and 3)" %
             (page_path, page.count("<!--"), page.count("</script>")))
    return json.loads(m.group(1))


def check_failed_pipelines(binary, echo, work):
    """One external program failing in Latin-1, one plugin throwing Latin-1 and markup."""
    program = os.path.join(work, "latin1_program.py")
    misbehave = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "external",
                             "misbehave.py")
    with open(program, "w") as f:
        f.write("import os, sys\n"
                "sys.stderr.buffer.write(b'error: caf\\xe9 " + HOSTILE + "\\n')\n"
                "sys.stderr.flush()\n"
                "os.execv(sys.executable, [sys.executable, %r, 'exit'])\n" % misbehave)
    path = os.path.join(work, "latin1.yaml")
    with open(path, "w") as f:
        f.write(scenario_text(
            HOSTILE + " caf\u00e9",
            "  odometry: {}\n"
            "  mine:\n    type: external\n    command: [/usr/bin/python3, %s]\n" % program +
            "  echo: {type: test_echo, throw_after_s: 3, latin1_message: true}\n",
            ["odometry.ate_rmse_m < 5", "echo.ate_rmse_m < 5"], plugin=echo))
    out_dir = os.path.join(work, "latin1_run")
    rc, out, err = run([binary, "run", path, "--out", out_dir, "--no-plots"])
    if rc != 5:
        fail("the Latin-1 run: exit %d, expected 5 (a pipeline failed)\n%s\n%s" %
             (rc, out[-1500:], err[-1500:]))
        return path
    for name in sorted(os.listdir(out_dir)):
        if name.endswith(".json"):
            try:
                strict_json(os.path.join(out_dir, name))
            except ValueError as e:
                fail("%s is not UTF-8 JSON: %s" % (name, e))
    metrics = strict_json(os.path.join(out_dir, "metrics.json"))["pipelines"]
    if "ate_rmse_m" not in metrics.get("odometry", {}):
        fail("the healthy pipeline was not scored: %s" % metrics.get("odometry"))
    for name in ("mine", "echo"):
        if metrics.get(name, {}).get("health", {}).get("failed") != 1:
            fail("metrics.json %s: %s" % (name, metrics.get(name)))
    events = strict_json(os.path.join(out_dir, "events.json"))
    reasons = {e["pipeline"]: e["reason"] for e in events["events"]
               if e.get("type") == "pipeline_failed"}
    if "the wheels went out of sync (caf\ufffd " + HOSTILE + ")" not in reasons.get("echo", ""):
        fail("events.json: the plugin's reason %r" % reasons.get("echo"))
    if "caf\ufffd " + HOSTILE not in reasons.get("mine", ""):
        fail("events.json: the program's reason %r" % reasons.get("mine"))
    check_rounded(out_dir)
    data = page_data(os.path.join(out_dir, "viewer.html"))
    if data.get("scenario") != HOSTILE + " caf\u00e9":
        fail("viewer.html: the scenario's name reads back as %r" % data.get("scenario"))
    failed = {p["name"]: p.get("failed") for p in data.get("pipelines", [])}
    if HOSTILE not in str(failed.get("echo")):
        fail("viewer.html: the failure reason reads back as %r" % failed.get("echo"))
    PAGES.append((os.path.join(out_dir, "viewer.html"), HOSTILE + " caf\u00e9 seed 1"))
    print("ok: a run with Latin-1 failures: exit 5, every JSON file UTF-8 and rounded, "
          "viewer.html's data free of '<'", flush=True)
    return path


def check_landmark_label(source, work):
    """A landmark label reaches viewer.html as text."""
    out_dir = os.path.join(work, "latin1_run")
    if not os.path.isdir(out_dir):
        return
    with open(os.path.join(out_dir, "odometry_landmarks.json"), "w") as f:
        json.dump([{"id": 3, "type": "door_plate", "status": "converged", "label": HOSTILE,
                    "position_in_world": [1.0, 1.2, 1.5],
                    "covariance": [[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01]]}], f)
    page = os.path.join(work, "label_viewer.html")
    rc, out, err = run(["/usr/bin/python3", os.path.join(source, "scripts", "make_viewer.py"),
                        out_dir, "--out", page])
    if rc != 0:
        fail("make_viewer.py with a hostile label: exit %d\n%s" % (rc, err[-1500:]))
        return
    data = page_data(page)
    labels = [row for p in data.get("pipelines", []) if p["name"] == "odometry"
              for row in [p.get("landmarks")] if row]
    if HOSTILE not in json.dumps(labels, ensure_ascii=False):
        fail("viewer.html: the landmark label is not in the page's data: %s" % labels)
    else:
        PAGES.append((page, HOSTILE))
        print("ok: a landmark label '%s' is text in viewer.html" % HOSTILE, flush=True)


def check_junit(binary, work, latin1_path, source):
    """`test --junit`: every case reported, one attachment per case, nothing from a name."""
    injected = os.path.join(work, "x]] [[ATTACHMENT|secrets.txt]] [[y.yaml")
    with open(injected, "w") as f:
        f.write(scenario_text("injected", "  odometry: {}\n", ["odometry.ate_rmse_m < 5"]))
    with open(os.path.join(work, "secrets.txt"), "w") as f:
        f.write("not to be attached\n")
    junit = os.path.join(work, "junit.xml")
    rc, out, err = run([binary, "test", latin1_path, injected, "--out",
                        os.path.join(work, "suite"), "--junit", junit], cwd=work)
    if rc != 1 or not os.path.isfile(junit):
        fail("test --junit: exit %d (expected 1: a pipeline failed), report %s\n%s" %
             (rc, os.path.isfile(junit), err[-1500:]))
        return
    with open(junit, "rb") as f:
        data = f.read()
    root = ET.fromstring(data.decode("utf-8"))
    cases = list(root.iter("testcase"))
    by_name = {c.get("name"): c for c in cases}
    healthy = by_name.get("odometry.ate_rmse_m < 5")
    if healthy is None or healthy.find("failure") is not None or healthy.find("error") is not None:
        fail("junit.xml: the healthy pipeline's expectation: %s" % sorted(by_name))
    echo = by_name.get("echo.ate_rmse_m < 5")
    failure = echo.find("failure") if echo is not None else None
    if failure is None or "the wheels went out of sync (caf\ufffd " + HOSTILE + ")" not in \
            failure.get("message", ""):
        fail("junit.xml: the failed pipeline's expectation lacks its exception text: %s" %
             (failure.attrib if failure is not None else None))
    error = by_name.get("pipeline failed")
    error = error.find("error") if error is not None else None
    if error is None or "'echo' failed at t = " not in error.get("message", "") or \
            "caf\ufffd" not in error.get("message", ""):
        fail("junit.xml: the 'pipeline failed' case's message: %s" %
             (error.attrib if error is not None else None))
    # Exactly one attachment per case (CI systems read them from a case's system-out and
    # system-err), an existing page or log under --out; none is secrets.txt.
    markers = sum((e.text or "").count("[[ATTACHMENT|") for e in root.iter()
                  if e.tag in ("system-out", "system-err"))
    if markers != len(cases):
        fail("junit.xml: %d attachment markers for %d cases" % (markers, len(cases)))
    suite_dir = os.path.join(work, "suite")
    for case in cases:
        text = case.find("system-out").text if case.find("system-out") is not None else ""
        m = re.fullmatch(r"\[\[ATTACHMENT\|([^\[\]|]+)\]\]", text or "")
        if not m or not m.group(1).startswith(suite_dir + os.sep) or \
                not os.path.exists(m.group(1)):
            fail("junit.xml: case %r attaches %r" % (case.get("name"), text))
        for attachment in re.findall(r"\[\[ATTACHMENT\|(.+?)\]\]", text or ""):
            if os.path.basename(attachment) == "secrets.txt":
                fail("junit.xml: a name attached %r" % attachment)
    suites = [s.get("name") for s in root.iter("testsuite")]
    if "x]] [[ATTACHMENT|secrets.txt]] [[y" not in suites:
        fail("junit.xml: the suite names %s" % suites)
    print("ok: test --junit: %d cases, one attachment each, the exception text in the failure"
          % len(cases), flush=True)


def check_non_utf8_paths(binary, work):
    """A scenario path and --out that are not UTF-8; evaluate of an estimate named so."""
    wb = work.encode()
    scenario = os.path.join(wb, b"caf\xe9.yaml")
    with open(scenario, "w") as f:
        f.write(scenario_text("plain", "  odometry: {}\n", ["odometry.ate_rmse_m < 5"]))
    out_dir = os.path.join(wb, b"out_caf\xe9")
    p = subprocess.run([binary.encode(), b"run", scenario, b"--out", out_dir, b"--no-plots"],
                       capture_output=True, timeout=300)
    if p.returncode != 0:
        fail("a run of caf\\xe9.yaml into out_caf\\xe9: exit %d\n%s" %
             (p.returncode, p.stderr.decode("utf-8", "replace")[-1500:]))
        return
    try:
        provenance = strict_json(os.path.join(out_dir, b"provenance.json"))
        if "caf\ufffd.yaml" not in json.dumps(provenance, ensure_ascii=False):
            fail("provenance.json does not name the scenario with U+FFFD: %s" % provenance)
    except (OSError, ValueError) as e:
        fail("provenance.json: %s" % e)
    if not os.path.isfile(os.path.join(out_dir, b"viewer.html")):
        fail("the run into out_caf\\xe9 wrote no viewer.html")
    print("ok: a scenario path and --out that are not UTF-8: exit 0, provenance.json valid",
          flush=True)

    estimate = os.path.join(wb, b"est_caf\xe9.tum")
    shutil.copy(os.path.join(out_dir, b"odometry.tum"), estimate)
    eval_dir = os.path.join(wb, b"eval_caf\xe9")
    p = subprocess.run([binary.encode(), b"evaluate", out_dir, b"--estimate", b"mine=" + estimate,
                        b"--out", eval_dir, b"--no-plots"], capture_output=True, timeout=300)
    if p.returncode != 0:
        fail("evaluate of est_caf\\xe9.tum: exit %d\n%s" %
             (p.returncode, p.stderr.decode("utf-8", "replace")[-1500:]))
        return
    try:
        check_rounded(eval_dir)
        evaluation = strict_json(os.path.join(eval_dir, b"evaluation.json"))
        if "est_caf\ufffd.tum" not in json.dumps(evaluation, ensure_ascii=False):
            fail("evaluation.json does not name the estimate with U+FFFD")
    except (OSError, ValueError) as e:
        fail("evaluation.json: %s" % e)
    print("ok: evaluate of an estimate whose name is not UTF-8: exit 0, evaluation.json valid",
          flush=True)


def check_study_name(binary, work):
    """A study folder named <!--<script>caf\\xe9 (markup, then a byte that is not UTF-8):
    report.html's data free of '<', the name read back with U+FFFD."""
    path = os.path.join(work, "study.yaml")
    with open(path, "w") as f:
        f.write(scenario_text("study", "  odometry: {}\n", ["odometry.ate_rmse_m < 5"]) +
                "study:\n  runs: 1\n")
    out_dir = os.path.join(work, HOSTILE + "caf\udce9")  # the byte 0xE9 (os.fsencode)
    rc, out, err = run([binary, "study", path, "--out", out_dir, "--no-plots"])
    if rc != 0:
        fail("a study into %s: exit %d\n%s" % (HOSTILE, rc, err[-1500:]))
        return
    check_rounded(out_dir)
    data = page_data(os.path.join(out_dir, "report.html"))
    if data.get("study") != HOSTILE + "caf\ufffd":
        fail("report.html: the study's name reads back as %r" % data.get("study"))
    else:
        # The browser is given a UTF-8 path (node reads its arguments as UTF-8).
        copy = os.path.join(work, "study_report.html")
        shutil.copy(os.path.join(out_dir, "report.html"), copy)
        PAGES.append((copy, "study " + HOSTILE + "caf\ufffd"))
        print("ok: a study folder named '%scaf\\xe9': report.html's data free of '<'" % HOSTILE,
              flush=True)


def check_pages_in_browser(node, source):
    rc, out, err = run([node, os.path.join(source, "tests", "viewer", "open_pages.mjs")] +
                       [x for page in PAGES for x in page])
    sys.stdout.write(out)
    if rc != 0 or len(PAGES) != 3:
        fail("the pages in chromium (%d of 3 written): exit %d\n%s" % (len(PAGES), rc, err[-2000:]))
    else:
        print("ok: the 3 pages load in chromium and show '%s' as text" % HOSTILE, flush=True)


def main():
    binary, plugins, source, work = (os.path.abspath(a) for a in sys.argv[1:5])
    node = sys.argv[5] if len(sys.argv) > 5 else None
    sys.stdout.reconfigure(errors="backslashreplace")  # paths holding a byte that is not UTF-8
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    echo = os.path.join(plugins, "test_echo_plugin.so")
    latin1_path = check_failed_pipelines(binary, echo, work)
    check_landmark_label(source, work)
    check_junit(binary, work, latin1_path, source)
    check_non_utf8_paths(binary, work)
    check_study_name(binary, work)
    if node:
        check_pages_in_browser(node, source)
    else:
        print("note: no NODE given: the pages were not opened in a browser", flush=True)
    if FAILURES:
        print("%d failure(s)" % len(FAILURES))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
