#!/usr/bin/python3
"""What a run reports of an external pipeline (docs/protocol.md, "Unknown keys" and "Cost"), each
case checked from outside (exit code, stdout, stderr, the run folder):

- `finished` with a misspelt result key ("landmark"): the pipeline fails (exit 5) naming the
  message, the key, the key it misspells and every valid key; what arrived is kept (the whole
  trajectory, the innovations of the run as <pipeline>_nis.csv, the stage_seconds it sent); the
  closing table's row says `failed`;
- `finished` with a misspelt `stage_seconds`: a warning naming the key and the valid keys, and
  the results are scored (exit 0);
- an estimate reply with an unknown key at message 50: the pipeline fails there, that estimate
  is kept, and every live line from then on says `mine failed: ...`, never its last error;
- timing.json of an external run has its round trips by message kind, the program's reported and
  measured (wait4) cost and corridorsim's side, with plausible positive values, and no `cpu_*`
  figures that would describe corridorsim as if they were the program's; viewer.html carries them;
- `corridorsim --help` and `run --help` list exit code 5.

usage: reply_keys_test.py CORRIDORSIM WORK_DIR
"""
import json
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from external_test import NO_EXTRAS, fail, finish, scenario, run  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
PROGRAM = os.path.join(HERE, "reply_keys_program.py")
FINISHED_KEYS = "the valid keys are type, landmarks, detections, innovations, maps, health, " \
                "stage_seconds"


def case(binary, work, mode, cameras=(), extras=NO_EXTRAS):
    d = os.path.join(work, mode)
    os.makedirs(d, exist_ok=True)
    path = scenario(os.path.join(d, "s.yaml"), mode, cameras=cameras,
                    command=["/usr/bin/python3", PROGRAM, mode])
    rc, out, err = run(binary, ["run", path, "--out", os.path.join(d, "run"), *extras, "--force"],
                       timeout=300)
    return rc, out, err, os.path.join(d, "run")


def data_lines(path):
    with open(path) as f:
        return [line for line in f if line.strip() and not line.startswith("#")]


def odometry_steps(run_dir):
    return len(data_lines(os.path.join(run_dir, "odometry.tum")))


def check_finished_landmarks(name, out, d):
    steps = odometry_steps(d)
    mine = os.path.join(d, "mine.tum")
    if not os.path.exists(mine) or len(data_lines(mine)) != steps or steps == 0:
        fail("%s: mine.tum does not hold its %d estimates" % (name, steps))
    nis = os.path.join(d, "mine_nis.csv")
    if not os.path.exists(nis) or len(data_lines(nis)) < 2:
        fail("%s: the innovations it sent are lost (no mine_nis.csv)" % name)
    events = json.load(open(os.path.join(d, "events.json")))["events"]
    if not any(e.get("type") == "pipeline_failed" and
               "unknown key 'landmark'" in e.get("reason", "") for e in events):
        fail("%s: events.json has no pipeline_failed naming the key" % name)
    protocol = json.load(open(os.path.join(d, "timing.json")))["pipelines"].get("mine", {}).get(
        "protocol", {})
    if not (protocol.get("program_reported_seconds") or 0) > 0:
        fail("%s: the stage_seconds it sent are lost: protocol = %s" % (name, protocol))
    rows = [line for line in out.splitlines() if line.startswith("mine ")]
    if len(rows) != 1 or "failed at t = " not in rows[0] or "unknown key 'landmark'" not in rows[0]:
        fail("%s: the closing table's row is %r, not `failed` with its reason" % (name, rows))
    else:
        print("ok: %s fails it (exit 5) naming the key and the valid keys; its %d estimates, "
              "innovations and stage_seconds are kept; the table says %r" %
              (name, steps, rows[0][:60]))


def check_finished_stage(name, out, d):
    metrics = json.load(open(os.path.join(d, "metrics.json")))["pipelines"]["mine"]
    if "ate_rmse_m" not in metrics or "map" not in metrics:
        fail("%s: its results are not scored: %s" % (name, sorted(metrics)))
    else:
        print("ok: %s is a warning naming the key and the valid keys; the results are scored" %
              name)


def check_estimate_key(name, out, d):
    estimates = len(data_lines(os.path.join(d, "mine.tum")))
    if estimates != 50:
        fail("%s: mine.tum holds %d estimates, expected the 50 that arrived" % (name, estimates))
    # Non-interactive output: a live line at every 10 % of the run; those after the failure
    # (about 1 s of 48 s) say so, with the reason, and none gives mine's error in metres.
    live = [line for line in out.splitlines() if line.startswith("run: sim")]
    later = [line for line in live if float(line.split()[2]) > 1.5]  # "run: sim   12.3 s ..."
    said = "mine failed: 'odometry' message: estimate reply: unknown key 'covariances'"
    if len(later) < 3 or any(said not in line for line in later) or \
            any(re.search(r"(^|\s)mine -?[0-9.]+ m", line) for line in later):
        fail("%s: the live lines after the failure are %s" % (name, later))
    else:
        print("ok: %s fails it there, keeps that estimate, and the live line says %r" %
              (name, later[-1][later[-1].index("mine failed"):][:90]))


# The misspelt and unknown keys: the mode of reply_keys_program.py, the case's name, the exit code
# and the message on stderr the run must give, then the check of the rest (its stdout and folder).
KEY_CASES = [
    ("finished_landmarks", "a misspelt 'landmarks' in finished", 5,
     "'finish' message: finished reply: unknown key 'landmark' (did you mean 'landmarks'?); " +
     FINISHED_KEYS, check_finished_landmarks),
    ("finished_stage", "a misspelt 'stage_seconds' in finished", 0,
     "corridorsim: warning: pipeline 'mine': 'finish' message: finished reply: unknown key "
     "'stage_second' (did you mean 'stage_seconds'?); " + FINISHED_KEYS, check_finished_stage),
    ("estimate_key", "an unknown key in the 50th estimate", 5,
     "'odometry' message: estimate reply: unknown key 'covariances' (did you mean "
     "'covariance'?); the valid keys are type, stamp_ns, pose, covariance, detections, "
     "innovations", check_estimate_key),
]


def check_key_cases(binary, work):
    for mode, name, expect, wanted, check_rest in KEY_CASES:
        rc, out, err, d = case(binary, work, mode)
        if rc != expect or wanted not in err:
            fail("%s: exit %d (expected %d), stderr lacks %r:\n%s" %
                 (name, rc, expect, wanted, err[-3000:]))
        else:
            check_rest(name, out, d)


def positive(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and value > 0


def check_timing(binary, work):
    rc, out, err, d = case(binary, work, "ok", cameras=("front",), extras=["--no-plots"])
    name = "timing.json of an external run"
    if rc != 0:
        fail("%s: exit %d\n%s" % (name, rc, err[-3000:]))
        return
    mine = json.load(open(os.path.join(d, "timing.json")))["pipelines"]["mine"]
    protocol = mine.get("protocol", {})
    trips = protocol.get("round_trip_ms", {})
    problems = []
    steps = odometry_steps(d)
    for kind, count in (("start", 1), ("odometry", steps), ("cameras", None), ("finish", 1)):
        r = trips.get(kind, {})
        if (count is not None and r.get("messages") != count) or not positive(r.get("messages")):
            problems.append("round_trip_ms.%s.messages = %s (expected %s)" %
                            (kind, r.get("messages"), count))
        if not all(positive(r.get(k)) for k in ("mean", "p50", "p90", "max")) or \
                not r["p50"] <= r["p90"] <= r["max"] or r["max"] > 60000:
            problems.append("round_trip_ms.%s = %s" % (kind, r))
    if protocol.get("messages") != sum(r.get("messages", 0) for r in trips.values()):
        problems.append("messages = %s" % protocol.get("messages"))
    for key in ("round_trip_seconds", "program_reported_seconds",
                "program_reported_ms_per_message", "program_cpu_seconds",
                "program_cpu_ms_per_message", "program_peak_rss_mib", "corridorsim_cpu_seconds",
                "corridorsim_cpu_ms_per_message"):
        if not positive(protocol.get(key)):
            problems.append("%s = %s" % (key, protocol.get(key)))
    # The program's own CPU time: a Python interpreter's start alone takes more than 10 ms.
    if positive(protocol.get("program_cpu_seconds")) and protocol["program_cpu_seconds"] < 0.01:
        problems.append("program_cpu_seconds = %s: not the program's" %
                        protocol["program_cpu_seconds"])
    if abs(mine.get("stage_seconds", {}).get("dead_reckoning", -1) -
           protocol.get("program_reported_seconds", -2)) > 1e-5:
        problems.append("program_reported_seconds %s is not its stage_seconds %s" %
                        (protocol.get("program_reported_seconds"), mine.get("stage_seconds")))
    if "cpu_seconds" in mine or "cpu_ms_per_frame" in mine:
        problems.append("cpu_* figures of corridorsim's side under the program's name: %s" %
                        sorted(mine))
    page = os.path.join(d, "viewer.html")
    text = open(page).read() if os.path.exists(page) else ""
    if '"round_trip_ms"' not in text or '"program_cpu_seconds"' not in text:
        problems.append("viewer.html does not carry the protocol's cost")
    if problems:
        fail("%s: %s" % (name, "; ".join(problems)))
    else:
        odo = trips["odometry"]
        cam = trips["cameras"]
        print("ok: %s: odometry round trip median %s ms (p90 %s, %d messages), camera set %s ms; "
              "program CPU %s s, reported %s s; corridorsim's side %s s" %
              (name, odo["p50"], odo["p90"], odo["messages"], cam["p50"],
               protocol["program_cpu_seconds"], protocol["program_reported_seconds"],
               protocol["corridorsim_cpu_seconds"]))


def check_help(binary):
    for args, wanted in ((["--help"], "5 (a pipeline failed"),
                         (["run", "--help"], "5 a pipeline failed")):
        rc, out, err = run(binary, args)
        text = " ".join((out + err).split())
        if rc != 0 or wanted not in text:
            fail("corridorsim %s: exit %d, exit code 5 not listed (%r)" %
                 (" ".join(args), rc, wanted))
        else:
            print("ok: corridorsim %s lists exit code 5" % " ".join(args))


def main():
    binary, work = sys.argv[1], os.path.abspath(sys.argv[2])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    check_help(binary)
    check_key_cases(binary, work)
    check_timing(binary, work)
    return finish("all cases passed")


if __name__ == "__main__":
    sys.exit(main())
