#!/usr/bin/python3
"""`corridorsim plugin` and plugins in runs, as a user meets them (docs/plugins.md): a library
that cannot be a plugin is exit 2 with one message at the scenario line (nothing written; one of
the old std::string ABI names its demangled symbol and what to rebuild); a
plugin that throws during a run fails alone: exit 5, the other pipelines' results written, its
metrics `health.failed`, events.json saying why, byte-identical on a second run; shards whose
plugin libraries differ are not merged; `corridorsim test` reports a failed pipeline as an error
case.

usage: cli_plugin_test.py CORRIDORSIM PLUGIN_DIR SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

# What these runs and studies check is their results: plots/ and the pages are left out
# (scripts.plot_run, viewer.browser and viewer.odd_data test those).
NO_EXTRAS = ["--no-plots", "--no-viewer"]


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def run(args, expect):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != expect:
        fail("%s exited %d (expected %d)\nstdout:\n%s\nstderr:\n%s" %
             (" ".join(args), p.returncode, expect, p.stdout[-2000:], p.stderr[-2000:]))
    return p


def read(path):
    with open(path, "rb") as f:
        return f.read()


def write_scenario(path, base, duration_s, plugin, pipelines, sensors="", expectations="[]",
                   study=""):
    """`base` for `duration_s` with `plugin` loaded and its camera pipelines off: the odometry
    pipeline and `pipelines` (YAML lines) run."""
    with open(path, "w") as f:
        f.write(base + "duration_s: %d\n" % duration_s +
                "plugins: [%s]\n" % plugin + sensors +
                "pipelines:\n"
                "  p1_harris: {enabled: false}\n"
                "  p1_vp_doorplate: {enabled: false}\n" + pipelines +
                "expectations: %s\n" % expectations + study)
    return path


def failed_run(corridorsim, scenario, folder):
    """Runs `scenario` into `folder`, where a pipeline fails (exit 5): its metrics' pipelines and
    its pipeline_failed events."""
    run([corridorsim, "run", scenario, "--out", folder, *NO_EXTRAS], 5)
    metrics = json.loads(read(os.path.join(folder, "metrics.json")))["pipelines"]
    events = json.loads(read(os.path.join(folder, "events.json")))["events"]
    return metrics, [e for e in events if e["type"] == "pipeline_failed"]


def main():
    corridorsim, plugins, source, work = (os.path.abspath(a) for a in sys.argv[1:5])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    echo = os.path.join(plugins, "test_echo_plugin.so")

    # corridorsim plugin: what a library registers, or why it is refused.
    out = run([corridorsim, "plugin", echo], 0).stdout
    for part in ["plugin test_echo_plugin 2.5.0", "## pipeline type `test_echo`",
                 "| `scale` |  | 1 | [0.5, 2] |", "sha256 "]:
        if part not in out:
            fail("`corridorsim plugin` printed no %r:\n%s" % (part, out))
    err = run([corridorsim, "plugin", os.path.join(plugins, "test_broken_plugin_2.so")], 2).stderr
    if err.count("\n") != 1 or "command line: library: the plugin library" not in err or \
            "SDK ABI version" not in err:
        fail("a plugin of another ABI: expected one message naming both versions, got:\n" + err)

    # A plugin built with the old std::string ABI fails in dlopen, before the ABI check: one
    # message with the symbol demangled and what to rebuild, exit 2.
    err = run([corridorsim, "plugin", os.path.join(plugins, "test_old_string_abi_plugin.so")],
              2).stderr
    for part in ["undefined symbol: corridorsim::slam::IsPipelineName(std::string const&)",
                 "_GLIBCXX_USE_CXX11_ABI=1", "by the compiler corridorsim was built with"]:
        if err.count("\n") != 1 or part not in err:
            fail("a plugin of the old std::string ABI: expected one message with %r, got:\n%s"
                 % (part, err))

    # A scenario naming a library that cannot load: exit 2 at its line, nothing written.
    base = "include: %s/scenarios/default.yaml\n" % source
    bad = os.path.join(work, "bad.yaml")
    with open(bad, "w") as f:
        f.write(base + "plugins:\n  - %s\n  - no_such_plugin.so\n" % echo)
    err = run([corridorsim, "run", bad, "--out", os.path.join(work, "bad_out")], 2).stderr
    if "bad.yaml:4:5: plugins: the plugin library" not in err or "does not exist" not in err:
        fail("a missing plugin library: " + err)
    if os.path.exists(os.path.join(work, "bad_out")):
        fail("a bad plugin still created the run folder")

    # A plugin that throws mid-run fails alone.
    scenario = write_scenario(os.path.join(work, "throws.yaml"), base, 8, echo,
                              "  echo: {type: test_echo, throw_after_s: 3}\n",
                              expectations="[odometry.ate_rmse_m < 10, echo.ate_rmse_m < 10]")
    folders = []
    for k in (1, 2):
        folder = os.path.join(work, "run%d" % k)
        p = run([corridorsim, "run", scenario, "--out", folder, *NO_EXTRAS], 5)
        if "pipeline 'echo' failed at t = 3.0" not in p.stderr or \
                "the wheels went out of sync" not in p.stderr:
            fail("the failure is not on stderr:\n" + p.stderr)
        folders.append(folder)
    metrics = json.loads(read(os.path.join(folders[0], "metrics.json")))
    if metrics["pipelines"]["echo"] != {"health": {"failed": 1}}:
        fail("the failed pipeline's metrics: %s" % metrics["pipelines"]["echo"])
    if "ate_rmse_m" not in metrics["pipelines"]["odometry"]:
        fail("the other pipeline has no results: %s" % metrics["pipelines"]["odometry"])
    passed = {e["text"]: e["passed"] for e in metrics["expectations"]}
    if passed != {"odometry.ate_rmse_m < 10": True, "echo.ate_rmse_m < 10": False}:
        fail("expectations: %s" % passed)
    events = json.loads(read(os.path.join(folders[0], "events.json")))["events"]
    failures = [e for e in events if e["type"] == "pipeline_failed"]
    if len(failures) != 1 or failures[0]["pipeline"] != "echo" or \
            failures[0]["call"] != "OnOdometry" or \
            failures[0]["reason"] != "test_echo: the wheels went out of sync" or \
            not 3.0 < failures[0]["t"] < 3.1:
        fail("events.json failures: %s" % failures)
    times = [e["t_ns"] for e in events]
    if times != sorted(times):
        fail("events.json is not in time order")
    for name in ["metrics.json", "events.json", "odometry.tum", "echo.tum", "scenario.yaml"]:
        if read(os.path.join(folders[0], name)) != read(os.path.join(folders[1], name)):
            fail("%s differs between two runs of the same seed" % name)

    # The same from a camera frame, while another pipeline processes the same frame concurrently.
    camera = write_scenario(os.path.join(work, "camera.yaml"), base, 4, echo,
                            "  sees: {type: test_echo, read_upward: true, throw_after_s: 2}\n"
                            "  also: {type: test_echo, read_upward: true}\n"
                            "  bad: {type: test_echo, read_upward: true, bad_detection: true}\n",
                            sensors="sensors:\n"
                                    "  front: {enabled: false}\n"
                                    "  lateral: {enabled: false}\n"
                                    "  upward: {enabled: true, rate_hz: 5}\n")
    folder = os.path.join(work, "camera")
    metrics, failures = failed_run(corridorsim, camera, folder)
    frames = json.loads(read(os.path.join(folder, "timing.json")))["pipelines"]["also"]["frames"]
    if metrics["sees"] != {"health": {"failed": 1}} or "ate_rmse_m" not in metrics["also"] or \
            metrics["bad"] != {"health": {"failed": 1}} or frames < 15:
        fail("a camera-reading pipeline that throws: %s (the other saw %s frames)" %
             (metrics, frames))
    # A malformed detection fails its pipeline at the first frame, as a throw would.
    if [(e["pipeline"], e["call"], e["reason"]) for e in failures] != \
            [("bad", "TakeDetections",
              "reported a lamp detection that is a lamp without a positive radius"),
             ("sees", "OnCamera", "test_echo: the camera went dark")]:
        fail("events.json failures: %s" % failures)

    # The scenario's IMUs and scanners reach a plugin (OnImu, OnScan), and a throw there fails
    # that pipeline alone, named by the call.
    pipelines = {"imu": "imu_throw_after_s: 1", "scan": "scan_throw_after_s: 2", "calm": "scale: 1"}
    sensors = write_scenario(
        os.path.join(work, "sensors.yaml"), base, 4, echo,
        "".join("  %s: {type: test_echo, %s}\n" % item for item in pipelines.items()),
        sensors="sensors: {imu0: {type: imu, rate_hz: 100}, lidar: {type: laser, rate_hz: 10}}\n")
    metrics, failed = failed_run(corridorsim, sensors, os.path.join(work, "sensors"))
    failures = [(e["pipeline"], e["call"], e["reason"].split(" read ")[0].split(" swept ")[0],
                 round(e["t"], 2)) for e in failed]
    if failures != [("imu", "OnImu", "test_echo: IMU imu0", 1.01),
                    ("scan", "OnScan", "test_echo: scanner lidar", 2.1)] or \
            "ate_rmse_m" not in metrics["calm"]:
        fail("a plugin's OnImu and OnScan: %s; calm: %s" % (failures, metrics["calm"]))
    print("ok: a plugin receives the IMU's samples and the scanner's sweeps; a throw there fails "
          "it alone")

    # Measurement types of a pipeline's own: declared ones get NIS in metrics.json (and an
    # expectation may bound it); an undeclared one or a wrong dof fails that pipeline at once.
    pipelines = {"own": "own_measurement: true",
                 "stray": "own_measurement: true, undeclared_after_s: 1",
                 "wrong": "own_measurement: true, reported_dof: 2",
                 "late": "finish_detection: true"}
    own = write_scenario(
        os.path.join(work, "own.yaml"), base, 3, echo,
        "".join("  %s: {type: test_echo, %s}\n" % item for item in pipelines.items()),
        expectations="[own.nis.wheel_yaw.mean < 0.6, own.nis.wheel_yaw.mean > 0.4]")
    metrics, failed = failed_run(corridorsim, own, os.path.join(work, "own"))
    nis = metrics["own"].get("nis", {}).get("wheel_yaw", {})
    count = nis.get("count", 0)
    mean = 0.5 * sum(k % 3 for k in range(count)) / max(count, 1)  # NIS 0, 0.5, 1, 0, ...
    if count < 90 or abs(nis.get("mean", -1) - mean) > 1e-6 or \
            list(metrics["own"]["nis"]) != ["wheel_yaw"]:
        fail("a declared measurement type's NIS: %s" % metrics["own"].get("nis"))
    failures = [(e["pipeline"], e["call"], e["reason"]) for e in failed]
    if failures != [
            ("wrong", "TakeInnovations", "reported an innovation of 'wheel_yaw' that has 2 "
             "degrees of freedom, but the type was declared with 1"),
            ("stray", "TakeInnovations", "reported an innovation of 'wall_line' that is of a "
             "measurement type it did not declare (Pipeline::measurement_types: wheel_yaw (1 dof))"),
            ("late", "Finish", "reported a wall_line detection that is of a measurement type it "
             "did not declare (Pipeline::measurement_types: none)")]:
        fail("undeclared and wrong-dof measurement types: %s" % failures)
    passed = [e["passed"] for e in json.loads(read(os.path.join(work, "own", "metrics.json")))[
        "expectations"]]
    if passed != [True, True]:
        fail("expectations on a declared type's NIS: %s" % passed)
    nis_csv = read(os.path.join(work, "own", "own_nis.csv")).decode().splitlines()
    if nis_csv[0] != "t,type,dof,nis,accepted" or not nis_csv[1].split(",")[1:] == \
            ["wheel_yaw", "1", "0.000000", "1"]:
        fail("own_nis.csv: %s" % nis_csv[:3])
    print("ok: a plugin's own measurement types get NIS; undeclared ones fail it at once")

    # Shards whose plugin libraries differ are not merged: the plan records each one's SHA-256.
    lib = os.path.join(work, "lib")
    os.makedirs(lib)
    shutil.copy(echo, os.path.join(lib, "echo.so"))
    study = write_scenario(os.path.join(work, "study.yaml"), base, 4, "lib/echo.so",
                           "  echo: {type: test_echo}\n", study="study: {runs: 2}\n")
    run([corridorsim, "study", study, "--shard", "1/2", *NO_EXTRAS, "--out",
         os.path.join(work, "shard1")], 0)
    with open(os.path.join(lib, "echo.so"), "ab") as f:
        f.write(b"rebuilt")  # still a loadable library, with other bytes
    run([corridorsim, "study", study, "--shard", "2/2", *NO_EXTRAS, "--out",
         os.path.join(work, "shard2")], 0)
    err = run([corridorsim, "study", "merge", os.path.join(work, "shard1"),
               os.path.join(work, "shard2"), "--out", os.path.join(work, "merged")], 2).stderr
    if "the plugin library %s differs (SHA-256 " % os.path.realpath(os.path.join(lib, "echo.so")) \
            not in err:
        fail("a merge of shards with different plugin libraries: " + err)
    if os.path.exists(os.path.join(work, "merged")):
        fail("a refused merge wrote its folder")

    # corridorsim test: the failure is an error case; the run's exit 1.
    junit = os.path.join(work, "junit.xml")
    run([corridorsim, "test", scenario, "--junit", junit, "--out", os.path.join(work, "test")], 1)
    cases = ET.parse(junit).getroot().findall(".//testcase")
    errors = [c.get("name") for c in cases if c.find("error") is not None]
    failures = [c.get("name") for c in cases if c.find("failure") is not None]
    if errors != ["pipeline failed"] or failures != ["echo.ate_rmse_m < 10"]:
        fail("junit.xml: errors %s, failures %s" % (errors, failures))


if __name__ == "__main__":
    main()
    print("cli_plugin_test: ok")
