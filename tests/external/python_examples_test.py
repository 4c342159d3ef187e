#!/usr/bin/python3
"""The shipped Python pipelines (examples/python_pipeline/, README.md), run as a user runs them:

- odometry.py beside the built-in `odometry`: the trajectory, covariance and metrics.json entries
  are byte-identical (the protocol delivers every message and number exactly); then its 4-seed
  study through `corridorsim test --junit` (no failure, no error);
- lamps.py (OpenCV on the upward camera) beats dead reckoning: its run passes its expectation,
  and its 4-seed study through `corridorsim test --junit` passes (the paired difference of ATEs
  is below zero over the seeds).

usage: python_examples_test.py CORRIDORSIM SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

# What these runs and studies check is their results: plots/ and the pages are left out
# (scripts.plot_run, viewer.browser and viewer.odd_data test those).
NO_EXTRAS = ["--no-plots", "--no-viewer"]


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def run(args, expect=0):
    print("+ " + " ".join(args), flush=True)
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != expect:
        fail("%s exited %d (expected %d)\n%s\n%s" % (" ".join(args), p.returncode, expect,
                                                    p.stdout[-3000:], p.stderr[-3000:]))
    return p


def body(path):
    """A run folder file without its first line (which names the pipeline)."""
    with open(path, "rb") as f:
        return f.read().split(b"\n", 1)[1]


def junit_ok(binary, scenario, work, name):
    report = os.path.join(work, name + "_junit.xml")
    run([binary, "test", scenario, "--junit", report, "--out", os.path.join(work, name + "_test")])
    root = ET.parse(report).getroot()
    cases = list(root.iter("testcase"))
    bad = [c.get("name") for c in cases if c.find("failure") is not None or c.find("error") is not None]
    if not cases or bad:
        fail("%s: test --junit: %d cases, failing %s" % (name, len(cases), bad))
    print("ok: %s: test --junit, %d cases passed" % (name, len(cases)))


def main():
    binary, source, work = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    examples = os.path.join(source, "examples", "python_pipeline")

    odometry = os.path.join(examples, "odometry.yaml")
    d = os.path.join(work, "odometry")
    run([binary, "run", odometry, "--out", d, *NO_EXTRAS])
    for a, b in [("odometry.tum", "python_odometry.tum"),
                 ("odometry_cov.txt", "python_odometry_cov.txt")]:
        if body(os.path.join(d, a)) != body(os.path.join(d, b)):
            fail("%s and %s differ" % (a, b))
    with open(os.path.join(d, "metrics.json")) as f:
        metrics = json.load(f)["pipelines"]
    if metrics["odometry"] != metrics["python_odometry"] or "ate_rmse_m" not in metrics["odometry"]:
        fail("metrics.json entries differ:\n%s\n%s" % (metrics["odometry"], metrics["python_odometry"]))
    print("ok: the Python port of odometry is byte-identical to the built-in one "
          "(ATE %.6f m over %d lines)" % (metrics["odometry"]["ate_rmse_m"],
                                          body(os.path.join(d, "odometry.tum")).count(b"\n")))
    junit_ok(binary, odometry, work, "odometry")

    lamps = os.path.join(examples, "lamps.yaml")
    d = os.path.join(work, "lamps")
    run([binary, "run", lamps, "--out", d, *NO_EXTRAS])
    with open(os.path.join(d, "metrics.json")) as f:
        metrics = json.load(f)["pipelines"]
    mine, dead = metrics["python_lamps"]["ate_rmse_m"], metrics["odometry"]["ate_rmse_m"]
    if not mine < 0.5 * dead:
        fail("lamps.py's ATE %.4f m is not below half of odometry's %.4f m" % (mine, dead))
    print("ok: lamps.py ATE %.4f m, odometry %.4f m" % (mine, dead))
    junit_ok(binary, lamps, work, "lamps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
