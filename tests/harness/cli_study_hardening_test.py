#!/usr/bin/env python3
"""`corridorsim study`, `study merge`, `study --slurm` and `test --junit` against hostile input and
signals (docs/studies.md, docs/ci.md):

- a --slurm --out that an #SBATCH line cannot hold (a newline that would start a command, '%',
  quotes, '#', '\\', whitespace, control characters) is refused, exit 2, nothing written; a study
  file whose name is shell syntax is quoted in the scripts' exec lines, which run as written;
- killing a study or a test suite (SIGKILL or SIGINT) leaves none of its runs running, and no
  run folder is committed afterwards;
- a merge that lacks runs of the plan is refused (exit 2) naming the missing seeds and shards, as
  is --force over a folder to merge;
- the JUnit report of a study named in Japanese, with bytes that are not UTF-8 and a control
  character in its name, whose runs fail, is XML that xml.etree reads;
- a scenario's `baseline: true` pipelines may diverge: the shortened default.yaml's study counts
  their divergences and does not fail on them, in `study` and in `test`.

Usage: cli_study_hardening_test.py CORRIDORSIM SOURCE_DIR WORK_DIR"""

import json
import os
import shlex
import signal
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_test_support import NO_EXTRAS, fail  # noqa: E402


def run(binary, args, expect, cwd):
    """cli_test_support.run for hostile input: the output's bytes decoded leniently (names that
    are not UTF-8) and as they are (a carriage return stays one), returned as (stdout, stderr)."""
    result = subprocess.run([binary] + args, cwd=cwd, capture_output=True)
    stdout = result.stdout.decode(errors="replace")
    stderr = result.stderr.decode(errors="replace")
    if result.returncode != expect:
        fail("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" % (
            " ".join(str(a) for a in args), result.returncode, expect, stdout[-3000:], stderr))
    return stdout, stderr


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def processes_with(text):
    """The processes (not this one) whose command line holds `text`."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open("/proc/%s/cmdline" % entry, "rb") as f:
                if text.encode() in f.read():
                    found.append(int(entry))
        except OSError:
            pass
    return found


def wait_for(condition, seconds, what):
    deadline = time.time() + seconds
    while time.time() < deadline:
        if condition():
            return
        time.sleep(0.1)
    fail("timed out waiting for " + what)


def committed_runs(folder):
    found = []
    for root, _, files in os.walk(folder):
        if "metrics.json" in files:
            found.append(root)
    return found


def check_slurm(binary, work, short):
    # A newline in --out would end the #SBATCH line and make the rest a command of every task.
    owned = os.path.join(work, "owned")
    hostile = "o/x\ntouch %s\n#" % owned
    _, err = run(binary, ["study", short, "--slurm", "--out", hostile], 2, work)
    if "--out" not in err or "control character (\\x0A)" not in err:
        fail("a newline in --slurm --out: " + err)
    for bad in ("o/a b", "o/%j", "o/it's", "o/x#y", "o/back\\slash", 'o/q"uote', "o/t\tab"):
        _, err = run(binary, ["study", short, "--slurm", "--out", bad], 2, work)
        if "--out" not in err or "#SBATCH" not in err:
            fail("--slurm --out %r: %s" % (bad, err))
    if os.path.exists(os.path.join(work, "o")) or os.path.exists(owned):
        fail("a refused --slurm --out wrote something")
    # A study file named in shell syntax: quoted in the exec lines, which run as written.
    tricky = os.path.join(work, "s'; touch owned; echo '$(touch owned).yaml")
    shutil.copy(short, tricky)
    run(binary, ["study", tricky, "--slurm", "--slurm-tasks", "2", "--out", "slurm_ok",
                 *NO_EXTRAS], 0, work)
    folder = os.path.join(work, "slurm_ok")
    array = open(os.path.join(folder, "slurm", "study.sbatch")).read()
    merge = open(os.path.join(folder, "slurm", "merge.sbatch")).read()
    if "#SBATCH --output=%s\n" % os.path.join(folder, "slurm", "task_%a.log") not in array or \
            "#SBATCH --output=%s\n" % os.path.join(folder, "slurm", "merge.log") not in merge:
        fail("the #SBATCH --output lines:\n" + array + merge)
    exec_line = [line for line in array.splitlines() if line.startswith("exec ")][0]
    words = shlex.split(exec_line.replace("${SLURM_ARRAY_TASK_ID}", "1"))
    if words[2:4] != ["study", tricky] or words[-2:] != ["--out", os.path.join(folder, "shards", "1")]:
        fail("the array task's exec line: %s" % words)
    for script in ("study.sbatch", "merge.sbatch"):
        subprocess.run(["bash", "-n", os.path.join(folder, "slurm", script)], check=True)
    # Run as Slurm would: the tasks, then the merge.
    for task in ("1", "2"):
        env = dict(os.environ, SLURM_ARRAY_TASK_ID=task)
        result = subprocess.run(["bash", os.path.join(folder, "slurm", "study.sbatch")], cwd=work,
                                env=env, capture_output=True, text=True)
        if result.returncode != 0:
            fail("array task %s: %s%s" % (task, result.stdout, result.stderr))
    result = subprocess.run(["bash", os.path.join(folder, "slurm", "merge.sbatch")], cwd=work,
                            capture_output=True, text=True)
    if result.returncode != 0 or not os.path.isfile(os.path.join(folder, "summary.json")):
        fail("merge job: %s%s" % (result.stdout, result.stderr))
    if os.path.exists(owned):
        fail("a path in a Slurm script ran as a command")


def check_kill(binary, work, slow):
    """A study (or test suite) killed with `sig` once its runs are running: none outlives it."""
    for sig in (signal.SIGKILL, signal.SIGINT):
        for job in ("study", "test"):
            out = "%s_%s" % (job, sig.name)
            if job == "study":
                args = ["study", slow, "--jobs", "2", "--out", out, *NO_EXTRAS]
            else:
                args = ["test", slow, "--out", out, "--junit", out + ".xml"]
            marker = out + "/"
            proc = subprocess.Popen([binary] + args, cwd=work, stdout=subprocess.DEVNULL,
                                    stderr=subprocess.PIPE)
            try:
                # `corridorsim run` children (and a test's study) hold the folder in their
                # command lines.
                wait_for(lambda: len(processes_with(marker)) >= 2, 120,
                         "the runs of %s to start" % out)
                time.sleep(1.0)
                proc.send_signal(sig)
                _, err = proc.communicate(timeout=60)
            finally:
                if proc.poll() is None:  # the test failed: leave nothing running
                    proc.send_signal(signal.SIGINT)
                    proc.wait()
            if proc.returncode != -sig:
                fail("%s: ended with %d after %s: %s" % (out, proc.returncode, sig.name, err))
            if sig == signal.SIGINT and b"stopped by signal 2" not in err:
                fail("%s: no word of the stop: %s" % (out, err))
            wait_for(lambda: not processes_with(marker), 5, "the runs of %s to end" % out)
            time.sleep(2.0)
            if processes_with(marker) or committed_runs(os.path.join(work, out)):
                fail("%s: a run outlived its %s or committed later" % (out, job))
            if job == "test" and os.path.exists(os.path.join(work, out + ".xml")):
                fail("%s: a stopped suite wrote a report" % out)
    # A stopped run is not recorded as failed: the study resumes it.
    if os.path.exists(os.path.join(work, "study_SIGINT", "status", "p000", "seed_1.json")):
        fail("a run stopped with its study was recorded")
    # Ctrl-C in a terminal: SIGINT to the whole process group, the runs with their study. They
    # end at once; none of them is recorded as failed.
    proc = subprocess.Popen([binary, "study", slow, "--jobs", "2", "--out", "group",
                             *NO_EXTRAS], cwd=work, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, start_new_session=True)
    try:
        wait_for(lambda: len(processes_with("group/")) >= 2, 120, "the runs of group to start")
        time.sleep(1.0)
        os.killpg(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    if proc.returncode != -signal.SIGINT or processes_with("group/"):
        fail("Ctrl-C of a study's process group: %d %s" % (proc.returncode, err))
    status = os.path.join(work, "group", "status", "p000")
    if os.path.isdir(status) and os.listdir(status):
        fail("runs stopped with their study were recorded: %s" % os.listdir(status))


def check_merge(binary, work, short):
    shards = os.path.join(work, "mm", "shards")
    for k in (1, 2, 3):
        run(binary, ["study", short, "--runs", "3", "--shard", "%d/3" % k, "--out",
                     os.path.join(shards, str(k)), *NO_EXTRAS], 0, work)
    parts = [os.path.join(shards, str(k)) for k in (1, 2, 3)]
    _, err = run(binary, ["study", "merge", parts[0], parts[1], "--out", "merged", *NO_EXTRAS],
                 2, work)
    if "1 of the plan's 3 run(s)" not in err or "p000 seed 3" not in err or \
            "shard(s) 3/3" not in err or "incomplete" not in err:
        fail("an incomplete merge: " + err)
    if os.path.exists(os.path.join(work, "merged")):
        fail("an incomplete merge wrote its folder")
    # A shard that has not ended (a run neither finished nor recorded) is missing too.
    shutil.move(os.path.join(parts[1], "runs", "p000", "seed_2"), os.path.join(work, "held"))
    _, err = run(binary, ["study", "merge"] + parts + ["--out", "merged", *NO_EXTRAS], 2, work)
    if "p000 seed 2" not in err or "shard(s) 2/3" not in err:
        fail("a shard with a run missing: " + err)
    shutil.move(os.path.join(work, "held"), os.path.join(parts[1], "runs", "p000", "seed_2"))
    # --force never removes the folders it merges (Slurm's layout: shards/K inside the study).
    _, err = run(binary, ["study", "merge"] + parts + ["--out", "mm", "--force", *NO_EXTRAS], 2,
                 work)
    if "--force" not in err or not all(os.path.isdir(p) for p in parts):
        fail("--force over the folders merged: " + err)
    # A point scenario that is not the plan's is refused before anything is written.
    point = os.path.join(parts[0], "points", "p000.yaml")
    original = open(point).read()
    write(point, original + "# changed\n")
    _, err = run(binary, ["study", "merge"] + parts + ["--out", "merged", *NO_EXTRAS], 2, work)
    if "SHA-256" not in err or os.path.exists(os.path.join(work, "merged")):
        fail("a changed point scenario: " + err)
    write(point, original)
    # A link in a run folder is copied as a link, never followed (one to "/" would copy the
    # file system).
    outside = os.path.join(work, "outside")
    os.makedirs(outside)
    write(os.path.join(outside, "big"), "x" * 1000)
    os.symlink(outside, os.path.join(parts[0], "runs", "p000", "seed_1", "link"))
    out, _ = run(binary, ["study", "merge"] + parts + ["--out", "merged", *NO_EXTRAS], 0, work)
    link = os.path.join(work, "merged", "runs", "p000", "seed_1", "link")
    if not os.path.islink(link) or os.readlink(link) != outside:
        fail("a link in a merged run folder was followed")
    summary = json.load(open(os.path.join(work, "merged", "summary.json")))
    if summary["points"][0]["runs"]["finished"] != 3:
        fail("the complete merge: %s" % summary["points"][0]["runs"])


def check_junit(binary, work, source):
    # Japanese, a byte that is not UTF-8 (Latin-1 e-acute) and a control character in the name;
    # long enough that the log's tail, cut at 4000 bytes, is mostly Japanese.
    name = ("失敗する研究" * 9).encode() + b"_\x01\xe9.yaml"
    path = os.path.join(work.encode(), name)
    with open(path, "w") as f:
        f.write("include: %s\nduration_s: 30\nstudy:\n  runs: 12\n  run_timeout_s: 1\n"
                % os.path.join(source, "scenarios", "p3_lamps.yaml"))
    result = subprocess.run([binary, "test", path, "--out", "suite_ja", "--junit", "ja.xml"],
                            cwd=work, capture_output=True)
    if result.returncode != 1:
        fail("test of the failing study: exit %d\n%s" % (result.returncode, result.stderr))
    data = open(os.path.join(work, "ja.xml"), "rb").read()
    data.decode("utf-8")  # strictly: raises on a byte that is not UTF-8
    root = ET.fromstring(data)
    suite = root.find("testsuite")
    if root.get("errors") != "12" or "失敗する研究" not in suite.get("name") or \
            "\ufffd\ufffd" not in suite.get("name"):
        fail("ja.xml: %s %s" % (root.attrib, suite.attrib))
    # The folder and log under --out: the stem with its control character and its byte that is
    # not UTF-8 each as "_" (docs/ci.md: nothing in a name changes what the report attaches).
    folder_name = name[:-5].replace(b"\x01", b"_").replace(b"\xe9", b"_")
    log = open(os.path.join(work.encode(), b"suite_ja", b"000_" + folder_name + b".log"), "rb").read()
    if len(log) <= 4000:
        fail("the study's log is too short to be cut: %d bytes" % len(log))
    # Each error case's details: "..." and the log's last 4000 bytes from the first whole
    # character on, a byte that is not UTF-8 and a control character each as U+FFFD.
    tail = log[-4000:]
    while tail[0] & 0xC0 == 0x80:
        tail = tail[1:]
    expected = "..." + "".join("\ufffd" if ord(c) < 0x20 and c not in "\t\n\r" else c
                               for c in tail.decode("utf-8", errors="replace"))
    if "失敗する研究" not in expected:
        fail("the log's tail holds no Japanese: %r" % expected[-300:])
    errors = [case.find("error") for case in root.iter("testcase") if case.find("error") is not None]
    if len(errors) != 12:
        fail("ja.xml: %d error cases" % len(errors))
    for error in errors:
        if error.text != expected:
            fail("an error case's details are not the log's tail: %r\nexpected %r"
                 % (error.text[-300:], expected[-300:]))


def check_baselines(binary, work, source):
    # default.yaml shortened; P1's system left out, so that only the baselines run; with a low
    # divergence_nees both diverge in every seed (their average NEES is above 1.5 in 10 s).
    base = os.path.join(work, "baselines.yaml")
    write(base, "include: %s\nduration_s: 10\npipelines:\n  p1_vp_doorplate: {enabled: false}\n"
                "expectations: []\nstudy:\n  runs: 2\n  divergence_nees: 1.5\n"
          % os.path.join(source, "scenarios", "default.yaml"))
    out, _ = run(binary, ["study", base, "--out", "baselines", *NO_EXTRAS], 0, work)
    if "p000 odometry: seeds 1, 2" not in out or "p000 p1_harris: seeds 1, 2" not in out:
        fail("the baselines' divergences are not reported:\n" + out)
    pipelines = json.load(open(os.path.join(work, "baselines", "summary.json")))["points"][0][
        "pipelines"]
    for name in ("odometry", "p1_harris"):
        if pipelines[name]["runs"]["diverged"] != 2 or not pipelines[name]["runs"]["may_diverge"]:
            fail("%s in summary.json: %s" % (name, pipelines[name]["runs"]))
    point = open(os.path.join(work, "baselines", "points", "p000.yaml")).read()
    if "    baseline: true\n" not in point:
        fail("the point's resolved scenario does not mark the baselines")
    run(binary, ["test", base, "--out", "suite_baselines", "--junit", "baselines.xml"], 0, work)
    root = ET.parse(os.path.join(work, "baselines.xml")).getroot()
    if root.get("failures") != "0" or root.get("errors") != "0":
        fail("baselines.xml: %s" % root.attrib)
    # Not a baseline: the same divergences fail the study.
    write(base.replace(".yaml", "_tested.yaml"),
          open(base).read().replace("pipelines:\n", "pipelines:\n  odometry: {baseline: false}\n"))
    out, _ = run(binary, ["study", base.replace(".yaml", "_tested.yaml"), "--out", "tested",
                          *NO_EXTRAS], 1, work)
    if "p000 seed 1: odometry diverged" not in out or "p1_harris diverged" in out:
        fail("a pipeline that is not a baseline must fail the study:\n" + out)


def main():
    binary, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    short = os.path.join(work, "short.yaml")
    write(short, "include: %s\nduration_s: 3\nstudy:\n  runs: 2\n"
          % os.path.join(source, "scenarios", "umbmark_cw.yaml"))
    slow = os.path.join(work, "slow.yaml")
    write(slow, "include: %s\nduration_s: 300\nstudy:\n  runs: 2\n"
          % os.path.join(source, "scenarios", "p3_lamps.yaml"))
    check_slurm(binary, work, short)
    check_merge(binary, work, short)
    check_kill(binary, work, slow)
    check_junit(binary, work, source)
    check_baselines(binary, work, source)
    print("PASS")


if __name__ == "__main__":
    main()
