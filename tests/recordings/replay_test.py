#!/usr/bin/python3
"""recording.replay.<scenario>: a short live run with --record, then `corridorsim replay` of its
recording: the two run folders hold the same files, byte for byte, except what says how the run
was made (timing.json, provenance.json, maps/*_frame_times.csv: wall-clock time per frame) and the
recording itself. With --also-without-record, a third run without --record must equal them too
(recording changes nothing), and a replay with SCENARIO given (not the recording's own) too.

With --plugin LIB, the scenario gets the plugin library and a pipeline of its `test_echo` type
(tests/plugins/echo_plugin.cpp) beside its own: a plugin replays as a built-in pipeline does.

Usage: replay_test.py CORRIDORSIM SCENARIO WORK_DIR DURATION_S [--also-without-record]
                      [--plugin LIB]
"""
import filecmp
import os
import shutil
import subprocess
import sys

NOT_COMPARED = {"timing.json", "provenance.json", "recording.mcap", "recording.bag",
                ".corridorsim-output"}


def run(argv):
    result = subprocess.run(argv, capture_output=True, text=True)
    if result.returncode not in (0, 3, 5):
        sys.exit("replay_test: %s exited %d:\n%s%s" % (" ".join(argv), result.returncode,
                                                       result.stdout[-3000:], result.stderr[-3000:]))
    return result.returncode


def files(folder):
    found = []
    for root, _, names in os.walk(folder):
        for name in names:
            rel = os.path.relpath(os.path.join(root, name), folder)
            if name in NOT_COMPARED or name.endswith("_frame_times.csv"):
                continue
            found.append(rel)
    return sorted(found)


def compare(a, b, what):
    fa, fb = files(a), files(b)
    if fa != fb:
        sys.exit("replay_test: %s: different files: %s" % (what, sorted(set(fa) ^ set(fb))))
    for rel in fa:
        if not filecmp.cmp(os.path.join(a, rel), os.path.join(b, rel), shallow=False):
            sys.exit("replay_test: %s: %s differs" % (what, rel))
    return len(fa)


def main():
    corridorsim, scenario, work, duration = sys.argv[1:5]
    also = "--also-without-record" in sys.argv[5:]
    shutil.rmtree(work, ignore_errors=True)
    if "--plugin" in sys.argv[5:]:
        plugin = sys.argv[sys.argv.index("--plugin") + 1]
        os.makedirs(work)
        with_plugin = os.path.join(work, "with_plugin.yaml")
        with open(with_plugin, "w") as f:
            f.write("include: %s\nplugins:\n  - %s\npipelines:\n  echo: {type: test_echo}\n"
                    % (os.path.abspath(scenario), plugin))
        scenario = with_plugin
    common = ["--set", "duration_s=" + duration, "--no-plots", "--no-viewer"]
    live = os.path.join(work, "live")
    code_live = run([corridorsim, "run", scenario, "--record", "--out", live] + common)
    replay = os.path.join(work, "replay")
    code_replay = run([corridorsim, "replay", os.path.join(live, "recording.mcap"), "--out", replay,
                       "--no-plots", "--no-viewer"])
    if code_replay != code_live:
        sys.exit("replay_test: the live run exited %d, the replay %d" % (code_live, code_replay))
    n = compare(live, replay, "live vs replay")
    if also:
        # A replay with the scenario given explicitly reads the same stream.
        explicit = os.path.join(work, "replay_explicit")
        run([corridorsim, "replay", os.path.join(live, "recording.mcap"), scenario, "--set",
             "duration_s=" + duration, "--out", explicit, "--no-plots", "--no-viewer"])
        compare(live, explicit, "live vs replay with the scenario given")
        plain = os.path.join(work, "plain")
        run([corridorsim, "run", scenario, "--out", plain] + common)
        compare(live, plain, "run --record vs run")
    print("replay_test: ok: %s, %s s: %d files byte-identical" % (os.path.basename(scenario), duration, n))


if __name__ == "__main__":
    main()
