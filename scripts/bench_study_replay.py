#!/usr/bin/env python3
"""What replay saves a study (issue 54's figure; docs/studies.md, "Replay instead of rendering"):
a sweep of one P1 option (pipelines.p1_vp_doorplate.k_m, 5 values) over 4 seeds of
scenarios/default.yaml cut to --duration seconds, run as a study with replay (each seed rendered
once and recorded, replayed for the other 4 points) and with --no-replay (all 20 runs render), in
one invocation on the same machine. Prints both wall times and their ratio, checks that both
studies wrote the same summary and run results, and breaks the replayed runs' time down by stage
(their timing.json) against the rendered runs'.

    scripts/bench_study_replay.py [--corridorsim build/bin/corridorsim] [--duration 30]
                                  [--points 5] [--runs 4] [--jobs 2] [--out out/bench_replay]
                                  [--order live-first|replay-first]
                                  [--set KEY=VALUE ...]  (passed to both studies)

Writes OUT/bench_study_replay.json. Standard library only. Speed is measured here, never
asserted by a test (cli.study_replay_same_files checks the files)."""
import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time

STAGES = ("setup", "physics", "rendering", "pipelines", "pipelines_wait", "metrics", "writing",
          "recording")
COMPARED_SUFFIXES = (".tum", "_cov.txt")
COMPARED_NAMES = ("metrics.json", "events.json")


def study_file(source, out, duration, points):
    values = ", ".join("%.1e" % (1e-4 * (1 + i)) for i in range(points))
    path = os.path.join(out, "sweep.yaml")
    with open(path, "w") as f:
        f.write("""# A sweep of P1's odometry noise k (pipelines.p1_vp_doorplate.k_m) on default.yaml:
# the points differ only in a pipeline option, so they share one sensor stream per seed.
include: %s
duration_s: %g
expectations: []  # default.yaml's hold for its whole round trip
study:
  vary:
    pipelines.p1_vp_doorplate.k_m: [%s]
""" % (os.path.join(source, "scenarios", "default.yaml"), duration, values))
    return path


def run_study(binary, scenario, args, out, replay):
    shutil.rmtree(out, ignore_errors=True)
    command = [binary, "study", scenario, "--runs", str(args.runs), "--jobs", str(args.jobs),
               "--out", out, "--no-plots", "--no-viewer"]
    for setting in args.set or []:
        command += ["--set", setting]
    if not replay:
        command.append("--no-replay")
    start = time.monotonic()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(command, capture_output=True, text=True)
    wall = time.monotonic() - start
    # CPU seconds of the study and every run it waited for: on a machine that others share, a
    # steadier measure of the work than the wall clock.
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    # 1 with every run finished: a baseline-free pipeline diverged (accuracy, not speed).
    if done.returncode not in (0, 1):
        sys.exit("bench_study_replay: %s exited %d:\n%s%s" % (
            " ".join(command), done.returncode, done.stdout[-3000:], done.stderr[-3000:]))
    with open(os.path.join(out, "timing.json")) as f:
        timing = json.load(f)
    if any(r["outcome"] != "finished" for r in timing["runs"]):
        sys.exit("bench_study_replay: a run of %s did not finish:\n%s" % (out, done.stdout[-3000:]))
    return {"command": " ".join(command), "exit_code": done.returncode, "wall_seconds": wall,
            "cpu_seconds": cpu, "timing": timing}


def kind(record):
    stream = record.get("stream", "live")
    return "replayed" if stream.startswith("replayed") else \
        "recorded" if stream.startswith("recorded") else "live"


def breakdown(out, timing):
    """Per kind of run (live, recorded, replayed): count, mean wall seconds as the study saw it,
    the mean of each stage of the runs' own timing.json, and the mean CPU seconds spent inside
    the pipelines (their timing.json's pipelines.<name>.cpu_seconds): what a replay cannot save."""
    kinds = {}
    for r in timing["runs"]:
        folder = os.path.join(out, "runs", r["point"], "seed_%d" % r["seed"])
        with open(os.path.join(folder, "timing.json")) as f:
            run_timing = json.load(f)
        stages = run_timing["stages_seconds"]
        k = kinds.setdefault(kind(r), {"runs": 0, "wall_seconds": 0.0,
                                       "pipelines_cpu_seconds": 0.0,
                                       "stages_seconds": {s: 0.0 for s in STAGES}})
        k["runs"] += 1
        k["wall_seconds"] += r["wall_seconds"]
        k["pipelines_cpu_seconds"] += sum(p.get("cpu_seconds") or 0.0
                                          for p in run_timing["pipelines"].values())
        for s in STAGES:
            k["stages_seconds"][s] += stages.get(s, 0.0)
    for k in kinds.values():
        k["wall_seconds"] /= k["runs"]
        k["pipelines_cpu_seconds"] /= k["runs"]
        for s in STAGES:
            k["stages_seconds"][s] /= k["runs"]
    return kinds


def same_results(a, b, timing):
    for name in ("summary.json", "summary.csv", "paired.csv"):
        with open(os.path.join(a, name), "rb") as x, open(os.path.join(b, name), "rb") as y:
            if x.read() != y.read():
                sys.exit("bench_study_replay: %s differs with replay and without" % name)
    for r in timing["runs"]:
        folder = os.path.join("runs", r["point"], "seed_%d" % r["seed"])
        names = sorted(os.listdir(os.path.join(a, folder)))
        if names != sorted(os.listdir(os.path.join(b, folder))):
            sys.exit("bench_study_replay: %s holds other files with replay" % folder)
        for name in names:
            if name in COMPARED_NAMES or name.endswith(COMPARED_SUFFIXES):
                with open(os.path.join(a, folder, name), "rb") as x, \
                        open(os.path.join(b, folder, name), "rb") as y:
                    if x.read() != y.read():
                        sys.exit("bench_study_replay: %s/%s differs with replay" % (folder, name))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    source = os.path.dirname(here)
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--corridorsim", default=os.path.join(source, "build", "bin", "corridorsim"))
    parser.add_argument("--duration", type=float, default=30.0)
    parser.add_argument("--points", type=int, default=5)
    parser.add_argument("--runs", type=int, default=4)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="out/bench_replay")
    parser.add_argument("--order", choices=("live-first", "replay-first"), default="live-first")
    parser.add_argument("--set", action="append", metavar="KEY=VALUE")
    args = parser.parse_args()
    if not (1 <= args.duration <= 3600 and 2 <= args.points <= 100 and 1 <= args.runs <= 100 and
            1 <= args.jobs <= 256):
        sys.exit("bench_study_replay: --duration in [1, 3600], --points in [2, 100], --runs in "
                 "[1, 100], --jobs in [1, 256]")
    os.makedirs(args.out, exist_ok=True)
    scenario = study_file(source, args.out, args.duration, args.points)
    live_dir, replay_dir = os.path.join(args.out, "live"), os.path.join(args.out, "replay")
    if args.order == "live-first":
        live = run_study(args.corridorsim, scenario, args, live_dir, False)
        replay = run_study(args.corridorsim, scenario, args, replay_dir, True)
    else:
        replay = run_study(args.corridorsim, scenario, args, replay_dir, True)
        live = run_study(args.corridorsim, scenario, args, live_dir, False)
    if not any(kind(r) == "replayed" for r in replay["timing"]["runs"]):
        sys.exit("bench_study_replay: the study did not replay (see %s/logs)" % replay_dir)
    same_results(replay_dir, live_dir, replay["timing"])
    ratio = live["wall_seconds"] / replay["wall_seconds"]
    cpu_ratio = live["cpu_seconds"] / replay["cpu_seconds"]
    # The most replay could give if replaying cost nothing but the pipelines and recording
    # nothing: every point but one pays only its pipelines' CPU time.
    live_runs = breakdown(live_dir, live["timing"])["live"]
    run_cpu = live["cpu_seconds"] / live_runs["runs"]
    bound = args.points * run_cpu / (run_cpu + (args.points - 1) *
                                     live_runs["pipelines_cpu_seconds"])
    result = {
        "scenario": scenario, "duration_s": args.duration, "points": args.points,
        "runs": args.runs, "jobs": args.jobs, "cores": os.cpu_count(), "order": args.order,
        "load_average_at_end": os.getloadavg(),
        "no_replay": {"command": live["command"], "wall_seconds": live["wall_seconds"],
                      "cpu_seconds": live["cpu_seconds"],
                      "runs": breakdown(live_dir, live["timing"])},
        "replay": {"command": replay["command"], "wall_seconds": replay["wall_seconds"],
                   "cpu_seconds": replay["cpu_seconds"],
                   "runs": breakdown(replay_dir, replay["timing"])},
        "ratio": ratio,
        "cpu_ratio": cpu_ratio,
        "ratio_bound_pipelines_only": bound,
    }
    with open(os.path.join(args.out, "bench_study_replay.json"), "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    print("%d-point sweep of pipelines.p1_vp_doorplate.k_m x %d seeds, %g s of default.yaml, "
          "--jobs %d, %d cores" % (args.points, args.runs, args.duration, args.jobs,
                                   os.cpu_count()))
    print("%-12s %10s %10s" % ("", "wall s", "CPU s"))
    print("%-12s %10.1f %10.1f" % ("--no-replay", live["wall_seconds"], live["cpu_seconds"]))
    print("%-12s %10.1f %10.1f" % ("replay", replay["wall_seconds"], replay["cpu_seconds"]))
    print("%-12s %9.2fx %9.2fx (summaries and run results identical)" % ("ratio", ratio,
                                                                           cpu_ratio))
    print("bound: %.2fx if a replay cost only its pipelines' CPU time (%.2f s of a live run's "
          "%.2f CPU s) and recording cost nothing" % (bound, live_runs["pipelines_cpu_seconds"],
                                                      run_cpu))
    print("\nmean seconds per run by kind (the runs' timing.json; pipelines CPU: their "
          "cpu_seconds):")
    print("%-22s %5s %8s %9s " % ("study / kind", "runs", "wall", "pipe CPU") +
          " ".join("%9s" % s[:9] for s in STAGES))
    for label, study in (("no-replay", result["no_replay"]), ("replay", result["replay"])):
        for name, k in sorted(study["runs"].items()):
            print("%-22s %5d %8.2f %9.2f " % (label + " / " + name, k["runs"], k["wall_seconds"],
                                              k["pipelines_cpu_seconds"]) +
                  " ".join("%9.2f" % k["stages_seconds"][s] for s in STAGES))


if __name__ == "__main__":
    main()
