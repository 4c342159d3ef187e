#!/usr/bin/python3
"""Exit 0 means complete, descendants never survive, long jobs end on a stop signal
(harness/cli/supervisor.h, docs/architecture.md "Supervision"):

- a plugin whose static initializer calls exit(0): `plugin`, `run`, `study` and `test --junit`
  exit non-zero with one message, nothing written; a plugin calling _Exit(0) mid-run: `run`
  exits non-zero and leaves no folder, staging folder included;
- an external program's descendants, one in its process group and one that left it
  (setpgid(0, 0)), are gone once corridorsim has ended: after a normal run, after SIGTERM, after
  SIGKILL; the SIGTERMed run ends as SIGTERM ends a process (143) with no staging folder left;
- a study SIGTERMed mid-run ends the same way, its runs and their staging folders gone;
- a run's <pipeline>_errors.csv with an `inf` stamp is bad input for the study's summary (exit 2,
  the file and line), never an endless loop.
The bounds below (60 s) are hang checks, not timings.

usage: cli_supervision_test.py CORRIDORSIM PLUGIN_DIR SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

NO_EXTRAS = ["--no-plots", "--no-viewer"]
HANG_CHECK_S = 60
HERE = os.path.dirname(os.path.abspath(__file__))
NOT_COMPLETE = "the job ended before it finished"


def fail(message):
    print("FAIL: " + message, file=sys.stderr, flush=True)
    sys.exit(1)


def run(args, cwd=None):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       timeout=HANG_CHECK_S * 5, cwd=cwd)
    return p.returncode, p.stdout, p.stderr


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except (FileNotFoundError, ProcessLookupError):
        return False


def wait_for(condition, seconds, what):
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            fail("waited %d s for %s" % (seconds, what))
        time.sleep(0.05)


def leftovers(folder):
    """Staging folders (`.<name>.partial-<pid>`) anywhere below `folder`."""
    found = []
    for root, dirs, _files in os.walk(folder):
        found += [os.path.join(root, d) for d in dirs if ".partial-" in d]
    return found


def check_exiting_plugins(binary, plugins, source, work):
    at_load = os.path.join(plugins, "test_broken_plugin_7.so")
    mid_run = os.path.join(plugins, "test_broken_plugin_8.so")
    base = "include: %s/scenarios/default.yaml\n" % source
    rc, out, err = run([binary, "plugin", at_load])
    if rc == 0 or NOT_COMPLETE not in err or "exited 0" not in err:
        fail("`plugin` of a library calling exit(0) as it loads: exit %d\n%s%s" % (rc, out, err))
    scenario = os.path.join(work, "at_load.yaml")
    with open(scenario, "w") as f:
        f.write(base + "duration_s: 3\nplugins: [%s]\nstudy: {runs: 1}\n" % at_load)
    for job, args in [("run", ["run", scenario, "--out", "at_load_run"] + NO_EXTRAS),
                      ("study", ["study", scenario, "--out", "at_load_study"] + NO_EXTRAS),
                      ("test", ["test", scenario, "--out", "at_load_test",
                                "--junit", "at_load.xml"])]:
        rc, out, err = run([binary] + args, cwd=work)
        if rc == 0 or NOT_COMPLETE not in err:
            fail("`%s` with a plugin calling exit(0) as it loads: exit %d\n%s%s" %
                 (job, rc, out, err))
    if leftovers(work) or any(os.path.exists(os.path.join(work, n)) for n in
                              ("at_load_run", "at_load_study", "at_load_test")):
        fail("a job whose plugin called exit(0) left folders: %s" % os.listdir(work))
    print("ok: exit(0) in a plugin's static initializer: plugin, run, study, test exit non-zero")

    scenario = os.path.join(work, "mid_run.yaml")
    with open(scenario, "w") as f:
        f.write(base + "duration_s: 6\nplugins: [%s]\n"
                "pipelines:\n  echo: {type: test_echo, throw_after_s: 2}\n" % mid_run)
    rc, out, err = run([binary, "run", scenario, "--out", "mid_run"] + NO_EXTRAS, cwd=work)
    if rc == 0 or NOT_COMPLETE not in err:
        fail("a plugin calling _Exit(0) mid-run: exit %d\n%s%s" % (rc, out[-2000:], err))
    if os.path.exists(os.path.join(work, "mid_run")) or leftovers(work):
        fail("a plugin calling _Exit(0) mid-run left a folder: %s" % os.listdir(work))
    print("ok: _Exit(0) in a plugin mid-run: exit %d, no folder left" % rc)


def external_scenario(path, pid_dir, mode):
    program = os.path.join(HERE, "..", "external", "supervision_descendants.py")
    command = ["/usr/bin/python3", program, pid_dir, mode]
    with open(path, "w") as f:
        f.write("""name: descendants
seed: 1
duration_s: 4
world: {layout: straight, length_m: 12.0, doors: {count: 2}, plates: {count: 2}}
path: {kind: round_trip, speed_mps: 0.5}
sensors:
  front: {enabled: false}
  lateral: {enabled: false}
  upward: {enabled: false}
pipelines:
  odometry: {}
  mine: {type: external, command: %s, timeout_s: 600}
study: {runs: 1}
""" % json.dumps(command))
    return path


def read_pids(pid_dir):
    return {name: int(open(os.path.join(pid_dir, name + ".pid")).read())
            for name in ("program", "same_group", "own_group")}


def check_descendants_gone(pids, case):
    # corridorsim has ended: every descendant must be gone. The wait is a hang check.
    deadline = time.monotonic() + 5
    while any(alive(p) for p in pids.values()) and time.monotonic() < deadline:
        time.sleep(0.05)
    survivors = {name: pid for name, pid in pids.items() if alive(pid)}
    for pid in survivors.values():
        os.kill(pid, signal.SIGKILL)
    if survivors:
        fail("%s: descendants of the external program outlived corridorsim: %s" % (case, survivors))


def check_external_descendants(binary, work):
    # A normal run.
    case = os.path.join(work, "normal")
    os.makedirs(case)
    scenario = external_scenario(os.path.join(case, "s.yaml"), case, "ok")
    rc, out, err = run([binary, "run", scenario, "--out", os.path.join(case, "run")] + NO_EXTRAS)
    if rc != 0:
        fail("a run with a program leaving descendants: exit %d\n%s%s" % (rc, out[-2000:], err))
    check_descendants_gone(read_pids(case), "a normal run")
    print("ok: a normal run: the program's descendants are gone")

    # SIGTERM and SIGKILL to corridorsim while the program hangs.
    for sig in (signal.SIGTERM, signal.SIGKILL):
        case = os.path.join(work, sig.name)
        os.makedirs(case)
        scenario = external_scenario(os.path.join(case, "s.yaml"), case, "hang")
        proc = subprocess.Popen([binary, "run", scenario, "--out", os.path.join(case, "run")] +
                                NO_EXTRAS, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        try:
            wait_for(lambda: os.path.exists(os.path.join(case, "program.pid")) and leftovers(case),
                     HANG_CHECK_S, "the program to start")
            time.sleep(0.5)
            proc.send_signal(sig)
            _, err = proc.communicate(timeout=HANG_CHECK_S)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        if proc.returncode != -sig:
            fail("%s to a run: it ended with %d, not as %s ends a process\n%s" %
                 (sig.name, proc.returncode, sig.name, err.decode(errors="replace")))
        check_descendants_gone(read_pids(case), "after %s to corridorsim" % sig.name)
        # SIGKILL: the supervising process ends at once, its reaper right after it.
        wait_for(lambda: not leftovers(case), 5 if sig == signal.SIGKILL else 0.01,
                 "the staging folder to be removed after %s" % sig.name)
        if os.path.exists(os.path.join(case, "run")):
            fail("%s to a run: the run folder was committed" % sig.name)
        print("ok: %s to a run: exit %d, the program's descendants and the staging folder gone" %
              (sig.name, 128 + sig))


def study_case(work, case, name, scenario, duration_s, runs):
    """A new folder `work`/`case` holding the study file `name`: `runs` runs of `scenario` cut to
    `duration_s`. Returns the folder and the file."""
    folder = os.path.join(work, case)
    os.makedirs(folder)
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write("include: %s\nduration_s: %d\nstudy:\n  runs: %d\n" % (scenario, duration_s, runs))
    return folder, path


def check_study_stop(binary, work, source):
    case, slow = study_case(work, "study_stop", "slow.yaml",
                            os.path.join(source, "scenarios", "p3_lamps.yaml"), 300, 2)
    proc = subprocess.Popen([binary, "study", slow, "--jobs", "2", "--out", "study"] + NO_EXTRAS,
                            cwd=case, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        wait_for(lambda: len(leftovers(os.path.join(case, "study"))) >= 2, HANG_CHECK_S * 2,
                 "the study's runs to start")
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=HANG_CHECK_S)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    if proc.returncode != -signal.SIGTERM:
        fail("SIGTERM to a study: it ended with %d\n%s" % (proc.returncode,
                                                           err.decode(errors="replace")))
    if leftovers(case):
        fail("SIGTERM to a study left staging folders: %s" % leftovers(case))
    print("ok: SIGTERM to a study: exit 143, no staging folder left")


def check_inf_stamp(binary, work, source):
    case, short = study_case(work, "inf_stamp", "short.yaml",
                             os.path.join(source, "scenarios", "umbmark_cw.yaml"), 3, 1)
    rc, out, err = run([binary, "study", short, "--out", "study"] + NO_EXTRAS, cwd=case)
    if rc != 0:
        fail("the study to tamper with: exit %d\n%s%s" % (rc, out[-2000:], err))
    csvs = [os.path.join(root, n) for root, _d, files in os.walk(os.path.join(case, "study"))
            for n in files if n.endswith("_errors.csv")]
    if not csvs:
        fail("the study's run wrote no _errors.csv")
    with open(csvs[0]) as f:
        lines = f.read().splitlines()
    # The last stamp: the series' grid runs to it.
    lines[-1] = "inf" + lines[-1][lines[-1].index(","):]
    with open(csvs[0], "w") as f:
        f.write("\n".join(lines) + "\n")
    # The same command again: every run is there, only the summary runs.
    try:
        rc, out, err = run([binary, "study", short, "--out", "study"] + NO_EXTRAS, cwd=case)
    except subprocess.TimeoutExpired:
        fail("a study whose run has an inf stamp did not end")
    where = "%s:%d:1: t:" % (os.path.relpath(csvs[0], case), len(lines))
    if rc != 2 or where not in err or "inf" not in err:
        fail("an inf stamp in %s: exit %d\n%s" % (csvs[0], rc, err))
    print("ok: an inf stamp is bad input for the summary: " + err.strip().splitlines()[-1])


def main():
    binary, plugins, source, work = (os.path.abspath(a) for a in sys.argv[1:5])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    check_exiting_plugins(binary, plugins, source, work)
    check_external_descendants(binary, work)
    check_study_stop(binary, work, source)
    check_inf_stamp(binary, work, source)
    print("PASS")


if __name__ == "__main__":
    main()
