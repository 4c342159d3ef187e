#!/usr/bin/env python3
"""`corridorsim evaluate` at its documented maxima: peak memory (RSS) and wall time (issue 51).

Writes a synthetic run folder (a 100 s ground_truth.tum at 100 Hz on a circle: evaluate reads
nothing else without --frame or --landmarks) and one estimate of POSES poses following it, every
pose associated (10 us apart, --max-dt 0.01), then runs

    corridorsim evaluate RUN --estimate mine=FILE [--align se3] --out OUT --no-plots

under /usr/bin/time -v (or wait4 where it is missing) and prints the peak RSS and the time. The
estimate is TUM by default, or ov_eval (--ov-eval: 20 columns, as many poses as fit in the 1 GiB
file bound). docs/evaluation.md ("Memory") states the bound these figures meet.

    scripts/bench_evaluate.py [--corridorsim build/bin/corridorsim] [--poses 10000000]
                              [--ov-eval] [--align none] [--out out/bench_evaluate]

Standard library only. Speed and memory are measured here, never asserted by a test."""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

TRUTH_HZ = 100
TRUTH_S = 100


def pose_line(t, covariance):
    a = 2 * math.pi * t / TRUTH_S
    x, y = 10 * math.cos(a), 10 * math.sin(a)
    yaw = a + math.pi / 2
    line = "%.6f %.4f %.4f 0 0 0 %.6f %.6f" % (t, x, y, math.sin(yaw / 2), math.cos(yaw / 2))
    if covariance:
        line += " 1e-4 0 0 1e-4 0 1e-4 0.01 0 0 0.01 0 0.01"
    return line + "\n"


def write_truth(run):
    os.makedirs(run, exist_ok=True)
    with open(os.path.join(run, "ground_truth.tum"), "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for k in range(TRUTH_S * TRUTH_HZ + 1):
            f.write(pose_line(k / TRUTH_HZ, False))


def write_estimate(path, poses, covariance):
    # Stamps 10 us apart from 0.000010 s (every one within 5 ms of a truth stamp): 10 M poses
    # span 100 s. Lines are built in blocks (Python writes ~1 M lines in a few seconds).
    step = TRUTH_S / poses
    with open(path, "w") as f:
        block = []
        for k in range(1, poses + 1):
            block.append(pose_line(k * step, covariance))
            if len(block) == 100000:
                f.write("".join(block))
                block = []
        f.write("".join(block))


def measure(command):
    """(exit code, peak RSS in bytes, wall seconds, stdout+stderr)."""
    start = time.monotonic()
    if os.path.exists("/usr/bin/time"):
        done = subprocess.run(["/usr/bin/time", "-v"] + command, capture_output=True, text=True)
        wall = time.monotonic() - start
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)
        return done.returncode, int(m.group(1)) * 1024 if m else -1, wall, done.stdout + done.stderr
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    output = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    return (os.waitstatus_to_exitcode(status), usage.ru_maxrss * 1024, time.monotonic() - start,
            output)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--corridorsim", default="build/bin/corridorsim")
    parser.add_argument("--poses", type=int, default=10_000_000)
    parser.add_argument("--ov-eval", action="store_true")
    parser.add_argument("--align", default="none")
    parser.add_argument("--out", default="out/bench_evaluate")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    run = os.path.join(args.out, "run")
    write_truth(run)
    estimate = os.path.join(args.out, "mine.txt" if args.ov_eval else "mine.tum")
    t0 = time.monotonic()
    write_estimate(estimate, args.poses, args.ov_eval)
    size = os.path.getsize(estimate)
    print("estimate: %d poses, %s, %.1f MiB (written in %.0f s)" % (
        args.poses, "ov_eval" if args.ov_eval else "TUM", size / 2**20, time.monotonic() - t0))
    out = os.path.join(args.out, "evaluation")
    shutil.rmtree(out, ignore_errors=True)
    command = [args.corridorsim, "evaluate", run, "--estimate", "mine=" + estimate, "--align",
               args.align, "--out", out, "--no-plots"]
    code, rss, wall, output = measure(command)
    if code != 0:
        sys.exit("evaluate exited %d:\n%s" % (code, output[-3000:]))
    result = {"poses": args.poses, "format": "ov_eval" if args.ov_eval else "tum",
              "file_bytes": size, "align": args.align, "peak_rss_bytes": rss,
              "bytes_per_pose": round(rss / args.poses, 1), "wall_s": round(wall, 1)}
    print("peak RSS %.0f MiB (%.0f bytes per pose), %.1f s" % (
        rss / 2**20, rss / args.poses, wall))
    with open(os.path.join(args.out, "bench_evaluate.json"), "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
