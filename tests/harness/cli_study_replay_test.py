#!/usr/bin/env python3
"""A study whose points differ only in a pipeline option reuses renders (docs/studies.md,
"Replay instead of rendering"): a 2-point x 2-seed sweep of p1_vp_doorplate.k_m on a short
default.yaml gives, with replay (each seed rendered once by p000, recorded, replayed for p001)
and with --no-replay (every run renders), the same files byte for byte: every run folder's
metrics.json, trajectories, covariances and events, and the study's summary; the same file names
in every run folder (the recordings made for replay are removed); with --record every run
folder keeps its recording; two shards that replay within themselves merge to the same study; a
resumed study whose seed has no recording left renders the rest; points whose pipelines read
other cameras render every run.

Usage: cli_study_replay_test.py CORRIDORSIM SOURCE_DIR WORK_DIR"""

import json
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_test_support import NO_EXTRAS, fail, fresh_folder, read, run  # noqa: E402

POINTS = ("p000", "p001")
SEEDS = (3, 4)
SUMMARY_FILES = ("summary.json", "summary.csv", "paired.csv", "report.md")
# report.md names the command that made it (its --out): that line is left out.
MADE_BY = b"Made by `corridorsim study "
# What depends on the machine and the clock, not on the stream: left out of the comparison.
NOT_COMPARED = ("timing.json", "provenance.json")


def run_files(folder):
    return sorted(os.listdir(folder))


def compared_files(folder):
    return [name for name in run_files(folder)
            if name in ("metrics.json", "events.json")
            or name.endswith(".tum") or name.endswith("_cov.txt")]


def summary_bytes(path):
    return b"\n".join(line for line in read(path).split(b"\n") if not line.startswith(MADE_BY))


def same_studies(a, b):
    for name in SUMMARY_FILES:
        if summary_bytes(os.path.join(a, name)) != summary_bytes(os.path.join(b, name)):
            fail("%s differs between %s and %s" % (name, a, b))
    for point in POINTS:
        for seed in SEEDS:
            folder = os.path.join("runs", point, "seed_%d" % seed)
            fa, fb = os.path.join(a, folder), os.path.join(b, folder)
            if run_files(fa) != run_files(fb):
                fail("%s holds %s with replay, %s without" % (folder, run_files(fa),
                                                              run_files(fb)))
            names = compared_files(fa)
            if "metrics.json" not in names or not any(n.endswith("_cov.txt") for n in names):
                fail("%s lacks results: %s" % (fa, run_files(fa)))
            for name in names:
                if read(os.path.join(fa, name)) != read(os.path.join(fb, name)):
                    fail("%s/%s differs with replay and without" % (folder, name))


def status(study, point, seed):
    return json.loads(read(os.path.join(study, "status", point, "seed_%d.json" % seed)))


def main():
    binary, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
    fresh_folder(work)
    study = os.path.join(work, "sweep.yaml")
    with open(study, "w") as f:
        f.write("""include: %s
duration_s: 5
expectations: []  # default.yaml's hold for its round trip, not for 5 s of it
study:
  runs: 2
  first_seed: 3
  vary:
    pipelines.p1_vp_doorplate.k_m: [1.0e-4, 4.0e-4]
""" % os.path.join(source, "scenarios", "default.yaml"))

    # With replay: p000 renders and records each seed, p001 replays it; 2 workers, so that a
    # seed's replay runs while the other seed records.
    out = run(binary, ["study", study, "--jobs", "2", "--out", "replay", *NO_EXTRAS], 0, work)
    if "replayed for the other points" not in out.stdout or "(replayed)" not in out.stdout:
        fail("the study did not say it replays:\n" + out.stdout)
    replay = os.path.join(work, "replay")
    for seed in SEEDS:
        first, other = status(replay, "p000", seed), status(replay, "p001", seed)
        if first["stream"] != "recorded for replay" or \
                other["stream"] != "replayed from runs/p000/seed_%d/recording.mcap" % seed:
            fail("streams of seed %d: %s, %s" % (seed, first["stream"], other["stream"]))
        log = read(os.path.join(replay, "logs", "p001", "seed_%d.log" % seed)).decode()
        if "replay: " not in log:
            fail("p001 seed %d was not replayed:\n%s" % (seed, log[-2000:]))
        timing = json.loads(read(os.path.join(replay, "runs", "p001", "seed_%d" % seed,
                                              "timing.json")))
        if timing["stages_seconds"]["rendering"] != 0:
            fail("a replay rendered: %s" % timing["stages_seconds"])

    # Without replay: every run renders; the same bytes.
    out = run(binary, ["study", study, "--jobs", "2", "--out", "live", "--no-replay",
                       *NO_EXTRAS], 0, work)
    if "(replayed)" in out.stdout or "(recorded)" in out.stdout:
        fail("--no-replay replayed:\n" + out.stdout)
    live = os.path.join(work, "live")
    if status(live, "p001", 3)["stream"] != "live":
        fail("--no-replay's stream: %s" % status(live, "p001", 3))
    same_studies(replay, live)

    # --record: every run folder keeps a recording, the replayed ones too; results the same.
    run(binary, ["study", study, "--jobs", "2", "--out", "recorded", "--record", *NO_EXTRAS], 0,
        work)
    recorded = os.path.join(work, "recorded")
    for point in POINTS:
        for seed in SEEDS:
            folder = os.path.join(recorded, "runs", point, "seed_%d" % seed)
            if not os.path.isfile(os.path.join(folder, "recording.mcap")):
                fail("--record: %s has no recording.mcap" % folder)
            os.remove(os.path.join(folder, "recording.mcap"))
    if status(recorded, "p001", 4)["stream"] != "replayed from runs/p000/seed_4/recording.mcap":
        fail("--record did not replay: %s" % status(recorded, "p001", 4))
    same_studies(recorded, live)

    # Two shards (run k of the plan in shard k mod 2: each holds both points of one seed), each
    # replaying within itself, merged: the same study.
    for k in (1, 2):
        out = run(binary, ["study", study, "--shard", "%d/2" % k, "--out", "part%d" % k,
                           *NO_EXTRAS], 0, work)
        if "(replayed)" not in out.stdout:
            fail("shard %d did not replay:\n%s" % (k, out.stdout))
    run(binary, ["study", "merge", "part1", "part2", "--out", "merged", *NO_EXTRAS], 0, work)
    same_studies(os.path.join(work, "merged"), live)

    # Resumed with one replayed run lost: its seed's recording is gone, so it renders; the
    # study's files are the same again.
    lost = os.path.join(replay, "runs", "p001", "seed_4")
    shutil.rmtree(lost)
    os.remove(os.path.join(replay, "status", "p001", "seed_4.json"))
    out = run(binary, ["study", study, "--jobs", "2", "--out", "replay", *NO_EXTRAS], 0, work)
    if "3 already finished, 1 to run" not in out.stdout or \
            status(replay, "p001", 4)["stream"] != "live":
        fail("the resumed study:\n%s\n%s" % (out.stdout, status(replay, "p001", 4)))
    same_studies(replay, live)
    # Points whose pipelines read other cameras (a recording holds only the cameras its run
    # rendered): every run renders, and the study says why.
    cameras = os.path.join(work, "cameras.yaml")
    with open(cameras, "w") as f:
        f.write("""include: %s
duration_s: 2
expectations: []
study:
  runs: 1
  first_seed: 3
  vary:
    pipelines.p1_vp_doorplate.use_door_plates: [true, false]
""" % os.path.join(source, "scenarios", "default.yaml"))
    out = run(binary, ["study", cameras, "--out", "cameras", *NO_EXTRAS], 0, work)
    if "every run renders (p001's pipelines read the cameras front, p000's front, lateral)" \
            not in out.stdout or "(replayed)" in out.stdout:
        fail("a sweep of the cameras read replayed:\n" + out.stdout)
    print("ok")


if __name__ == "__main__":
    main()
