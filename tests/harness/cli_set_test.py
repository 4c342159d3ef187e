#!/usr/bin/env python3
"""`--set KEY=VALUE` and `test --jobs` as a user runs them, on short camera-less runs of
scenarios/umbmark_cw.yaml: a set value is used and echoed in scenario.yaml, and rerunning that
file gives the same metrics.json; a bad key or value exits 2 naming --set and the key, before
anything is written, for every command that reads a scenario; a study's plan changes with --set;
`test` passes --set to every file's job, and its JUnit report and results are the same for
--jobs 1 and 2 but for the wall-clock `time` attributes.

Usage: cli_set_test.py CORRIDORSIM SOURCE_DIR WORK_DIR"""

import json
import os
import re
import shutil
import sys
import xml.etree.ElementTree as ET

sys.dont_write_bytecode = True  # nothing written into the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_study_test import fail, read, run  # noqa: E402  (the CLI tests' helpers)

NO_EXTRAS = ["--no-plots", "--no-viewer"]
# Short and camera-less: what these runs check is the settings, not the pictures.
SHORT = ["--set", "duration_s=4", "--set", "sensors.front.enabled=false",
         "--set", "sensors.lateral.enabled=false"]


def main():
    binary, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scenario = os.path.join(source, "scenarios", "umbmark_cw.yaml")

    # A set value is used, echoed and recorded; the echo repeats the run.
    settings = SHORT + ["--set", "world.doors.count=6", "--set", "seed=4", "--set", "seed=5",
                        "--set", "expectations=[odometry.ate_rmse_m < 50]"]
    run(binary, ["run", scenario, *settings, "--out", "r1", *NO_EXTRAS], 0, work)
    echo = read(os.path.join(work, "r1", "scenario.yaml")).decode()
    for line in ("\nduration_s: 4\n", "\nseed: 5\n", "expectations: [\"odometry.ate_rmse_m < 50\"]",
                 "\n  doors:\n    count: 6\n"):
        if line not in echo:
            fail("scenario.yaml lacks %r:\n%s" % (line, echo))
    provenance = json.loads(read(os.path.join(work, "r1", "provenance.json")))
    if provenance["scenario"].get("settings") != [s for s in settings if s != "--set"]:
        fail("provenance.json's scenario: %s" % provenance["scenario"])
    metrics = json.loads(read(os.path.join(work, "r1", "metrics.json")))
    if [e["text"] for e in metrics["expectations"]] != ["odometry.ate_rmse_m < 50"]:
        fail("the run's expectations: %s" % metrics["expectations"])
    run(binary, ["run", os.path.join("r1", "scenario.yaml"), "--out", "r2", *NO_EXTRAS], 0, work)
    for name in ("metrics.json", "scenario.yaml", "odometry.tum"):
        if read(os.path.join(work, "r1", name)) != read(os.path.join(work, "r2", name)):
            fail("%s differs between the run with --set and the rerun of its scenario.yaml" % name)
    # Without --set the same file gives another run (the set values were used).
    run(binary, ["run", scenario, *SHORT, "--out", "r3", *NO_EXTRAS], 0, work)
    if read(os.path.join(work, "r3", "metrics.json")) == read(os.path.join(work, "r1", "metrics.json")):
        fail("--set seed and world.doors.count changed nothing in metrics.json")

    # A bad setting: exit 2 naming --set and the key, nothing written, for every command that
    # reads a scenario.
    for job, extra in (("run", []), ("world", []), ("drive", []), ("dataset", []),
                       ("snapshot", ["--pose", "1,0,0"]), ("study", [])):
        out = run(binary, [job, scenario, "--set", "world.doors.cout=4", "--out", "bad_" + job,
                           *extra], 2, work)
        if "command line: --set: world.doors.cout: unknown key" not in out.stderr:
            fail("%s: %s" % (job, out.stderr))
        if os.path.exists(os.path.join(work, "bad_" + job)):
            fail("%s wrote its folder for a bad --set" % job)
    for setting, message in (
            ("duration_s", "command line: --set: expected KEY=VALUE"),
            ("duration_s=soon", "command line: --set: duration_s: "),
            ("duration_s=-1", "command line: --set: duration_s: must lie in"),
            ("include=x.yaml", "command line: --set: include: cannot be set"),
            ("expectations.5=x", "command line: --set: expectations.5: index 5 is beyond")):
        out = run(binary, ["run", scenario, "--set", setting, "--out", "bad"], 2, work)
        if message not in out.stderr:
            fail("--set %s: %s" % (setting, out.stderr))
    # One KEY=VALUE per --set: the scenario file after it stays the scenario file.
    out = run(binary, ["world", "--set", "world.doors.count=4", scenario, "--out", "w"], 0, work)
    if "umbmark_cw.yaml" not in out.stdout + out.stderr and \
            not os.path.exists(os.path.join(work, "w", "ground_truth.json")):
        fail("world with --set before the file: %s" % out.stdout)

    # study: scenario keys and study keys; the plan changes with --set.
    run(binary, ["study", scenario, *SHORT, "--set", "study.runs=2", "--jobs", "2", "--out", "s1",
                 *NO_EXTRAS], 0, work)
    summary = json.loads(read(os.path.join(work, "s1", "summary.json")))
    if summary["points"][0]["runs"]["finished"] != 2:
        fail("study --set study.runs=2: %s" % summary["points"][0]["runs"])
    if "\nduration_s: 4\n" not in read(os.path.join(work, "s1", "points", "p000.yaml")).decode():
        fail("the study's point scenario lacks the set duration_s")
    out = run(binary, ["study", scenario, *SHORT, "--set", "study.runs=2", "--set",
                       "world.doors.count=6", "--out", "s1", *NO_EXTRAS], 2, work)
    if "holds another study" not in out.stderr:
        fail("a --set that changes the scenario must change the plan: %s" % out.stderr)
    out = run(binary, ["study", scenario, *SHORT, "--set", "study.runz=2", "--out", "s2"], 2, work)
    if "command line: --set: study.runz: unknown key" not in out.stderr:
        fail("study --set study.runz: %s" % out.stderr)

    # test: --set reaches every file's job; --jobs 1 and 2 report the same.
    checked = os.path.join(work, "checked.yaml")
    with open(checked, "w") as f:
        f.write("include: %s\nexpectations:\n  - odometry.ate_rmse_m < 1e-9\n"
                "  - odometry.ate_rmse_m < 100\n" % scenario)
    study = os.path.join(work, "seeds.yaml")
    with open(study, "w") as f:
        f.write("include: %s\nstudy:\n  runs: 2\n  expectations:\n"
                "    - odometry.ate_rmse_m.mean < 100\n" % scenario)
    files = [checked, study, scenario]
    for jobs in ("1", "2"):
        out = run(binary, ["test", *files, *SHORT, "--jobs", jobs, "--out", "t" + jobs,
                           "--junit", "j%s.xml" % jobs], 3, work)
    reports = []
    for jobs in ("1", "2"):
        text = read(os.path.join(work, "j%s.xml" % jobs)).decode()
        ET.fromstring(text)  # well-formed
        text = re.sub(r' time="[0-9.]+"', ' time="T"', text)
        reports.append(text.replace(os.path.join(work, "t" + jobs), "OUT"))
    if reports[0] != reports[1]:
        fail("junit.xml differs between --jobs 1 and 2:\n%s\n%s" % tuple(reports))
    root = ET.fromstring(reports[0])
    if root.get("tests") != "5" or root.get("failures") != "1" or root.get("errors") != "0":
        fail("junit.xml: %s" % root.attrib)
    for folder, name in (("000_checked", "metrics.json"), ("002_umbmark_cw", "metrics.json"),
                         ("001_seeds", "summary.json")):
        a, b = (os.path.join(work, t, folder, name) for t in ("t1", "t2"))
        if read(a) != read(b):
            fail("%s/%s differs between --jobs 1 and 2" % (folder, name))
    echo = read(os.path.join(work, "t1", "000_checked", "scenario.yaml")).decode()
    if "\nduration_s: 4\n" not in echo:
        fail("test did not pass --set to its run")
    for bad_args, message in ((["--jobs", "0"], "--jobs: must be a whole number in [1, 256]"),
                              (["--set", "world.doors.cout=4"],
                               "command line: --set: world.doors.cout: unknown key")):
        out = run(binary, ["test", checked, *bad_args, "--out", "t_bad"], 2, work)
        if message not in out.stderr:
            fail("test %s: %s" % (bad_args, out.stderr))
        if os.path.exists(os.path.join(work, "t_bad")):
            fail("test ran something for %s" % bad_args)
    print("PASS")


if __name__ == "__main__":
    main()
