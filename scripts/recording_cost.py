#!/usr/bin/python3
"""Measures what --record costs a run and what a replay saves (issue 54; docs/recordings.md).

Runs a scenario (default: scenarios/default.yaml, the whole round trip) without and with --record,
alternating, `--repeats` times each; then replays the last recording. Prints, and writes to
<out>/recording_cost.json: the fastest wall time of each, the overhead of recording (ratio of the
fastest times, and the recorder's own stage seconds from timing.json), the recording's size and
and the replay's wall time and speed-up. It also checks that the replay's
metrics.json and trajectories equal the live run's, byte for byte. Wall clock: compare figures of
one invocation only, on a machine as idle as you can make it.

Usage:
  /usr/bin/python3 scripts/recording_cost.py [--bin build/bin/corridorsim]
      [--scenario scenarios/default.yaml] [--set KEY=VALUE ...] [--repeats 2]
      [--compression zstd] [--out out/recording_cost]

Exit 0; 1 when a run fails or the replay differs; 2 on bad arguments.
"""

import argparse
import filecmp
import json
import os
import shutil
import subprocess
import sys
import time


def run(argv):
    t0 = time.monotonic()
    result = subprocess.run(argv, capture_output=True, text=True)
    seconds = time.monotonic() - t0
    if result.returncode not in (0, 3):
        print("recording_cost: %s exited %d:\n%s" % (" ".join(argv), result.returncode,
                                                     result.stderr[-2000:]), file=sys.stderr)
        sys.exit(1)
    return seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default="build/bin/corridorsim")
    parser.add_argument("--scenario", default="scenarios/default.yaml")
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--compression", default="zstd", choices=["zstd", "lz4", "none"])
    parser.add_argument("--out", default="out/recording_cost")
    args = parser.parse_args()
    if not 1 <= args.repeats <= 10:
        parser.error("--repeats must be in [1, 10]")
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    sets = sum((["--set", s] for s in args.set), [])
    common = [args.scenario, "--no-plots", "--no-viewer", "--force"] + sets
    plain, recorded = [], []
    for i in range(args.repeats):
        plain.append(run([args.bin, "run"] + common + ["--out", os.path.join(args.out, "plain")]))
        recorded.append(run([args.bin, "run"] + common + [
            "--out", os.path.join(args.out, "recorded"), "--record", "--record-compression",
            args.compression]))
        print("repeat %d: without --record %.1f s, with %.1f s" % (i + 1, plain[-1], recorded[-1]))
    live = os.path.join(args.out, "recorded")
    recording = os.path.join(live, "recording.mcap")
    with open(os.path.join(live, "timing.json")) as f:
        timing = json.load(f)
    replay_dir = os.path.join(args.out, "replay")
    replay_s = run([args.bin, "replay", recording, "--no-plots", "--no-viewer", "--force",
                    "--out", replay_dir])
    with open(os.path.join(replay_dir, "timing.json")) as f:
        replay_timing = json.load(f)
    same = [n for n in sorted(os.listdir(live))
            if (n == "metrics.json" or n.endswith(".tum") or n.endswith("_cov.txt"))]
    differs = [n for n in same if not filecmp.cmp(os.path.join(live, n), os.path.join(replay_dir, n),
                                                  shallow=False)]
    size = os.path.getsize(recording)
    result = {
        "scenario": args.scenario, "settings": args.set, "compression": args.compression,
        "sim_seconds": timing["sim_seconds"],
        "wall_seconds_without_record": min(plain), "wall_seconds_with_record": min(recorded),
        "record_overhead": min(recorded) / min(plain) - 1.0,
        "recording_stage_seconds": timing["stages_seconds"].get("recording"),
        "recording_bytes": size,
        "recording_mb_per_sim_second": size / 1e6 / timing["sim_seconds"],
        "replay_wall_seconds": replay_s, "replay_speedup": min(plain) / replay_s,
        "replay_stages_seconds": replay_timing["stages_seconds"],
        "replay_files_compared": same, "replay_files_differing": differs,
    }
    with open(os.path.join(args.out, "recording_cost.json"), "w") as f:
        json.dump(result, f, indent=2)
    print("| | wall s | |\n|---|---:|---|")
    print("| run | %.1f | fastest of %d |" % (min(plain), args.repeats))
    print("| run --record (%s) | %.1f | +%.1f %% |" % (args.compression, min(recorded),
                                                      100 * result["record_overhead"]))
    print("| replay | %.1f | %.1fx faster than the run |" % (replay_s, result["replay_speedup"]))
    print("recording: %.1f MB (%.2f MB per simulated second of %.1f s)" % (
        size / 1e6, result["recording_mb_per_sim_second"], timing["sim_seconds"]))
    if differs:
        print("recording_cost: the replay's %s differ from the live run's" % ", ".join(differs),
              file=sys.stderr)
        sys.exit(1)
    print("replay: %s byte-identical to the live run's" % ", ".join(same))


if __name__ == "__main__":
    main()
