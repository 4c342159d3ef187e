#!/usr/bin/python3
"""External pipelines as a user meets them (docs/protocol.md), each case checked from outside:
the run's exit code, messages, metrics.json, events.json, <pipeline>.log and /proc.

- a well-behaved program: the run passes; it was given descriptors 0-3 only and a read-only
  shared memory (the program checks and exits 9 otherwise);
- each way a program can fail mid-run (exits, crashes, hangs past timeout_s, malformed,
  oversized, out-of-order, non-finite, a detection without a camera): that pipeline alone fails
  with its reason and last output, the built-in one beside it is written, exit 5;
- a program that cannot be started: exit 2 at the scenario's line, naming the command;
- a program that leaves a child behind, a program that prints 3 MB, corridorsim killed -9 mid
  run: no process survives, the log keeps the last MiB;
- determinism: two runs with a program whose pace is random give byte-identical files (timing
  aside), with camera sets (shared memory and inline) and dropped frames;
- a study (failed runs counted) and `test --junit` (an error case).

usage: external_test.py CORRIDORSIM SOURCE_DIR WORK_DIR
"""
import glob
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

# What these runs and studies check is their results: plots/ and the pages are left out
# (scripts.plot_run, viewer.browser and viewer.odd_data test those).
NO_EXTRAS = ["--no-plots", "--no-viewer"]

FAILURES = []


def fail(message):
    FAILURES.append(message)
    print("FAIL: " + message, flush=True)


def finish(passed):
    """main's exit status once every case ran: 1 if one failed (each said why), else 0 with
    `passed` printed."""
    if FAILURES:
        print("%d case(s) failed" % len(FAILURES))
        return 1
    print(passed)
    return 0


def scenario(path, mode, after=50, timeout_s=10, cameras=(), transport="shared_memory",
             options=None, command=None, extra=""):
    here = os.path.dirname(os.path.abspath(__file__))
    command = command or ["/usr/bin/python3", os.path.join(here, "misbehave.py"), mode, str(after)]
    sensors = "\n".join("  %s:\n    enabled: %s%s" % (c, "true" if c in cameras else "false",
                                                        "\n    rate_hz: 2" if c in cameras else "")
                        for c in ("front", "lateral", "upward"))
    text = """name: external_%s
seed: 1
world:
  layout: straight
  length_m: 12.0
  doors: {count: 2}
  plates: {count: 2}
path:
  kind: round_trip
  speed_mps: 0.5
sensors:
%s
pipelines:
  odometry: {}
  mine:
    type: external
    command: %s
    cameras: %s
    timeout_s: %s
    transport: %s
    options: %s
expectations:
  - odometry.ate_rmse_m < 5
%s""" % (mode, sensors, json.dumps(command), json.dumps(list(cameras)), timeout_s, transport,
         json.dumps(options or {}), extra)
    with open(path, "w") as f:
        f.write(text)
    return path


def run(binary, args, timeout=120):
    p = subprocess.run([binary] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def check_failed_run(binary, work, mode, expected_reason, timeout_s=10, log_has=None):
    case = os.path.join(work, mode)
    os.makedirs(case, exist_ok=True)
    path = scenario(os.path.join(case, "s.yaml"), mode, timeout_s=timeout_s)
    start = time.monotonic()
    rc, out, err = run(binary, ["run", path, "--out", os.path.join(case, "run"), *NO_EXTRAS])
    seconds = time.monotonic() - start
    name = "mode %s" % mode
    if rc != 5:
        fail("%s: exit %d, expected 5\n%s\n%s" % (name, rc, out[-2000:], err[-2000:]))
        return
    if "pipeline 'mine' failed" not in err or expected_reason not in err:
        fail("%s: stderr does not give the reason %r:\n%s" % (name, expected_reason, err[-2000:]))
    d = os.path.join(case, "run")
    metrics = json.load(open(os.path.join(d, "metrics.json")))["pipelines"]
    if metrics.get("mine", {}).get("health", {}).get("failed") != 1:
        fail("%s: metrics.json mine = %s" % (name, metrics.get("mine")))
    if "ate_rmse_m" not in metrics.get("odometry", {}):
        fail("%s: the built-in pipeline beside it was not scored: %s" % (name, metrics.get("odometry")))
    events = json.load(open(os.path.join(d, "events.json")))
    failed = [e for e in events["events"] if e.get("type") == "pipeline_failed"]
    if len(failed) != 1 or expected_reason not in json.dumps(failed[0]):
        fail("%s: events.json pipeline_failed = %s" % (name, failed))
    log = os.path.join(d, "mine.log")
    wanted = log_has if log_has is not None else "misbehave: %s at odometry message 50" % mode
    if wanted and (not os.path.exists(log) or wanted not in open(log).read()):
        fail("%s: mine.log lacks %r" % (name, wanted))
    print("ok: %s failed the pipeline alone (%.1f s): %s" % (
        name, seconds, failed[0].get("reason", failed[0]) if failed else "?"), flush=True)


def main():
    binary, source, work = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    # A well-behaved program.
    path = scenario(os.path.join(work, "ok.yaml"), "ok", cameras=("front",))
    rc, out, err = run(binary, ["run", path, "--out", os.path.join(work, "ok"), *NO_EXTRAS,
                                "--force"])
    if rc != 0:
        fail("mode ok: exit %d\n%s\n%s" % (rc, out[-2000:], err[-3000:]))
    elif os.path.exists(os.path.join(work, "ok", "mine.log")):
        fail("mode ok: a log although the program printed nothing")
    else:
        print("ok: a well-behaved program passes, descriptors 0-3, read-only shared memory")

    for mode, reason, timeout_s, log_has in [
            ("exit", "the program exited 3", 10, None),
            ("crash", "killed by signal 11", 10, None),
            ("hang", "timeout: no reply within timeout_s = 1 s", 1, None),
            ("malformed", "malformed message", 10, None),
            ("oversized", "oversized message", 10, None),
            ("wrong_type", "out of order: expected a 'estimate' reply, got 'processed'", 10, None),
            ("wrong_stamp", "out of order", 10, None),
            ("infinite", "non-finite", 10, None),
            ("nan", "non-finite", 10, None),
            ("detection_without_camera", "detections come with camera sets", 10, None)]:
        check_failed_run(binary, work, mode, reason, timeout_s, log_has)

    # A program that cannot be started: bad input.
    path = scenario(os.path.join(work, "missing.yaml"), "ok", command=["./no_such_program.py"])
    rc, out, err = run(binary, ["run", path, "--out", os.path.join(work, "missing"), *NO_EXTRAS])
    if rc != 2 or "missing.yaml:" not in err or "no_such_program.py" not in err or \
            os.path.exists(os.path.join(work, "missing")):
        fail("a missing program: exit %d (expected 2, naming the file and the command):\n%s" % (rc, err))
    else:
        print("ok: a missing program is bad input: " + err.strip().splitlines()[-1])

    # A child it leaves behind dies with its group; its pid file proves it ran.
    child_file = os.path.join(work, "child.pid")
    path = scenario(os.path.join(work, "orphan.yaml"), "orphan",
                    options={"child_pid_file": child_file})
    rc, out, err = run(binary, ["run", path, "--out", os.path.join(work, "orphan"), *NO_EXTRAS,
                                "--force"])
    child = int(open(child_file).read()) if os.path.exists(child_file) else None
    time.sleep(0.2)
    if rc != 0 or child is None or alive(child):
        fail("orphan: exit %d, child %s alive %s\n%s" % (rc, child, child and alive(child), err[-2000:]))
    else:
        print("ok: the child the program left behind is gone")

    # 3 MB of output: the log keeps the last MiB.
    path = scenario(os.path.join(work, "spam.yaml"), "spam")
    rc, out, err = run(binary, ["run", path, "--out", os.path.join(work, "spam"), *NO_EXTRAS,
                                "--force"])
    log = os.path.join(work, "spam", "mine.log")
    text = open(log).read() if os.path.exists(log) else ""
    if rc != 0 or not text.startswith("[corridorsim: the first ") or \
            "misbehave: the last spam line" not in text or len(text) > (1 << 20) + 200:
        fail("spam: exit %d, log of %d bytes starting %r" % (rc, len(text), text[:80]))
    else:
        print("ok: a 3 MB output keeps its last MiB (%d bytes)" % len(text))

    # corridorsim killed -9 mid-run: the program dies with it.
    pid_file = os.path.join(work, "hang.pid")
    path = scenario(os.path.join(work, "kill.yaml"), "hang", timeout_s=600,
                    options={"pid_file": pid_file})
    proc = subprocess.Popen([binary, "run", path, "--out", os.path.join(work, "kill"), *NO_EXTRAS,
                             "--force"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while not os.path.exists(pid_file) and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(1.0)  # past the 50th message: it hangs now
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    program = int(open(pid_file).read()) if os.path.exists(pid_file) else None
    deadline = time.monotonic() + 5
    while program and alive(program) and time.monotonic() < deadline:
        time.sleep(0.05)
    if program is None or alive(program):
        fail("kill -9: the program %s outlived corridorsim" % program)
    else:
        print("ok: corridorsim killed -9, its program is gone too")

    # Determinism: a random pace, camera sets with dropped frames, both transports.
    outputs = []
    for transport, k in [("shared_memory", 1), ("shared_memory", 2), ("inline", 3)]:
        path = scenario(os.path.join(work, "slow.yaml"), "slow", cameras=("front", "lateral"),
                        transport=transport)
        with open(path) as f:
            text = f.read().replace("    rate_hz: 2", "    rate_hz: 2\n    drop_probability: 0.3")
        with open(path, "w") as f:
            f.write(text)
        d = os.path.join(work, "slow%d" % k)
        rc, out, err = run(binary, ["run", path, "--out", d, *NO_EXTRAS, "--force"])
        if rc != 0:
            fail("slow %s: exit %d\n%s" % (transport, rc, err[-2000:]))
            break
        outputs.append(d)
    if len(outputs) == 3:
        # Wall clock: timing.json, and viewer.html which plots the frame times.
        files = sorted(f for f in os.listdir(outputs[0])
                       if f not in ("timing.json", "viewer.html"))
        events = json.load(open(os.path.join(outputs[0], "events.json")))
        dropped = sum(1 for e in events["events"] if e.get("type") == "frame_dropped")
        differ = [f for f in files if open(os.path.join(outputs[0], f), "rb").read() !=
                  open(os.path.join(outputs[1], f), "rb").read()]
        # The inline run differs in its scenario echo (transport) only.
        differ_inline = [f for f in files if f not in ("scenario.yaml", "provenance.json") and
                         open(os.path.join(outputs[0], f), "rb").read() !=
                         open(os.path.join(outputs[2], f), "rb").read()]
        if differ or differ_inline or dropped == 0 or sorted(os.listdir(outputs[1])) != sorted(
                os.listdir(outputs[0])):
            fail("determinism: files differ %s, inline %s; %d dropped frames" %
                 (differ, differ_inline, dropped))
        else:
            print("ok: a random pace and both transports give byte-identical files (%d files, "
                  "%d dropped frames)" % (len(files), dropped))

    # A study counts the failed runs; test --junit reports an error case.
    path = scenario(os.path.join(work, "study.yaml"), "exit", extra="study:\n  runs: 2\n")
    rc, out, err = run(binary, ["study", path, "--jobs", "2", *NO_EXTRAS, "--out",
                                os.path.join(work, "study"), "--force"], timeout=300)
    summary = os.path.join(work, "study", "summary.json")
    text = open(summary).read() if os.path.exists(summary) else ""
    if rc != 1 or '"failed"' not in text:
        fail("study: exit %d, summary %s" % (rc, text[:500]))
    else:
        print("ok: the study counts the failed runs (exit %d)" % rc)
    # The program is part of what a study's runs depend on: the same study resumes, an edited
    # script makes another one; provenance.json records the script's SHA-256.
    here = os.path.dirname(os.path.abspath(__file__))
    script = os.path.join(work, "copy_of_misbehave.py")
    shutil.copy(os.path.join(here, "misbehave.py"), script)
    path = scenario(os.path.join(work, "edited.yaml"), "exit",
                    command=["/usr/bin/python3", script, "exit", "50"],
                    extra="study:\n  runs: 1\n")
    study_dir = os.path.join(work, "edited_study")
    args = ["study", path, "--jobs", "1", *NO_EXTRAS, "--out", study_dir]
    first = run(binary, args + ["--force"], timeout=300)[0]
    again = run(binary, args, timeout=300)[0]
    provenance = glob.glob(os.path.join(study_dir, "runs", "*", "*", "provenance.json"))
    recorded = json.load(open(provenance[0])).get("external_programs", {}) if provenance else {}
    files = recorded.get("mine", {}).get("files", [])
    digest = hashlib.sha256(open(script, "rb").read()).hexdigest()
    with open(script, "a") as f:
        f.write("# edited\n")
    rc, out, err = run(binary, args, timeout=300)
    if (first != 1 or again != 1 or rc != 2 or "external program" not in err or
            not any(f.get("sha256") == digest and f.get("path") == script for f in files)):
        fail("an edited program: exits %d, %d, %d (expected 1, 1, 2), %s; recorded %s" %
             (first, again, rc, err.strip()[-300:], files))
    else:
        print("ok: provenance.json records the program's SHA-256; an edited script is another "
              "study")
    junit = os.path.join(work, "junit.xml")
    shutil.rmtree(os.path.join(work, "test"), ignore_errors=True)
    rc, out, err = run(binary, ["test", os.path.join(work, "exit", "s.yaml"), "--junit", junit,
                                "--out", os.path.join(work, "test")], timeout=300)
    errors = [e for e in ET.parse(junit).getroot().iter("error")] if os.path.exists(junit) else []
    if rc != 1 or not errors:
        fail("test --junit: exit %d, %d error elements" % (rc, len(errors)))
    else:
        print("ok: test --junit reports the failed pipeline as an error: %s" %
              errors[0].get("message", "")[:120])

    return finish("all external-pipeline cases passed")


if __name__ == "__main__":
    sys.exit(main())
