#!/usr/bin/env python3
"""`corridorsim evaluate` as a user runs it.

On a short real run: the run's own files scored with --align none give metrics.json's numbers
(to the files' rounding), the same command twice gives the same bytes. On a hand-made run folder
(the real run's world, a curved truth written by hand): a copy of the truth scaled by 3, rotated
and moved is brought to zero by sim3 and not by se3; a 0.3/-0.4 m offset is a 0.5 m ATE; an ov_eval
file whose sigma matches its error has NEES 1; a landmark map is scored by type. Then --expect
(exit 3), a failing plot script (exit 4, results kept) and bad input (exit 2, one message naming
the file and line or the flag, nothing written).

Then the folder rules: a run folder whose scenario.yaml names a plugin library and an external
program, each leaving a marker when it runs, is evaluated with --frame and neither marker appears;
an --out that is, contains or lies inside an input is refused (exit 2, naming --out); and a file
one pose over the maximum is refused at that line.

Usage: cli_evaluate_test.py CORRIDORSIM SOURCE_DIR WORK_DIR CXX_COMPILER"""

import json
import math
import os
import re
import shutil
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(binary, args, expect, env=None):
    """Runs it; its exit code must be `expect` (None: any)."""
    result = subprocess.run([binary] + args, capture_output=True, text=True, env=env)
    if expect is not None and result.returncode != expect:
        fail("%s: exit %d, expected %d\n%s\n%s" % (" ".join(args), result.returncode, expect,
                                                   result.stdout, result.stderr))
    return result


def close(what, a, b, tol):
    if a is None or b is None or abs(a - b) > tol:
        fail("%s: %r vs %r (tolerance %g)" % (what, a, b, tol))


def quaternion_of(m):
    """(x, y, z, w) of a rotation matrix (rows), w >= 0."""
    w = math.sqrt(max(0.0, 1.0 + m[0][0] + m[1][1] + m[2][2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + m[0][0] - m[1][1] - m[2][2])) / 2.0, m[2][1] - m[1][2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - m[0][0] + m[1][1] - m[2][2])) / 2.0, m[0][2] - m[2][0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - m[0][0] - m[1][1] + m[2][2])) / 2.0, m[1][0] - m[0][1])
    return x, y, z, w


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rot_z(a):
    return [[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]


def rot_x(a):
    return [[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]]


def arc(seconds=20.0):
    """A left arc at 1 m/s, radius 20 m, on the 100 Hz grid: [(t_ns, x, y, yaw)]."""
    out = []
    for k in range(int(seconds * 100) + 1):
        s = 0.01 * k
        yaw = s / 20.0
        out.append((k * 10_000_000, 20.0 * math.sin(yaw), 20.0 * (1.0 - math.cos(yaw)), yaw))
    return out


def tum_lines(poses, scale=1.0, rotation=None, translation=(0.0, 0.0, 0.0), extra=None):
    """Every other pose as TUM lines, moved by x -> scale R x + t (orientation R Rz(yaw))."""
    rotation = rotation or rot_z(0.0)
    lines = []
    for i, (t_ns, x, y, yaw) in enumerate(poses[::2]):
        p = [scale * sum(rotation[r][c] * v for c, v in enumerate((x, y, 0.0))) + translation[r]
             for r in range(3)]
        q = quaternion_of(matmul(rotation, rot_z(yaw)))
        line = "%d.%09d %.9f %.9f %.9f %.12f %.12f %.12f %.12f" % (
            t_ns // 1_000_000_000, t_ns % 1_000_000_000, *p, *q)
        lines.append(line + (" " + extra if extra else ""))
    return "\n".join(lines) + "\n"


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def main(corridorsim, source_dir, work, compiler):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    # --- A short real run: the run's own files give metrics.json's numbers. ---------------------
    write(os.path.join(work, "short.yaml"),
          "include: %s/scenarios/p3_lamps.yaml\nduration_s: 30\n"
          "pipelines:\n  p3_corners: {enabled: false}\nexpectations: []\n" % source_dir)
    real = os.path.join(work, "run")
    export = os.path.join(work, "export")
    run(corridorsim, ["run", os.path.join(work, "short.yaml"), "--out", real, "--no-plots",
                      "--no-viewer", "--export", export], 0)
    metrics = json.load(open(os.path.join(real, "metrics.json")))["pipelines"]
    args = ["evaluate", real, "--estimate", "odometry=%s/odometry_cov.txt" % real,
            "--estimate", "p3_upward=%s/p3_upward.tum" % real,
            "--landmarks", "p3_upward=%s/p3_upward_landmarks.json" % real]
    first, second = os.path.join(work, "eval1"), os.path.join(work, "eval2")
    run(corridorsim, args + ["--out", first], 0)
    run(corridorsim, args + ["--out", second, "--no-plots"], 0)
    evaluation = json.load(open(os.path.join(first, "evaluation.json")))
    if evaluation["alignment"] != "none" or evaluation["max_dt_s"] != 0.01:
        fail("defaults: %s" % evaluation)
    for name in ("odometry", "p3_upward"):
        e, m = evaluation["estimates"][name], metrics[name]
        for key in ("samples", "samples_without_truth", "rpe_1m_pairs", "rpe_5m_pairs"):
            if e[key] != m[key]:
                fail("%s.%s: %s vs metrics.json %s" % (name, key, e[key], m[key]))
        # Positions in the files are rounded to 1 um, headings to 1e-9 of a quaternion.
        for key in ("ate_rmse_m", "ate_mean_m", "ate_max_m", "ate_aligned_rmse_m",
                    "rpe_1m_trans_rmse_m", "final_position_error_m"):
            close("%s.%s" % (name, key), e[key], m[key], 3e-6)
        for key in ("ate_yaw_rmse_rad", "rpe_1m_yaw_rmse_rad", "final_yaw_error_rad"):
            close("%s.%s" % (name, key), e[key], m[key], 1e-7)
    if "nees_mean" not in evaluation["estimates"]["odometry"]:
        fail("the ov_eval file gave no NEES")
    if "nees_mean" in evaluation["estimates"]["p3_upward"]:
        fail("a TUM file gave a NEES")
    lamp_e = evaluation["estimates"]["p3_upward"]["map"]["lamp"]
    lamp_m = metrics["p3_upward"]["map"]["lamp"]
    for key in ("estimated", "matched", "spurious"):
        if lamp_e[key] != lamp_m[key]:
            fail("map.lamp.%s: %s vs metrics.json %s" % (key, lamp_e[key], lamp_m[key]))
    close("map.lamp.rmse_m", lamp_e["rmse_m"], lamp_m["rmse_m"], 3e-6)
    for f in sorted(os.listdir(second)):
        if open(os.path.join(first, f), "rb").read() != open(os.path.join(second, f), "rb").read():
            fail("%s differs between two evaluations" % f)
    for plot in ("trajectories.png", "errors_odometry.png", "nees_odometry.png",
                 "errors_p3_upward.png"):
        if not os.path.isfile(os.path.join(first, "plots", plot)):
            fail("plots/%s missing" % plot)

    # A camera's trajectory (what a visual system run on the export estimates): the truth times
    # the export's T_BS (body_from_sensor) is world_from_camera; --frame brings it back to the
    # robot through the run's mount, without it the lever arm is the error.
    sensor = open(os.path.join(export, "euroc", "mav0", "cam0", "sensor.yaml")).read()
    data = sensor[sensor.index("data:", sensor.index("T_BS")):]
    t_bs = [float(v) for v in data[data.index("[") + 1:data.index("]")].split(",")]
    lines = []
    for line in open(os.path.join(real, "ground_truth.tum")):
        if line.startswith("#"):
            continue
        t, x, y, _, _, _, qz, qw = line.split()
        yaw = 2.0 * math.atan2(float(qz), float(qw))
        r = rot_z(yaw)
        r_bs = [t_bs[0:3], t_bs[4:7], t_bs[8:11]]
        p = [sum(r[i][k] * t_bs[4 * k + 3] for k in range(3)) + (float(x), float(y), 0.0)[i]
             for i in range(3)]
        q = quaternion_of(matmul(r, r_bs))
        lines.append("%s %.9f %.9f %.9f %.12f %.12f %.12f %.12f" % (t, *p, *q))
    write(os.path.join(work, "camera.tum"), "\n".join(lines) + "\n")
    frame_out = os.path.join(work, "eval_frame")
    run(corridorsim, ["evaluate", real, "--estimate", "cam=%s/camera.tum" % work, "--frame",
                      "cam=upward", "--estimate", "raw=%s/camera.tum" % work, "--out", frame_out,
                      "--no-plots"], 0)
    est = json.load(open(os.path.join(frame_out, "evaluation.json")))["estimates"]
    close("--frame ate_3d_rmse_m", est["cam"]["ate_3d_rmse_m"], 0.0, 3e-6)
    close("--frame rotation_rmse_rad", est["cam"]["rotation_rmse_rad"], 0.0, 1e-6)
    close("no --frame ate_rmse_m (the mount's lever arm)", est["raw"]["ate_rmse_m"],
          math.hypot(t_bs[3], t_bs[7]), 1e-5)
    result = run(corridorsim, ["evaluate", real, "--estimate", "cam=%s/camera.tum" % work,
                               "--frame", "cam=front", "--out", frame_out + "_bad"], 2)
    if "--frame: camera 'front' is not enabled" not in result.stderr:
        fail("--frame of a disabled camera: " + result.stderr)

    # --- A hand-made run folder: errors known by hand. -------------------------------------------
    hand = os.path.join(work, "hand")
    os.makedirs(hand)
    shutil.copy(os.path.join(real, "world.json"), hand)
    truth = arc()
    # ground_truth.tum: every grid point, planar (tum_lines takes every other pose).
    lines = ["%d.%09d %.9f %.9f 0 0 0 %.12f %.12f" % (t // 10**9, t % 10**9, x, y,
                                                       math.sin(yaw / 2), math.cos(yaw / 2))
             for (t, x, y, yaw) in truth]
    write(os.path.join(hand, "ground_truth.tum"), "\n".join(lines) + "\n")
    rotation = matmul(rot_z(math.radians(40.0)), rot_x(math.radians(15.0)))
    write(os.path.join(work, "mono.tum"), tum_lines(truth, 3.0, rotation, (2.0, -1.0, 0.5)))
    write(os.path.join(work, "offset.tum"), tum_lines(truth, translation=(0.3, -0.4, 0.0)))
    # sigma_x 0.3 m, sigma_y 0.4 m: the offset is one sigma in each: NEES 2 (x, y) + 0 (yaw).
    cov = "0 0 0 0 0 0.0001 0.09 0 0 0.16 0 0"
    write(os.path.join(work, "offset_cov.txt"), tum_lines(truth, translation=(0.3, -0.4, 0.0),
                                                          extra=cov))

    def evaluate(extra, expect=0, env=None):
        out = os.path.join(work, "out_%d" % evaluate.n)
        evaluate.n += 1
        result = run(corridorsim, ["evaluate", hand, "--out", out, "--no-plots"] + extra, expect,
                     env)
        path = os.path.join(out, "evaluation.json")
        return (json.load(open(path))["estimates"] if os.path.exists(path) else None), result
    evaluate.n = 0

    est, _ = evaluate(["--estimate", "mono=%s/mono.tum" % work, "--align", "sim3"])
    mono = est["mono"]
    close("sim3 ate_3d_rmse_m", mono["ate_3d_rmse_m"], 0.0, 2e-6)
    close("sim3 rotation_rmse_rad", mono["rotation_rmse_rad"], 0.0, 1e-6)
    close("sim3 rpe_5m_trans_rmse_m", mono["rpe_5m_trans_rmse_m"], 0.0, 2e-6)
    close("sim3 scale", mono["align"]["scale"], 1.0 / 3.0, 1e-6)
    est, _ = evaluate(["--estimate", "mono=%s/mono.tum" % work, "--align", "se3"])
    if est["mono"]["ate_3d_rmse_m"] < 1.0:
        fail("se3 removed a scale of 3: %s" % est["mono"]["ate_3d_rmse_m"])

    est, result = evaluate(["--estimate", "offset=%s/offset.tum" % work,
                            "--estimate", "cov=%s/offset_cov.txt" % work,
                            "--expect", "offset.ate_rmse_m<0.6", "--expect", "cov.nees_mean<=2.01"])
    close("offset ate_rmse_m", est["offset"]["ate_rmse_m"], 0.5, 2e-6)
    close("offset final_position_error_m", est["offset"]["final_position_error_m"], 0.5, 2e-6)
    close("offset ate_aligned_rmse_m", est["offset"]["ate_aligned_rmse_m"], 0.0, 2e-6)
    close("cov nees_mean", est["cov"]["nees_mean"], 2.0, 1e-5)
    if result.stdout.count("PASS") != 2:
        fail("expectations not reported:\n" + result.stdout)
    est, result = evaluate(["--estimate", "offset=%s/offset.tum" % work, "--align", "se2",
                            "--expect", "offset.ate_rmse_m<0.6", "--expect",
                            "offset.align.scale>1"], expect=3)
    if "FAIL  offset.align.scale>1" not in result.stdout or est is None:
        fail("a failed --expect: exit 3 with its line and the results written\n" + result.stdout)

    # A map in the estimate's frame moves with its alignment: lamps of world.json shifted like
    # the offset estimate come back to 0 error with se2.
    world = json.load(open(os.path.join(hand, "world.json")))
    lamps = [{"id": i, "type": "lamp", "position_in_world":
              [l["center"][0] + 0.3, l["center"][1] - 0.4, l["center"][2]]}
             for i, l in enumerate(world["lamps"])]
    write(os.path.join(work, "lamps.json"), json.dumps(lamps))
    est, _ = evaluate(["--estimate", "offset=%s/offset.tum" % work, "--align", "se2",
                       "--landmarks", "offset=%s/lamps.json" % work,
                       "--landmarks", "raw=%s/lamps.json" % work])
    close("aligned map.lamp.rmse_m", est["offset"]["map"]["lamp"]["rmse_m"], 0.0, 2e-6)
    if est["offset"]["map"]["lamp"]["matched"] != len(lamps):
        fail("aligned lamps not all matched: %s" % est["offset"]["map"]["lamp"])
    close("unaligned map.lamp.rmse_m", est["raw"]["map"]["lamp"]["rmse_m"], 0.5, 2e-6)

    # A plot script that fails: exit 4, the results kept.
    env = dict(os.environ, CORRIDORSIM_PYTHON="/bin/false")
    out = os.path.join(work, "plots_fail")
    result = run(corridorsim, ["evaluate", hand, "--out", out, "--estimate",
                               "offset=%s/offset.tum" % work], 4, env)
    if not os.path.isfile(os.path.join(out, "evaluation.json")) or "plots/" not in result.stderr:
        fail("exit 4 without its results or message:\n" + result.stderr)

    # --- Bad input: exit 2, one message, nothing written. ---------------------------------------
    write(os.path.join(work, "bad.tum"), "# t x y z qx qy qz qw\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n")
    write(os.path.join(work, "back.tum"), "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n")
    write(os.path.join(work, "line.tum"), "".join("%d 0 0 0 0 0 0 1\n" % k for k in range(1, 50)))
    bad = [
        (["evaluate", os.path.join(work, "none"), "--estimate", "a=%s/offset.tum" % work],
         "command line: RUN_DIR: no such folder"),
        (["evaluate", hand, "--estimate", "a=%s/missing.tum" % work], "missing.tum: "),
        (["evaluate", hand, "--estimate", "a=%s/bad.tum" % work],
         "bad.tum:3:1: 7 columns where line 2 has 8"),
        (["evaluate", hand, "--estimate", "a=%s/back.tum" % work],
         "back.tum:2:1: stamp '0.5' is not after the previous pose's"),
        (["evaluate", hand, "--estimate", "a=%s/line.tum" % work, "--align", "se3"],
         "command line: --estimate: a: se3 alignment needs positions that do not all lie on "
         "one line"),
        (["evaluate", hand, "--estimate", "a=%s/offset.tum" % work, "--expect", "b.ate_rmse_m<1"],
         "command line: --expect: 'b' is no --estimate or --landmarks name"),
        (["evaluate", hand, "--estimate", "a=%s/offset.tum" % work, "--expect", "a.timing.steps<1"],
         "command line: --expect: unknown metric 'timing.steps'"),
        (["evaluate", work, "--estimate", "a=%s/offset.tum" % work],
         "ground_truth.tum: "),
        (["evaluate", hand, "--landmarks", "a=%s/bad.tum" % work], "bad.tum"),
    ]
    for i, (args, message) in enumerate(bad):
        out = os.path.join(work, "bad_out_%d" % i)
        result = run(corridorsim, args + ["--out", out], 2)
        lines = result.stderr.strip().split("\n")
        if len(lines) != 1 or not re.search(message, lines[0]):
            fail("%s: expected one message matching '%s', got:\n%s" % (args, message,
                                                                         result.stderr))
        if os.path.exists(out):
            fail("%s: bad input wrote %s" % (args, out))
    # An output folder that holds files is kept unless --force.
    out = os.path.join(work, "out_0")
    result = run(corridorsim, ["evaluate", hand, "--out", out, "--estimate",
                               "a=%s/offset.tum" % work], 2)
    if "--out" not in result.stderr or "--force" not in result.stderr:
        fail("a non-empty --out: " + result.stderr)
    run(corridorsim, ["evaluate", hand, "--out", out, "--force", "--no-plots", "--estimate",
                      "a=%s/offset.tum" % work], 0)

    # --- Reading a folder runs nothing of it. ----------------------------------------------------
    # A run folder whose scenario.yaml names a plugin library that leaves a marker when loaded and
    # an external program that leaves one when started: --frame reads the mounts, and neither
    # marker appears. (The library is real: built here, it does leave its marker when loaded.)
    evil = os.path.join(work, "evil_run")
    shutil.copytree(real, evil)
    plugin_marker = os.path.join(work, "plugin_was_loaded")
    program_marker = os.path.join(work, "program_was_started")
    write(os.path.join(work, "marker.cpp"),
          '#include <fstream>\nstruct Marker { Marker() { std::ofstream("%s") << "x"; } };\n'
          'static Marker marker;\n' % plugin_marker)
    library = os.path.join(evil, "evil.so")
    subprocess.run([compiler, "-shared", "-fPIC", "-o", library, os.path.join(work, "marker.cpp")],
                   check=True)
    scenario = open(os.path.join(real, "scenario.yaml")).read()
    scenario = scenario.replace("\npipelines:\n", "\nplugins: [evil.so]\npipelines:\n"
                                "  evil:\n    type: external\n"
                                "    command: [/bin/sh, -c, 'touch %s']\n" % program_marker, 1)
    if "evil.so" not in scenario:
        fail("the run's scenario.yaml has no pipelines: to add to")
    write(os.path.join(evil, "scenario.yaml"), scenario)
    run(corridorsim, ["evaluate", evil, "--estimate", "cam=%s/camera.tum" % work, "--frame",
                      "cam=upward", "--out", os.path.join(work, "eval_evil"), "--no-plots"], 0)
    for marker in (plugin_marker, program_marker):
        if os.path.exists(marker):
            fail("evaluate of a run folder ran code from it: %s exists" % marker)
    est = json.load(open(os.path.join(work, "eval_evil", "evaluation.json")))["estimates"]
    close("--frame of the evil folder", est["cam"]["ate_3d_rmse_m"], 0.0, 3e-6)
    # The control: a scenario that loads the library does leave the marker.
    run(corridorsim, ["run", os.path.join(evil, "scenario.yaml"), "--check"], None)
    if not os.path.exists(plugin_marker):
        fail("the marker library leaves no marker when loaded: the check above proves nothing")

    # --- No output is, contains or lies inside an input. -----------------------------------------
    before = sorted(os.listdir(hand))
    for args, message in [
        (["--out", hand, "--force"], "--out: '[^']*hand' contains '[^']*ground_truth.tum', a file "
                                     "of RUN_DIR"),
        (["--out", os.path.join(hand, "ground_truth.tum"), "--force"], "--out: .* is "),
        (["--out", work, "--force"], "--out: .* contains "),
        (["--out", os.path.join(work, "offset.tum", "x")], "--out: .* lies inside "),
        (["--out", os.path.join(work, "link_to_hand"), "--force"], "--out: .* contains "),
    ]:
        if not os.path.lexists(os.path.join(work, "link_to_hand")):
            os.symlink(hand, os.path.join(work, "link_to_hand"))
        result = run(corridorsim, ["evaluate", hand, "--estimate", "a=%s/offset.tum" % work,
                                   "--no-plots"] + args, 2)
        lines = result.stderr.strip().split("\n")
        if len(lines) != 1 or not re.search(message, lines[0]):
            fail("%s: expected one message matching '%s', got:\n%s" % (args, message,
                                                                         result.stderr))
    if sorted(os.listdir(hand)) != before:
        fail("a refused --out changed the run folder: %s" % sorted(os.listdir(hand)))

    # --- The maxima: one pose over kMaxTrajectoryPoses is refused at its line. -------------------
    big = os.path.join(work, "over_maximum.tum")
    maximum = 10_000_000
    with open(big, "w") as f:
        block = 100_000
        for start in range(0, maximum + 1, block):
            f.write("".join("%d.%06d 0 0 0 0 0 0 1\n" % (k // 10**6, k % 10**6)
                            for k in range(start + 1, min(start + block, maximum + 1) + 1)))
    result = run(corridorsim, ["evaluate", hand, "--estimate", "big=" + big, "--no-plots",
                               "--out", os.path.join(work, "over_out")], 2)
    if not re.search(r"over_maximum.tum:10000001:1: more than 10000000 poses", result.stderr):
        fail("one pose over the maximum: " + result.stderr)
    os.remove(big)
    print("ok")


if __name__ == "__main__":
    if len(sys.argv) != 5:
        fail(__doc__)
    main(*sys.argv[1:])
