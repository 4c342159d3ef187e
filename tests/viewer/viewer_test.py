#!/usr/bin/python3
"""viewer.html and report.html as a user meets them (docs/viewer.md), checked in Debian's
chromium by tests/viewer/browser_test.mjs (playwright-core):

  - a 30 s p3_lamps run with --keep-frames: viewer.html written, self-contained (no URL of
    another file, no fetch), frames/ within its budget, byte-identical frames/ on a rerun; the
    browser test loads it from file:// with no console error and reads the drawn poses and
    ellipses back against ground_truth.tum, <pipeline>.tum and <pipeline>_cov.txt;
    first_frame_test.mjs reads the plan's canvas back at the moments before the first paint
    (no click, no wait after load): it holds the drawn plan;
  - a run with an IMU and a laser scanner (docs/viewer.md, "Sensors"): browser_test.mjs sensors
    checks the scan layer (the drawn sweep, its points' count and positions) and the IMU plots
    (their series, every sample a row of the file, the extremes kept) against sensors/, and the
    viewer checks pass on it too; the p3_lamps page (no sensors/) carries no sensors section; a
    malformed IMU file and a scanner without its truth file: the page is written and says so;
  - a 2-seed study of the same: report.html links every run's viewer (relative), the browser
    test resolves them;
  - corridorsim test --junit with a failing expectation: the case's attachment is the run's
    viewer.html;
  - a broken run folder: make_viewer.py exits 2 naming the file and line; run exits 4 when the
    page fails and keeps its results.

    viewer_test.py CORRIDORSIM SOURCE_DIR WORK_DIR
Screenshots stay in WORK_DIR/shots (a CI artefact).
"""

import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
VIEWER_BUDGET_BYTES = 10_000_000
# 8 s of the short run with a 1 kHz IMU (8001 samples: more than the page's 6000, so decimated)
# and a scanner; no camera pipeline, so nothing renders.
SENSORS_SCENARIO = """include: {scenario}
duration_s: 8
sensors:
  imu0: {{type: imu, rate_hz: 1000, mount: {{x_m: 0.1, y_m: 0.05, z_m: 0.25}}}}
  scanner: {{type: laser, rate_hz: 10, mount: {{x_m: 0.16, z_m: 0.30}}}}
"""


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def run(argv, expect=(0,), env=None, timeout=900):
    print("+", " ".join(argv), flush=True)
    p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=env, timeout=timeout)
    if p.returncode not in expect:
        print(p.stdout[-4000:])
        fail(f"{' '.join(argv)} exited {p.returncode}, expected {expect}")
    return p


def write(path, text):
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def check_self_contained(page_path):
    page = open(page_path, encoding="utf-8").read()
    size = os.path.getsize(page_path)
    # Nothing loads from elsewhere: no src/href to a URL or file, no fetch or XHR of our own.
    for pattern in [r'<script[^>]+src=', r'<link[^>]+href=', r'<img[^>]+src="(?!data:)',
                    r'@import', r'url\((?!["\']?data:)']:
        if re.search(pattern, page):
            fail(f"{page_path}: not self-contained: matches {pattern}")
    if "fetch(" in page.split('id="corridorsim-data"')[0]:
        fail(f"{page_path}: calls fetch()")
    return size


def page_data(page):
    return json.loads(re.search(r'id="corridorsim-data" type="application/json">(.*?)</script>',
                                open(page, encoding="utf-8").read(), re.S).group(1)
                      .replace("<\\/", "</"))


def check_sensors(corridorsim, source, work, scenario, shots, node):
    """A run with an IMU and a scanner: its page in the browser; broken sensor files."""
    browser_test = os.path.join(source, "tests", "viewer", "browser_test.mjs")
    sensors = os.path.join(work, "sensors.yaml")
    write(sensors, SENSORS_SCENARIO.format(scenario=scenario))
    folder = os.path.join(work, "run_sensors")
    run([corridorsim, "run", sensors, "--out", folder, "--no-plots", "--set",
         "pipelines.p3_corners.enabled=false", "--set", "pipelines.p3_upward.enabled=false",
         "--set", "expectations=[]"])
    page = os.path.join(folder, "viewer.html")
    check_self_contained(page)
    data = page_data(page)
    imus, lasers = data["sensors"]["imus"], data["sensors"]["lasers"]
    if [q["name"] for q in imus] != ["imu0"] or [q["name"] for q in lasers] != ["scanner"] or \
            imus[0]["problem"] or lasers[0]["problem"] or imus[0]["samples"] != 8001 or \
            not 0 < len(imus[0]["gyro"]["t"]) <= 6000 or lasers[0]["sweeps"] != 80 or \
            len(lasers[0]["t"]) != 80:
        fail(f"the sensors page's data: IMUs {[(q['name'], q.get('samples')) for q in imus]}, "
             f"scanners {[(q['name'], q.get('sweeps')) for q in lasers]}")
    run([node, browser_test, "sensors", "--page", page, "--run", folder, "--shots", shots],
        timeout=300)
    run([node, browser_test, "viewer", "--page", page, "--run", folder, "--shots",
         os.path.join(shots, "sensors_run")], timeout=300)

    # Broken sensor files: the page is written all the same and says what it left out.
    broken = os.path.join(work, "run_sensors_broken")
    shutil.copytree(folder, broken)
    imu = os.path.join(broken, "sensors", "imu0_imu.csv")
    lines = open(imu, encoding="utf-8").read().split("\n")
    lines[49] = lines[49].replace(",", ",x", 1)
    write(imu, "\n".join(lines))
    os.remove(os.path.join(broken, "sensors", "scanner_scans_truth.csv"))
    run([PYTHON, os.path.join(source, "scripts", "make_viewer.py"), broken])
    data = page_data(os.path.join(broken, "viewer.html"))
    problems = [q["problem"] for q in data["sensors"]["imus"] + data["sensors"]["lasers"]]
    if problems != ["sensors/imu0_imu.csv:50: not a number in the line",
                    "sensors/scanner_scans_truth.csv: is missing (the scanner's true poses are in "
                    "it)"]:
        fail(f"the broken sensors' problems on the page: {problems}")
    run([node, browser_test, "sensors", "--page", os.path.join(broken, "viewer.html"), "--run",
         broken, "--shots", shots], timeout=300)
    # More ways a file can be malformed: each named with its line (the IMU's chunked reading
    # finds the line of a chunk that does not parse).
    def field(k, value):  # the line with its k-th field replaced
        return lambda line: ",".join(line.split(",")[:k] + [value] + line.split(",")[k + 1:])
    cases = [("imu0_imu.csv", 7000, lambda line: line + ",1",
              "imu0_imu.csv:7001: expected 29 fields, got 30"),
             ("imu0_imu.csv", 3000, field(0, "0.5"),
              "imu0_imu.csv:3001: t 0.5 is not after the previous sample's 2.998"),
             ("imu0_imu.csv", 100, field(1, "nan"), "imu0_imu.csv:101: a value is not finite"),
             ("scanner_scans.csv", 11, field(1, "-1.0"),
              "scanner_scans.csv:12: the sweep's angles, times or range limits differ from the "
              "first sweep's")]
    for name, index, change, want in cases:
        shutil.rmtree(broken)
        shutil.copytree(folder, broken)
        path = os.path.join(broken, "sensors", name)
        lines = open(path, encoding="utf-8").read().split("\n")
        lines[index] = change(lines[index])
        write(path, "\n".join(lines))
        run([PYTHON, os.path.join(source, "scripts", "make_viewer.py"), broken])
        sensors = page_data(os.path.join(broken, "viewer.html"))["sensors"]
        problems = [q["problem"] for q in sensors["imus"] + sensors["lasers"] if q["problem"]]
        if problems != ["sensors/" + want]:
            fail(f"{name} with line {index + 1} changed: the page says {problems}, not {want}")
    print("ok: sensors: the scan layer and the IMU plots drawn from sensors/; broken files named "
          "on the page")


def main():
    corridorsim, source, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    shots = os.path.join(work, "shots")
    node = shutil.which("node")
    if node is None:
        fail("node is not installed (scripts/setup.sh)")
    browser_test = os.path.join(source, "tests", "viewer", "browser_test.mjs")

    # A short run that keeps its frames.
    scenario = os.path.join(work, "short.yaml")
    write(scenario, f"include: {source}/scenarios/p3_lamps.yaml\nduration_s: 30\n")
    first = os.path.join(work, "run")
    out = run([corridorsim, "run", scenario, "--out", first, "--no-plots", "--keep-frames",
               "--keep-frames-mb", "2"]).stdout
    page = os.path.join(first, "viewer.html")
    if not os.path.isfile(page) or "viewer.html" not in out:
        fail("run did not write viewer.html (or did not say so)")
    frames_bytes = sum(os.path.getsize(os.path.join(first, "frames", f))
                       for f in os.listdir(os.path.join(first, "frames")) if f.endswith(".jpg"))
    if not 0 < frames_bytes <= 2_000_000:
        fail(f"frames/ holds {frames_bytes} bytes of JPEG, budget 2 MB")
    size = check_self_contained(page)
    print(f"viewer.html: {size / 1e6:.2f} MB with {frames_bytes / 1e6:.2f} MB of frames")
    if size > VIEWER_BUDGET_BYTES + 1.4 * frames_bytes:
        fail(f"viewer.html is {size} bytes: over the budget")
    data = page_data(page)
    if not data["frames"] or not data["pipelines"] or not data["truth"]["t"]:
        fail("the page's data lacks frames, pipelines or the truth")
    if "sensors" in data:
        fail("a run without sensors/ has a sensors section in its page")

    # Same scenario and seed: the same frames/ bytes.
    second = os.path.join(work, "run2")
    run([corridorsim, "run", scenario, "--out", second, "--no-plots", "--no-viewer",
         "--keep-frames", "--keep-frames-mb", "2"])
    if os.path.exists(os.path.join(second, "viewer.html")):
        fail("--no-viewer wrote viewer.html")
    for f in sorted(os.listdir(os.path.join(first, "frames"))):
        a = open(os.path.join(first, "frames", f), "rb").read()
        b = open(os.path.join(second, "frames", f), "rb").read()
        if a != b:
            fail(f"frames/{f} differs between two runs of one scenario and seed")

    # The page in a real browser.
    run([node, browser_test, "viewer", "--page", page, "--run", first, "--shots", shots],
        timeout=300)
    # The plan is drawn in the first frame the page paints (a headless screenshot's frame).
    run([node, os.path.join(source, "tests", "viewer", "first_frame_test.mjs"), "--page", page],
        timeout=300)

    check_sensors(corridorsim, source, work, scenario, shots, node)

    # A study: report.html, links to every run's viewer.
    study = os.path.join(work, "study.yaml")
    write(study, f"include: {scenario}\nstudy:\n  runs: 2\n")
    study_dir = os.path.join(work, "study")
    run([corridorsim, "study", study, "--out", study_dir, "--jobs", "2", "--no-plots"])
    report = os.path.join(study_dir, "report.html")
    if not os.path.isfile(report):
        fail("study did not write report.html")
    check_self_contained(report)
    viewers = re.findall(r'"viewer":"([^"]+)"', open(report, encoding="utf-8").read())
    if len(viewers) != 2 or any(os.path.isabs(v) for v in viewers):
        fail(f"report.html should link 2 run viewers by relative paths, links {viewers}")
    run([node, browser_test, "report", "--page", report, "--shots", shots], timeout=300)

    # corridorsim test: a failing case points at its run's viewer.
    failing = os.path.join(work, "failing.yaml")
    write(failing, f"include: {scenario}\nduration_s: 10\nexpectations:\n"
                   "  - odometry.ate_rmse_m < 0.0000001\n")
    junit = os.path.join(work, "junit.xml")
    run([corridorsim, "test", failing, "--junit", junit, "--out", os.path.join(work, "suite")],
        expect=(3,))
    cases = [c for c in ET.parse(junit).getroot().iter("testcase")
             if c.find("failure") is not None]
    if len(cases) != 1:
        fail(f"expected one failed case, got {len(cases)}")
    attachment = re.search(r"\[\[ATTACHMENT\|(.*?)\]\]", cases[0].find("system-out").text).group(1)
    if not attachment.endswith("viewer.html") or not os.path.isfile(attachment):
        fail(f"the failed case's attachment {attachment} is not an existing viewer.html")
    if attachment not in cases[0].find("failure").text:
        fail("the failure's text does not name the viewer")

    # Bad input: make_viewer names the file and line; the run keeps its results with exit 4.
    broken = os.path.join(work, "broken")
    shutil.copytree(first, broken)
    name = data["pipelines"][0]["name"]
    with open(os.path.join(broken, f"{name}.tum"), "a", encoding="utf-8") as f:
        f.write("12.5 1 2\n")
    p = run([PYTHON, os.path.join(source, "scripts", "make_viewer.py"), broken], expect=(2,))
    if f"{name}.tum" not in p.stdout or not re.search(r":\d+:", p.stdout):
        fail(f"make_viewer.py's message should name {name}.tum and its line: {p.stdout}")
    # A data folder whose make_viewer.py fails (the rest is the checkout's).
    data_dir = os.path.join(work, "data_failing_viewer")
    os.makedirs(os.path.join(data_dir, "scripts"))
    for d in ("scenarios", "models", "viewer"):
        os.symlink(os.path.join(source, d), os.path.join(data_dir, d))
    write(os.path.join(data_dir, "scripts", "make_viewer.py"),
          "import sys\nsys.exit('make_viewer.py: broken on purpose')\n")
    env = dict(os.environ, CORRIDORSIM_DATA_DIR=data_dir)
    exit4 = os.path.join(work, "run_exit4")
    run([corridorsim, "run", scenario, "--out", exit4, "--no-plots"], expect=(4,), env=env)
    if not os.path.isfile(os.path.join(exit4, "metrics.json")):
        fail("a failed viewer.html lost the run's results")
    print("PASS viewer: run page, frames, browser checks, sensors, study report, JUnit link, bad "
          "input")


if __name__ == "__main__":
    main()
