#!/usr/bin/env python3
"""The study's speed and memory (issue 17's figures), measured in one benchmark run:

  1. throughput of a camera-less study with 1 worker and with 2 workers, side by side (the same
     runs: scenarios/default.yaml's round trip with odometry only and no camera), and its ratio;
  2. the peak memory of each worker (a run's peak RSS, from wait4) and whether it stays flat over
     the study (the mean of the last tenth of the runs against the first tenth);
  3. the study's own overhead: 1 - (sum of the runs' wall time) / (workers x the study's wall
     time), which counts scheduling, the summary and the idle tail when fewer runs than workers
     are left.

    scripts/bench_study.py [--corridorsim build/bin/corridorsim] [--runs 40] [--out out/bench_study]
                           [--scenario FILE (default: a camera-less default.yaml)]

Prints a table and writes OUT/bench_study.json. Standard library only. Speed is measured here,
never asserted by a test (docs/studies.md, "Speed and memory")."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time


def camera_less_scenario(source, out):
    path = os.path.join(out, "camera_less.yaml")
    with open(path, "w") as f:
        f.write("""# default.yaml's 55 m round trip, odometry only, no camera rendered.
include: %s
sensors:
  front: {enabled: false}
  lateral: {enabled: false}
  upward: {enabled: false}
pipelines:
  p1_harris: {enabled: false}
  p1_vp_doorplate: {enabled: false}
expectations: []
""" % os.path.join(source, "scenarios", "default.yaml"))
    return path


def only_divergences(out):
    """Whether the study's exit 1 means only that pipelines diverged: every run finished and
    summary.json counts diverged runs that fail it."""
    try:
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
            points = summary["points"]
    except (OSError, ValueError, KeyError):
        return False
    return summary.get("diverged_runs_failing", 0) > 0 and all(
        p["runs"]["failed"] == 0 and p["runs"]["timed_out"] == 0 and p["runs"]["not_run"] == 0
        for p in points)


def study(binary, scenario, runs, jobs, out):
    shutil.rmtree(out, ignore_errors=True)
    start = time.monotonic()
    done = subprocess.run([binary, "study", scenario, "--runs", str(runs), "--jobs", str(jobs),
                           "--out", out, "--no-plots"], capture_output=True, text=True)
    wall = time.monotonic() - start
    # Exit 1 with every run finished means only that a pipeline diverged (the study names it):
    # that is the filter's accuracy, not the study's speed, which is measured all the same.
    if done.returncode == 1 and only_divergences(out):
        at = done.stdout.find("run(s) diverged")
        print("bench_study: note: runs diverged with %d worker(s) (accuracy, not speed):\n%s" % (
            jobs, done.stdout[max(at, 0):][:1000]))
    elif done.returncode != 0:
        sys.exit("bench_study: the study with %d worker(s) exited %d:\n%s%s" % (
            jobs, done.returncode, done.stdout[-2000:], done.stderr[-2000:]))
    with open(os.path.join(out, "timing.json")) as f:
        timing = json.load(f)
    records = sorted(timing["runs"], key=lambda r: r["seed"])
    seconds = [r["wall_seconds"] for r in records]
    rss = [r["peak_rss_mib"] for r in records]
    tenth = max(1, len(rss) // 10)
    return {
        "jobs": jobs,
        "runs": runs,
        "wall_seconds": wall,
        "runs_per_hour": 3600.0 * runs / wall,
        "run_seconds_mean": sum(seconds) / len(seconds),
        "peak_rss_mib_max": max(rss),
        "peak_rss_mib_first_tenth": sum(rss[:tenth]) / tenth,
        "peak_rss_mib_last_tenth": sum(rss[-tenth:]) / tenth,
        "overhead_fraction": 1.0 - sum(seconds) / (jobs * wall),
        "summary_seconds": timing.get("summary_seconds"),
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    source = os.path.dirname(here)
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--corridorsim", default=os.path.join(source, "build", "bin", "corridorsim"))
    parser.add_argument("--runs", type=int, default=40)
    parser.add_argument("--out", default="out/bench_study")
    parser.add_argument("--scenario")
    args = parser.parse_args()
    if not 2 <= args.runs <= 10000:
        sys.exit("bench_study: --runs must lie in [2, 10000]")
    os.makedirs(args.out, exist_ok=True)
    scenario = args.scenario or camera_less_scenario(source, args.out)
    one = study(args.corridorsim, scenario, args.runs, 1, os.path.join(args.out, "j1"))
    two = study(args.corridorsim, scenario, args.runs, 2, os.path.join(args.out, "j2"))
    for name in ("summary.json", "summary.csv", "paired.csv"):
        with open(os.path.join(args.out, "j1", name), "rb") as a, \
                open(os.path.join(args.out, "j2", name), "rb") as b:
            if a.read() != b.read():
                sys.exit("bench_study: %s differs between 1 and 2 workers" % name)
    result = {"scenario": scenario, "cores": os.cpu_count(), "one_worker": one,
              "two_workers": two, "speedup": two["runs_per_hour"] / one["runs_per_hour"]}
    with open(os.path.join(args.out, "bench_study.json"), "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    print("study of %d runs of %s (%s cores)" % (args.runs, scenario, os.cpu_count()))
    print("%-10s %10s %12s %12s %14s %14s %10s" % ("workers", "wall s", "runs/hour", "run s mean",
                                                  "peak RSS MiB", "first/last", "overhead"))
    for r in (one, two):
        print("%-10d %10.1f %12.1f %12.2f %14.1f %7.1f/%-6.1f %9.2f%%" % (
            r["jobs"], r["wall_seconds"], r["runs_per_hour"], r["run_seconds_mean"],
            r["peak_rss_mib_max"], r["peak_rss_mib_first_tenth"], r["peak_rss_mib_last_tenth"],
            100.0 * r["overhead_fraction"]))
    print("throughput 2 workers / 1 worker: %.2fx (summaries identical)" % result["speedup"])


if __name__ == "__main__":
    main()
