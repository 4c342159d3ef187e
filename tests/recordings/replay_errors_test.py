#!/usr/bin/python3
"""recording.replay_errors: what replay refuses, each with exit code 2 and one message naming the
problem (docs/recordings.md, "Replay"): a missing file, a file that is not MCAP, a recording cut
short, a corrupt chunk (its record and byte offset), a scenario whose stream differs (the first
key), another seed, a pipeline whose camera was not recorded, a recording without corridorsim's
truth, an output folder that holds the recording. Nothing is written by a refused replay.

Usage: replay_errors_test.py CORRIDORSIM SOURCE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys


def run(argv):
    return subprocess.run(argv, capture_output=True, text=True)


def expect_refused(argv, *needles):
    result = run(argv)
    if result.returncode != 2:
        sys.exit("replay_errors_test: %s exited %d, expected 2:\n%s%s" % (
            " ".join(argv), result.returncode, result.stdout[-2000:], result.stderr[-2000:]))
    lines = [l for l in result.stderr.splitlines() if l.strip()]
    if len(lines) != 1:
        sys.exit("replay_errors_test: %s: expected one line on stderr, got:\n%s" % (" ".join(argv), result.stderr))
    for needle in needles:
        if needle not in lines[0]:
            sys.exit("replay_errors_test: %s: %r not in %r" % (" ".join(argv), needle, lines[0]))
    print("refused as expected: " + lines[0][:200])


def main():
    corridorsim, source, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    default = os.path.join(source, "scenarios", "default.yaml")
    live = os.path.join(work, "live")
    common = ["--set", "duration_s=2", "--no-plots", "--no-viewer"]
    result = run([corridorsim, "run", default, "--record", "--out", live] + common)
    if result.returncode not in (0, 3):
        sys.exit("replay_errors_test: the recording run failed:\n" + result.stderr)
    recording = os.path.join(live, "recording.mcap")
    out = os.path.join(work, "out")
    replay = [corridorsim, "replay"]

    expect_refused(replay + [os.path.join(work, "nothing.mcap"), "--out", out], "nothing.mcap", "no such recording")
    text = os.path.join(work, "text.mcap")
    with open(text, "w") as f:
        f.write("not an MCAP file at all\n")
    expect_refused(replay + [text, "--out", out], "text.mcap")
    data = open(recording, "rb").read()
    cut = os.path.join(work, "cut.mcap")
    with open(cut, "wb") as f:
        f.write(data[: len(data) // 2])
    expect_refused(replay + [cut, "--out", out], "cut.mcap", "cut short")
    # A flipped byte in the middle of the data section: a chunk's CRC or its compressed stream.
    corrupt = os.path.join(work, "corrupt.mcap")
    broken = bytearray(data)
    for i in range(len(data) // 3, len(data) // 3 + 64):
        broken[i] ^= 0x5A
    with open(corrupt, "wb") as f:
        f.write(bytes(broken))
    expect_refused(replay + [corrupt, "--out", out], "corrupt.mcap", "at byte")
    expect_refused(replay + [recording, default, "--set", "duration_s=2", "--set",
                             "world.length_m=60", "--out", out], "world.length_m")
    expect_refused(replay + [recording, "--seed", "2", "--out", out], "--seed")
    expect_refused(replay + [recording, "--out", live, "--force"], "recording")
    # A run whose pipelines read no camera renders none: P1's pipelines cannot replay on it.
    wheels = os.path.join(work, "wheels")
    wheels_yaml = os.path.join(work, "wheels.yaml")
    with open(wheels_yaml, "w") as f:
        f.write("include: %s\npipelines:\n  p1_harris: {enabled: false}\n"
                "  p1_vp_doorplate: {enabled: false}\nexpectations: []\n" % default)
    result = run([corridorsim, "run", wheels_yaml, "--record", "--out", wheels] + common)
    if result.returncode not in (0, 3):
        sys.exit("replay_errors_test: the wheels-only run failed:\n" + result.stderr)
    expect_refused(replay + [os.path.join(wheels, "recording.mcap"), default, "--set", "duration_s=2",
                             "--out", out], "camera 'front'")
    # Recorded without corridorsim's truth: not a recording replay can score.
    no_truth = os.path.join(work, "no_truth")
    result = run([corridorsim, "run", default, "--record", "--record-topics", "/front/*,/tf*",
                  "--out", no_truth] + common)
    if result.returncode not in (0, 3):
        sys.exit("replay_errors_test: the filtered run failed:\n" + result.stderr)
    expect_refused(replay + [os.path.join(no_truth, "recording.mcap"), "--out", out],
                   "not a corridorsim recording")
    # Without the lateral camera's topics: refused, naming the topic.
    no_lateral = os.path.join(work, "no_lateral")
    result = run([corridorsim, "run", default, "--record", "--record-topics",
                  "/front/*,/corridorsim/truth,/corridorsim/wheel_odometry,/corridorsim/front/*,"
                  "/corridorsim/camera_set,/corridorsim/events", "--out", no_lateral] + common)
    if result.returncode not in (0, 3):
        sys.exit("replay_errors_test: the filtered run failed:\n" + result.stderr)
    expect_refused(replay + [os.path.join(no_lateral, "recording.mcap"), "--out", out],
                   "/lateral/image_raw")
    if os.path.exists(out):
        sys.exit("replay_errors_test: a refused replay wrote " + out)
    print("replay_errors_test: ok")


if __name__ == "__main__":
    main()
