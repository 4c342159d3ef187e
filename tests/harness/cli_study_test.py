#!/usr/bin/env python3
"""`corridorsim study` and `corridorsim test` as a user runs them, on a short camera-less
scenario: the summary is the same bytes for 1 and 2 workers and for shards merged; a rerun skips
finished runs; a failed run and a timed-out run are recorded with their seeds and the study goes
on (exit 1); study expectations give exit 3; bad input exits 2 before anything runs, naming the
file, line and key; `test` writes JUnit XML that a standard XML reader parses with one test case
per expectation.

Usage: cli_study_test.py CORRIDORSIM SOURCE_DIR WORK_DIR"""

import csv
import json
import math
import os
import shutil
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_test_support import NO_EXTRAS, fail, read, run  # noqa: E402


def same_files(a, b, names):
    for name in names:
        if read(os.path.join(a, name)) != read(os.path.join(b, name)):
            fail("%s differs between %s and %s" % (name, a, b))


def check_axis_series(series, error_files):
    """The per-axis series recomputed here from the runs' errors CSVs: at each grid time, each
    run's first sample in [t, t + step), the RMS over runs of the error and of the sigma."""
    runs = []
    for path in error_files:
        with open(path) as f:
            rows = list(csv.DictReader(f))
        runs.append([{k: float(v) if v else math.nan for k, v in r.items()} for r in rows])
    step = series["step_s"]
    columns = {"x_m": ("ex_m", "sigma_x_m"), "y_m": ("ey_m", "sigma_y_m"),
               "yaw_rad": ("eyaw_rad", "sigma_yaw_rad")}
    for i, t in enumerate(series["t"]):
        samples = []
        for rows in runs:
            first = next((r for r in rows if r["t"] >= t - 1e-9), None)
            if first is not None and first["t"] < t + step:
                samples.append(first)
        if series["runs_with_error"][i] != len(samples):
            fail("runs_with_error at t=%g: %s, expected %d" % (t, series["runs_with_error"][i],
                                                                len(samples)))
        for axis, (error, sigma) in columns.items():
            for key, column in (("error_rms_" + axis, error), ("sigma_rms_" + axis, sigma)):
                expected = math.sqrt(sum(r[column] ** 2 for r in samples) / len(samples))
                got = series[key][i]
                if abs(got - expected) > 1e-6 * max(1.0, abs(expected)):
                    fail("%s at t=%g: %r, expected %r" % (key, t, got, expected))


def check_nis_series(nis, nis_files, step):
    """Each type's NIS series recomputed from the runs' NIS CSVs: the accepted innovations in
    [k step, (k + 1) step) pooled, their count and mean."""
    bins = {}
    for path in nis_files:
        with open(path) as f:
            for r in csv.DictReader(f):
                if r["accepted"] == "1":
                    b = bins.setdefault(r["type"], {}).setdefault(int(float(r["t"]) // step),
                                                                  [0, 0.0])
                    b[0] += 1
                    b[1] += float(r["nis"])
    if sorted(bins) != sorted(k for k in nis if "series" in nis[k]) or "lamp" not in bins:
        fail("NIS types: %s against %s" % (sorted(bins), sorted(nis)))
    for kind, by_bin in bins.items():
        series = nis[kind]["series"]
        keys = sorted(by_bin)
        if series["t"] != [k * step for k in keys] or \
                series["count"] != [by_bin[k][0] for k in keys]:
            fail("NIS %s bins: %s %s" % (kind, series["t"], series["count"]))
        for k, got in zip(keys, series["anis"]):
            if abs(got - by_bin[k][1] / by_bin[k][0]) > 1e-6:
                fail("NIS %s at bin %d: %r" % (kind, k, got))
        mean = sum(series["anis"]) / len(series["anis"])
        if abs(nis[kind]["time_average"] - mean) > 1e-6:
            fail("NIS %s time average %r, expected %r" % (kind, nis[kind]["time_average"], mean))


def check_case_times(root):
    """Each suite's cases share its time: they add up to it (3 decimals each), none negative."""
    for suite in root.findall("testsuite"):
        cases = [float(c.get("time")) for c in suite.findall("testcase")]
        if min(cases) < 0 or abs(sum(cases) - float(suite.get("time"))) > 0.001 * len(cases):
            fail("suite %s: case times %s against %s" % (suite.get("name"), cases,
                                                           suite.get("time")))


def main():
    binary, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    base = os.path.join(source, "scenarios", "umbmark_cw.yaml")
    study = os.path.join(work, "sweep.yaml")
    with open(study, "w") as f:
        f.write("""include: %s
duration_s: 8
pipelines:
  odometry: {baseline: false}  # umbmark_cw.yaml marks it a baseline: here its divergences count
  odometry_tight:
    type: odometry
study:
  runs: 3
  first_seed: 11
  vary:
    robot.odometry.random_k_m: [1.0e-5, 1.0e-3]
  expectations:
    - odometry.ate_rmse_m.mean < 5
    - paired(odometry, odometry_tight).ate_rmse_m.diff <= 0
    - odometry.runs.diverged < 4
    - runs.failed < 1
""" % base)
    summary_files = ["summary.json", "summary.csv", "paired.csv"]

    # One worker and two workers: the same bytes, in the summary and in every run.
    run(binary, ["study", study, "--jobs", "1", "--out", "j1", *NO_EXTRAS], 0, work)
    out = run(binary, ["study", study, "--jobs", "2", "--out", "j2", *NO_EXTRAS], 0, work)
    if "ATE RMSE mean" not in out.stdout or "mean ATE (m): odometry" not in out.stdout:
        fail("no closing table or progress line:\n" + out.stdout)
    same_files(os.path.join(work, "j1"), os.path.join(work, "j2"), summary_files)
    log = read(os.path.join(work, "j1", "logs", "p000", "seed_11.log")).decode()
    if "run: " not in log:
        fail("a run's log holds not its output: %r" % log[:200])
    for point in ("p000", "p001"):
        for seed in (11, 12, 13):
            run_dir = os.path.join("runs", point, "seed_%d" % seed)
            same_files(os.path.join(work, "j1", run_dir), os.path.join(work, "j2", run_dir),
                       ["metrics.json", "odometry.tum"])
    summary = json.loads(read(os.path.join(work, "j1", "summary.json")))
    points = summary["points"]
    if [p["vary"]["robot.odometry.random_k_m"] for p in points] != ["1.0e-5", "1.0e-3"]:
        fail("sweep points: %s" % [p["vary"] for p in points])
    low, high = (p["pipelines"]["odometry"]["metrics"]["ate_rmse_m"] for p in points)
    if not (low["n"] == 3 and high["n"] == 3 and low["mean"] < high["mean"]):
        fail("more odometry noise must give a larger ATE: %s vs %s" % (low, high))
    if not (low["ci_low"] <= low["mean"] <= low["ci_high"] and low["min"] <= low["median"]):
        fail("inconsistent statistics: %s" % low)
    values = points[0]["pipelines"]["odometry"]["values"]
    if values["seed"] != [11, 12, 13] or len(values["ate_rmse_m"]) != 3:
        fail("per-seed values: %s" % values)
    series = points[0]["pipelines"]["odometry"]["series"]
    if not series["t"] or len(series["anees"]) != len(series["t"]):
        fail("NEES series: %s" % list(series))
    check_axis_series(series, [os.path.join(work, "j1", "runs", "p000", "seed_%d" % seed,
                                            "odometry_errors.csv") for seed in (11, 12, 13)])
    # Each run is the run `corridorsim run` gives for that seed.
    run(binary, ["run", os.path.join(work, "j1", "points", "p001.yaml"), "--seed", "12", "--out",
                 "single", *NO_EXTRAS], 0, work)
    same_files(os.path.join(work, "single"), os.path.join(work, "j1", "runs", "p001", "seed_12"),
               ["metrics.json"])
    pairs = points[0]["paired"]
    if len(pairs) != 1 or pairs[0]["metrics"]["ate_rmse_m"]["n"] != 3:
        fail("paired comparison: %s" % pairs)
    csv_lines = read(os.path.join(work, "j1", "summary.csv")).decode().splitlines()
    if not csv_lines[0].startswith("point,robot.odometry.random_k_m,pipeline,metric,n,mean"):
        fail("summary.csv header: " + csv_lines[0])
    if len(csv_lines) != 1 + 2 * 2 * len(summary["metrics"]):
        fail("summary.csv rows: %d" % len(csv_lines))

    # Shards merged: the same summary as the whole study.
    for k in (1, 2, 3):
        run(binary, ["study", study, "--shard", "%d/3" % k, "--out", "shard%d" % k, *NO_EXTRAS],
            0, work)
    run(binary, ["study", "merge", "shard1", "shard2", "shard3", "--out", "merged",
                 *NO_EXTRAS], 0, work)
    same_files(os.path.join(work, "j1"), os.path.join(work, "merged"), summary_files)

    # A rerun skips finished runs; a missing run folder is run again.
    out = run(binary, ["study", study, "--out", "j1", *NO_EXTRAS], 0, work)
    if "6 already finished, 0 to run" not in out.stdout:
        fail("rerun did not skip the finished runs:\n" + out.stdout)
    shutil.rmtree(os.path.join(work, "j1", "runs", "p000", "seed_12"))
    out = run(binary, ["study", study, "--out", "j1", *NO_EXTRAS], 0, work)
    if "5 already finished, 1 to run" not in out.stdout:
        fail("rerun did not run the missing run:\n" + out.stdout)
    same_files(os.path.join(work, "j1"), os.path.join(work, "j2"), summary_files)

    # A run that fails is recorded with its seed, the others are summarised, exit 1.
    blocker = os.path.join(work, "j1", "runs", "p001", "seed_13")
    shutil.rmtree(blocker)
    with open(blocker, "w") as f:
        f.write("not a folder\n")
    out = run(binary, ["study", study, "--out", "j1", *NO_EXTRAS], 1, work)
    if "p001 seed 13: exited 2" not in out.stdout:
        fail("the failed run is not named:\n" + out.stdout)
    summary = json.loads(read(os.path.join(work, "j1", "summary.json")))
    if summary["points"][1]["runs"]["failed_seeds"] != [13]:
        fail("failed seeds: %s" % summary["points"][1]["runs"])
    status = json.loads(read(os.path.join(work, "j1", "status", "p001", "seed_13.json")))
    if status["outcome"] != "failed" or status["seed"] != 13:
        fail("status: %s" % status)
    os.remove(blocker)
    run(binary, ["study", study, "--out", "j1", *NO_EXTRAS], 0, work)
    same_files(os.path.join(work, "j1"), os.path.join(work, "j2"), summary_files)

    # A study folder of another plan is not mixed with this one.
    other = os.path.join(work, "other.yaml")
    with open(other, "w") as f:
        f.write(read(study).decode().replace("runs: 3", "runs: 2"))
    out = run(binary, ["study", other, "--out", "j1", *NO_EXTRAS], 2, work)
    if "--force" not in out.stderr:
        fail("another plan in the same folder: " + out.stderr)

    # NIS over time: each landmark type's innovations of all runs pooled per time bin.
    landmarks = os.path.join(work, "landmarks.yaml")
    with open(landmarks, "w") as f:
        f.write("include: %s\nduration_s: 6\nstudy:\n  runs: 2\n"
                % os.path.join(source, "scenarios", "p3_lamps.yaml"))
    run(binary, ["study", landmarks, "--out", "nis", *NO_EXTRAS, "--jobs", "2"], 0, work)
    summary = json.loads(read(os.path.join(work, "nis", "summary.json")))
    nis = summary["points"][0]["pipelines"]["p3_upward"]["nis"]
    check_nis_series(nis, [os.path.join(work, "nis", "runs", "p000", "seed_%d" % seed,
                                        "p3_upward_nis.csv") for seed in (1, 2)], 1.0)

    # A run over its time limit is killed and recorded as timed out.
    slow = os.path.join(work, "slow.yaml")
    with open(slow, "w") as f:
        f.write("include: %s\nduration_s: 30\nstudy:\n  runs: 1\n  run_timeout_s: 1\n"
                % os.path.join(source, "scenarios", "p3_lamps.yaml"))
    out = run(binary, ["study", slow, "--out", "slow", *NO_EXTRAS], 1, work)
    if "timed out after 1 s" not in out.stdout:
        fail("no timeout:\n" + out.stdout)

    # A failed study expectation: exit 3, the results written.
    strict = os.path.join(work, "strict.yaml")
    with open(strict, "w") as f:
        f.write(read(study).decode().replace("odometry.ate_rmse_m.mean < 5",
                                             "odometry.ate_rmse_m.mean < 0.000001"))
    out = run(binary, ["study", strict, "--out", "strict", *NO_EXTRAS], 3, work)
    if "FAILED p000: odometry.ate_rmse_m.mean < 0.000001" not in out.stdout:
        fail("the failed expectation is not named:\n" + out.stdout)

    # A diverged run (here: average NEES above a low divergence_nees) fails the study, exit 1,
    # naming point, seed, pipeline and reason; a pipeline in may_diverge is reported only.
    diverging = os.path.join(work, "diverging.yaml")
    with open(diverging, "w") as f:
        f.write(read(study).decode().replace("  runs: 3\n", "  runs: 3\n  divergence_nees: 5\n"))
    out = run(binary, ["study", diverging, "--out", "div", *NO_EXTRAS], 1, work)
    if "p001 seed 12: odometry diverged: average NEES" not in out.stdout or \
            "p000 seed" in out.stdout.split("run(s) diverged")[-1]:
        fail("the diverged runs are not named (only p001's diverge):\n" + out.stdout)
    runs = json.loads(read(os.path.join(work, "div", "summary.json")))["points"][1]["pipelines"][
        "odometry"]["runs"]
    if runs["diverged_seeds"] != [11, 12, 13] or runs["may_diverge"] or \
            not runs["diverged_why"][0].startswith("average NEES"):
        fail("diverged runs in summary.json: %s" % runs)
    out = run(binary, ["study", diverging, "--out", "div2", *NO_EXTRAS, "--may-diverge",
                       "odometry_tight,odometry"], 0, work)
    if "p001 odometry: seeds 11, 12, 13" not in out.stdout:
        fail("allowed divergences are not reported:\n" + out.stdout)
    # Shards exit 0 (their verdict is the merge's); the merge exits 1 on the divergences.
    for k in (1, 2):
        run(binary, ["study", diverging, "--shard", "%d/2" % k, "--out", "dshard%d" % k,
                     *NO_EXTRAS], 0, work)
    out = run(binary, ["study", "merge", "dshard1", "dshard2", "--out", "dmerged", *NO_EXTRAS],
              1, work)
    if "p001 seed 13: odometry_tight diverged" not in out.stdout:
        fail("the merge does not name the diverged runs:\n" + out.stdout)
    # --slurm hands --may-diverge to every array task (their plans must be the study's).
    run(binary, ["study", diverging, "--slurm", "--slurm-tasks", "2", "--may-diverge", "odometry",
                 "--out", "dslurm", *NO_EXTRAS], 0, work)
    if " --may-diverge odometry " not in read(os.path.join(work, "dslurm", "slurm",
                                                           "study.sbatch")).decode():
        fail("the array script does not pass --may-diverge")
    with open(diverging.replace(".yaml", "_allowed.yaml"), "w") as f:
        f.write(read(diverging).decode().replace(
            "  divergence_nees: 5\n", "  divergence_nees: 5\n  may_diverge: [odometry_tight]\n"))
    out = run(binary, ["study", diverging.replace(".yaml", "_allowed.yaml"), "--out", "div3",
                       *NO_EXTRAS], 1, work)
    if "odometry_tight diverged" in out.stdout or "odometry diverged" not in out.stdout:
        fail("study.may_diverge exempts only the pipelines it names:\n" + out.stdout)

    # Bad input: exit 2 with file:line: key, and nothing runs.
    bad = os.path.join(work, "bad.yaml")
    with open(bad, "w") as f:
        f.write("include: %s\nstudy:\n  vary:\n    robot.odometry.random_k_m: [1.0e-5, oops]\n"
                % base)
    out = run(binary, ["study", bad, "--out", "bad"], 2, work)
    if "bad.yaml:4:" not in out.stderr or "study.vary.robot.odometry.random_k_m" not in out.stderr:
        fail("bad sweep value: " + out.stderr)
    if os.path.exists(os.path.join(work, "bad", "runs")):
        fail("a run started for bad input")
    for args, pattern in (
            (["study", study, "--shard", "4/3"], "--shard"),
            (["study", study, "--jobs", "0"], "--jobs"),
            (["study", study, "--runs", "1.5"], "--runs"),
            (["study", study, "--may-diverge", "odometry,nope"], "--may-diverge: 'nope'"),
            (["study", "merge", "j1", "strict", "--out", "m2"], "plans differ")):
        out = run(binary, args, 2, work)
        if pattern not in out.stderr:
            fail("%s: %s" % (args, out.stderr))

    # `corridorsim test`: JUnit XML with one case per expectation.
    scenario = os.path.join(work, "checked.yaml")
    with open(scenario, "w") as f:
        f.write("include: %s\nduration_s: 8\nexpectations:\n  - odometry.ate_rmse_m < 1e-9\n"
                "  - odometry.ate_rmse_m < 100\n" % base)
    out = run(binary, ["test", scenario, study, "--out", "suite", "--junit", "junit.xml"], 3, work)
    root = ET.parse(os.path.join(work, "junit.xml")).getroot()
    # checked: 2 expectations; sweep: 2 points x (4 expectations + 2 "does not diverge").
    if root.tag != "testsuites" or root.get("tests") != "14" or root.get("failures") != "1":
        fail("junit.xml: %s %s" % (root.tag, root.attrib))
    suites = root.findall("testsuite")
    if [s.get("name") for s in suites] != ["checked", "sweep"]:
        fail("test suites: %s" % [s.get("name") for s in suites])
    failure = suites[0].find("testcase/failure")
    if failure is None or "measured" not in failure.get("message") or \
            "< 1e-9" not in failure.get("message"):
        fail("failure message: %s" % (failure.attrib if failure is not None else None))
    for case in root.iter("testcase"):
        if float(case.get("time")) < 0 or "[[ATTACHMENT|" not in case.find("system-out").text:
            fail("test case %s: time or attachment" % case.get("name"))
    check_case_times(root)
    names = [c.get("name") for c in suites[1].findall("testcase")]
    for name in ("p001 (robot.odometry.random_k_m=1.0e-3): runs.failed < 1",
                 "p001 (robot.odometry.random_k_m=1.0e-3): odometry_tight does not diverge"):
        if name not in names:
            fail("study cases: %s" % names)
    # A diverged run of a pipeline not in may_diverge: a failed case naming seed and reason.
    run(binary, ["test", diverging, "--out", "suite4", "--junit", "diverging.xml"], 3, work)
    root = ET.parse(os.path.join(work, "diverging.xml")).getroot()
    failed = {c.get("name"): c.find("failure").get("message") for c in root.iter("testcase")
              if c.find("failure") is not None}
    if sorted(failed) != ["p001 (robot.odometry.random_k_m=1.0e-3): odometry does not diverge",
                          "p001 (robot.odometry.random_k_m=1.0e-3): odometry_tight does not "
                          "diverge"] or "seed 12: average NEES" not in "".join(failed.values()):
        fail("diverging.xml: %s" % failed)
    # A study whose run timed out: an error case naming the seed; its time is counted once.
    run(binary, ["test", slow, "--out", "suite3", "--junit", "slow.xml"], 1, work)
    root = ET.parse(os.path.join(work, "slow.xml")).getroot()
    errors = [c for c in root.iter("testcase") if c.find("error") is not None]
    if root.get("errors") != "1" or len(errors) != 1 or errors[0].get("name") != "p000 seed 1":
        fail("slow.xml: %s %s" % (root.attrib, [c.get("name") for c in root.iter("testcase")]))
    check_case_times(root)
    out = run(binary, ["test", scenario, bad, "--out", "suite2"], 2, work)
    if os.path.exists(os.path.join(work, "suite2")):
        fail("test ran something before rejecting a bad file")
    print("PASS")


if __name__ == "__main__":
    main()
