#!/usr/bin/python3
"""Checks every shipped scenario's expectations over many seeds (not in CI: hours of runs).

An expectation in a shipped scenario is a claim about a system under test that holds on at least
99 % of seeds (issue 36). This script runs each scenario as a study over seeds A-B (default
1-30, `corridorsim study` with `--no-plots`), reads every run's metrics.json and reports, per
expectation, how many seeds passed, the measured values (worst, mean, standard deviation) and the
margin to the bound; and per pipeline with doors, the door landmarks registered on a closed
doorway or on no doorway at all (cabinets, bookshelves, walls), which must be none.

Usage:
  /usr/bin/python3 scripts/check_expectations.py [--bin build/bin/corridorsim] [--seeds 1-30]
      [--jobs 2] [--out out/expectations] [scenarios/x.yaml ...]

Without scenario arguments: every scenarios/*.yaml with at least one expectation. A study folder
left by an earlier call is resumed (finished runs are skipped; `corridorsim study` refuses a
folder of another build, then use a new --out). Writes <out>/expectations.json and prints a
table. Exit 0 when every expectation passed on every seed and no pipeline registered a closed
door or a non-door; 1 otherwise; 2 on bad arguments.
"""

import argparse
import glob
import json
import math
import os
import re
import subprocess
import sys

DOOR_KEYS = ("closed_registered", "non_door_registered")


def parse_seeds(text):
    m = re.fullmatch(r"(\d{1,9})-(\d{1,9})", text)
    if not m or int(m.group(1)) > int(m.group(2)) or int(m.group(2)) - int(m.group(1)) >= 10000:
        raise argparse.ArgumentTypeError("expected A-B with A <= B and at most 10000 seeds, got '%s'"
                                         % text)
    return int(m.group(1)), int(m.group(2))


def check_summary(binary, scenario):
    result = subprocess.run([binary, "run", scenario, "--check"], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("check_expectations: %s does not load:\n%s" % (scenario, result.stderr.strip()))
    m = re.search(r"(\d+) expectation\(s\)", result.stdout)
    return int(m.group(1)) if m else 0


def run_study(binary, scenario, first, last, jobs, out):
    """Runs the scenario over seeds first..last as a study (a study file that includes it) into
    `out`; returns the run folders' metrics.json paths by seed (missing: the run failed)."""
    os.makedirs(out, exist_ok=True)
    study_file = os.path.join(out, "study.yaml")
    with open(study_file, "w") as f:
        f.write("# Written by scripts/check_expectations.py\n")
        f.write("include: %s\n" % json.dumps(os.path.abspath(scenario)))
        f.write("study:\n  first_seed: %d\n  runs: %d\n" % (first, last - first + 1))
    folder = os.path.join(out, "study")
    command = [binary, "study", study_file, "--jobs", str(jobs), "--no-plots", "--out", folder]
    print("check_expectations: " + " ".join(command), flush=True)
    result = subprocess.run(command, capture_output=True, text=True)
    # 0: passed; 1: a run failed or a pipeline diverged; 3: a study expectation failed. Each run's
    # own expectations are read from its metrics.json either way.
    if result.returncode not in (0, 1, 3):
        sys.exit("check_expectations: the study of %s exited %d:\n%s" %
                 (scenario, result.returncode, result.stderr.strip()[-3000:]))
    found = {}
    for seed in range(first, last + 1):
        hits = glob.glob(os.path.join(folder, "runs", "*", "seed_%d" % seed, "metrics.json"))
        found[seed] = hits[0] if hits else None
    return found


def summarise(values):
    finite = [v for v in values if v is not None and math.isfinite(v)]
    if not finite:
        return None, None, None
    mean = sum(finite) / len(finite)
    std = math.sqrt(sum((v - mean) ** 2 for v in finite) / (len(finite) - 1)) if len(finite) > 1 else 0.0
    return mean, std, finite


def check_scenario(scenario, runs):
    """Per expectation: seeds passed, failed (with their seeds), measured values; per pipeline:
    closed and non-door registrations."""
    expectations = {}
    doors = {}
    missing = [seed for seed, path in runs.items() if path is None]
    for seed, path in sorted(runs.items()):
        if path is None:
            continue
        with open(path) as f:
            metrics = json.load(f)
        for e in metrics.get("expectations", []):
            entry = expectations.setdefault(e["text"], {"passed": 0, "failed_seeds": [], "measured": []})
            if e.get("passed"):
                entry["passed"] += 1
            else:
                entry["failed_seeds"].append(seed)
            entry["measured"].append(e.get("measured"))
        for name, pipeline in metrics.get("pipelines", {}).items():
            door = pipeline.get("map", {}).get("door") if isinstance(pipeline.get("map"), dict) else None
            if not isinstance(door, dict):
                continue
            counts = doors.setdefault(name, {k: 0 for k in DOOR_KEYS} | {"seeds": []})
            wrong = 0
            for k in DOOR_KEYS:
                n = door.get(k) or 0
                counts[k] += n
                wrong += n
            if wrong:
                counts["seeds"].append(seed)
    return {"missing_runs": missing, "expectations": expectations, "doors": doors}


def bound_of(text):
    m = re.search(r"(<=|>=|<|>)\s*(\S+)\s*$", text)
    return (m.group(1), float(m.group(2))) if m else (None, None)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenarios", nargs="*")
    parser.add_argument("--bin", default="build/bin/corridorsim")
    parser.add_argument("--seeds", type=parse_seeds, default=(1, 30))
    parser.add_argument("--jobs", type=int, default=2, choices=range(1, 65), metavar="1..64")
    parser.add_argument("--out", default="out/expectations")
    args = parser.parse_args()
    if not os.access(args.bin, os.X_OK):
        parser.error("--bin: %s is not an executable" % args.bin)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    scenarios = args.scenarios or sorted(glob.glob(os.path.join(root, "scenarios", "*.yaml")))
    first, last = args.seeds
    report = {"seeds": [first, last], "scenarios": {}}
    ok = True
    for scenario in scenarios:
        if not os.path.isfile(scenario):
            parser.error("no such scenario file: %s" % scenario)
        if check_summary(args.bin, scenario) == 0:
            print("check_expectations: %s has no expectations; skipped" % scenario)
            continue
        stem = os.path.splitext(os.path.basename(scenario))[0]
        runs = run_study(args.bin, scenario, first, last, args.jobs, os.path.join(args.out, stem))
        result = check_scenario(scenario, runs)
        report["scenarios"][stem] = result
        print("\n## %s (seeds %d-%d)" % (stem, first, last))
        if result["missing_runs"]:
            ok = False
            print("  runs that wrote no metrics (failed): seeds %s" % result["missing_runs"])
        print("  %-58s %7s %10s %10s %10s %10s" % ("expectation", "passed", "worst", "mean", "std",
                                                    "margin"))
        for text, e in result["expectations"].items():
            op, bound = bound_of(text)
            mean, std, finite = summarise(e["measured"])
            worst = None
            if finite:
                worst = max(finite) if op in ("<", "<=") else min(finite)
            margin = (bound - worst if op in ("<", "<=") else worst - bound) if worst is not None else None
            e.update({"mean": mean, "std": std, "worst": worst, "margin": margin})
            fmt = lambda v: "%10.4g" % v if v is not None else "%10s" % "-"
            print("  %-58s %3d/%-3d %s %s %s %s" % (text[:58], e["passed"], len(e["measured"]),
                                                   fmt(worst), fmt(mean), fmt(std), fmt(margin)))
            if e["failed_seeds"]:
                ok = False
                print("    FAILED on seeds %s" % e["failed_seeds"])
        for name, counts in result["doors"].items():
            print("  %s: %d door landmark(s) on a closed doorway, %d on no doorway%s" % (
                name, counts["closed_registered"], counts["non_door_registered"],
                " (seeds %s)" % counts["seeds"] if counts["seeds"] else ""))
            if counts["seeds"]:
                ok = False
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "expectations.json"), "w") as f:
        json.dump(report, f, indent=1, sort_keys=True)
    print("\ncheck_expectations: %s (%s)" % ("every expectation held" if ok else "FAILED",
                                             os.path.join(args.out, "expectations.json")))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
