"""corridorsim.files and corridorsim.analysis (docs/analysis.md) on hand-made folders: the strict
readers and their file:line errors, the runner's arithmetic (RoundToStep's halves, NormalizeAngle,
truth interpolation, non-finite estimates, ATE / RPE / final error against an independent numpy
computation), Study's tables and paired comparison, Dataset's two layouts, and the lazy import.
No simulator needed; scripts/check_analysis.py checks the exactness on real runs."""

import json
import math
import os
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest

import corridorsim
from corridorsim import analysis, dataset_files, files
from corridorsim.analysis import Dataset, Run, Study, normalize_angle, round_to_step
from corridorsim.files import InputError

PYTHON_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


# ------------------------------------------------------------------------------------------------
# Writers of hand-made folders (the formats of harness/run/run_folder.cpp and run_io.cpp)

def tum_line(t_ns, x, y, yaw):
    """sim::TumLine of a planar pose: seconds from the integer, 6 decimals, quaternion with 9."""
    return (f"{t_ns // 10**9}.{t_ns % 10**9:09d} {x:.6f} {y:.6f} {0.0:.6f} {0.0:.9f} {0.0:.9f} "
            f"{math.sin(yaw / 2):.9f} {math.cos(yaw / 2):.9f}")


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def write_json(path, value):
    write(path, json.dumps(value, indent=2) + "\n")


def truth_poses(n=201, dt_ns=100_000_000):
    """A robot driving at 0.5 m/s and turning slowly: (t_ns, x, y, yaw) every 0.1 s."""
    out = []
    for i in range(n):
        t = i * dt_ns / 1e9
        yaw = 0.05 * t
        out.append((i * dt_ns, 0.5 * t + 0.02 * math.sin(t), 0.01 * t * t, yaw))
    return out


def write_run(run_dir, estimates=None, pipelines=("offset",)):
    """A run folder: the truth, one estimate 0.1 m ahead in x (or `estimates`), its covariance,
    errors, NIS, landmarks, events and a metrics.json holding only counts (filled by the tests
    from the Python side where they need numbers)."""
    truth = truth_poses()
    write(os.path.join(run_dir, "ground_truth.tum"),
          "# ground truth\n# timestamp tx ty tz qx qy qz qw\n" +
          "".join(tum_line(*p) + "\n" for p in truth))
    if estimates is None:
        estimates = [(t, x + 0.1, y, yaw) for t, x, y, yaw in truth]
    for name in pipelines:
        write(os.path.join(run_dir, f"{name}.tum"), f"# {name}: estimated world_from_robot\n" +
              "".join(tum_line(*p) + "\n" for p in estimates))
        write(os.path.join(run_dir, f"{name}_cov.txt"),
              "# header\n" + "".join(tum_line(*p) + f" 0 0 0 0 0 {1e-4:.9e} {4e-2:.9e} "
                                     f"{1e-3:.9e} 0 {9e-2:.9e} 0 0\n" for p in estimates))
        write(os.path.join(run_dir, f"{name}_errors.csv"),
              "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n"
              "0.000000000,0.100000,0.000000,0.00000000,0.200000,0.300000,0.01000000,0.25\n"
              "0.100000000,0.100000,0.000000,0.00000000,,,,\n")
        write(os.path.join(run_dir, f"{name}_nis.csv"),
              "t,type,dof,nis,accepted\n1.000000000,lamp,2,1.500000,1\n"
              "2.000000000,door_plate,3,30.250000,0\n")
        write_json(os.path.join(run_dir, f"{name}_landmarks.json"), [
            {"id": 3, "type": "lamp", "status": "converged", "label": "",
             "position_in_world": [1.0, 2.0, 2.5],
             "covariance": [[0.01, 0.001, 0.0], [0.001, 0.02, 0.0], [0.0, 0.0, None]]}])
    write_json(os.path.join(run_dir, "metrics.json"), {
        "schema_version": 1, "run": {"sim_seconds": 20.0},
        "pipelines": {name: {"samples": len(estimates)} for name in pipelines},
        "expectations": [{"text": "offset.ate_rmse_m < 0.2", "measured": 0.1, "passed": True}]})
    write_json(os.path.join(run_dir, "world.json"), {
        "walls": [{"id": 1, "start": [0, -1.2], "end": [10, -1.2]}],
        "distractors": [{"id": 9, "class": "poster", "wall_id": 1, "center": [2.0, -1.19, 1.5],
                         "size": [0.5, 0.7], "normal": [0, 1, 0], "text": "42"}]})
    write_json(os.path.join(run_dir, "events.json"), {
        "seed": 7, "duration_s": 20.0,
        "events": [{"t": 1.5, "t_ns": 1500000000, "type": "slip", "wheel": "left",
                    "extra_distance_m": 0.001},
                   {"t": 20.0, "t_ns": 20000000000, "type": "path_done"}]})
    write_json(os.path.join(run_dir, "timing.json"), {"sim_seconds": 20.0})
    write_json(os.path.join(run_dir, "provenance.json"), {"version": "test"})
    write(os.path.join(run_dir, "scenario.yaml"), "seed: 7\nduration_s: 20\n")
    return truth, estimates


def reference_metrics(truth, estimates):
    """ATE, RPE and final error of the same poses, computed independently with numpy (homogeneous
    matrices, vectorised sums): agrees with the exact path to rounding."""
    def as_read(p):
        fields = [float(v) for v in tum_line(*p).split()]
        return fields[1], fields[2], 2.0 * math.atan2(fields[6], fields[7])

    t_truth = np.array([p[0] for p in truth])
    tp = np.array([as_read(p) for p in truth])
    rows = []
    for p in estimates:
        e = as_read(p)
        if not np.all(np.isfinite(e)) or p[0] < t_truth[0] or p[0] > t_truth[-1]:
            continue
        k = np.searchsorted(t_truth, p[0])
        if t_truth[k] == p[0]:
            tr = tp[k]
        else:
            f = (p[0] - t_truth[k - 1]) / (t_truth[k] - t_truth[k - 1])
            dyaw = math.remainder(tp[k][2] - tp[k - 1][2], 2 * math.pi)
            tr = np.array([*(tp[k - 1][:2] + f * (tp[k][:2] - tp[k - 1][:2])),
                           tp[k - 1][2] + f * dyaw])
        rows.append((e, tr))
    est = np.array([r[0] for r in rows])
    tru = np.array([r[1] for r in rows])
    err = np.hypot(est[:, 0] - tru[:, 0], est[:, 1] - tru[:, 1])
    out = {"ate_rmse_m": float(np.sqrt(np.mean(err ** 2))), "final_position_error_m": err[-1]}

    def matrix(p):
        c, s = math.cos(p[2]), math.sin(p[2])
        return np.array([[c, -s, p[0]], [s, c, p[1]], [0, 0, 1]])

    travelled = np.concatenate([[0], np.cumsum(np.hypot(*np.diff(tru[:, :2], axis=0).T))])
    for d in (1, 5, 10):
        trans, yaw = [], []
        for i in range(len(tru)):
            later = np.nonzero(travelled[i + 1:] - travelled[i] >= d)[0]
            if not len(later):
                break
            j = i + 1 + later[0]
            motion_t = np.linalg.inv(matrix(tru[i])) @ matrix(tru[j])
            motion_e = np.linalg.inv(matrix(est[i])) @ matrix(est[j])
            error = np.linalg.inv(motion_t) @ motion_e
            trans.append(np.hypot(error[0, 2], error[1, 2]))
            yaw.append(abs(math.atan2(error[1, 0], error[0, 0])))
        out[f"rpe_{d}m_trans_rmse_m"] = float(np.sqrt(np.mean(np.square(trans)))) if trans else None
        out[f"rpe_{d}m_yaw_rmse_rad"] = float(np.sqrt(np.mean(np.square(yaw)))) if yaw else None
    return out, len(rows)


# ------------------------------------------------------------------------------------------------
# The runner's arithmetic

def test_round_to_step_rounds_halves_away_from_zero_like_c():
    assert round_to_step(0.5, 1) == 1.0
    assert round_to_step(1.5, 1) == 2.0
    assert round_to_step(2.5, 1) == 3.0      # Python's round(2.5) is 2
    assert round_to_step(-2.5, 1) == -3.0
    assert round_to_step(0.49999999999999994, 1) == 0.0  # floor(x + 0.5) would give 1
    zero = round_to_step(-0.4, 1)
    assert zero == 0.0 and math.copysign(1.0, zero) == 1.0  # -0 becomes 0
    assert round_to_step(0.1234565, 1e6) == 0.123457 or round_to_step(0.1234565, 1e6) == 0.123456
    # exact half steps on the metric grid: 2.5e-6 m is 2.5 steps (x * 1e6 == 2.5 exactly)
    assert 2.5e-6 * 1e6 == 2.5 and round_to_step(2.5e-6, 1e6) == 3e-6
    assert round_to_step(0.07440649999, 1e6) == 0.074406
    assert round_to_step(0.11149995, 1e8) == 0.11149995
    assert math.isnan(round_to_step(math.nan, 1e6))


def test_normalize_angle_keeps_pi_and_moves_minus_pi():
    assert normalize_angle(math.pi) == math.pi
    assert normalize_angle(-math.pi) == math.pi
    assert normalize_angle(3 * math.pi) == math.pi
    assert normalize_angle(0.25) == 0.25
    assert abs(normalize_angle(2 * math.pi + 0.5) - 0.5) < 1e-15
    assert math.isnan(normalize_angle(math.inf))


def test_a_constant_offset_gives_its_ate_and_final_error(tmp_path):
    truth, estimates = write_run(str(tmp_path))
    run = Run(str(tmp_path))
    assert run.ate("offset") == 0.1
    assert run.final_error("offset") == 0.1
    assert run.ate_aligned("offset") < 0.001
    assert run.rpe("offset", 1) == 0.0 and run.rpe("offset", 1, "yaw") == 0.0
    m = run.trajectory_metrics("offset")
    assert m["samples"] == len(estimates) and m["samples_without_truth"] == 0
    assert m["rpe_1m_pairs"] > m["rpe_10m_pairs"] > 0
    # half the run: about 5 m, so no pair 10 m apart (metrics.json's null)
    write_run(str(tmp_path), estimates=estimates[:100])
    short = Run(str(tmp_path))
    assert short.rpe("offset", 10) is None and short.rpe("offset", 10, "yaw") is None
    assert short.trajectory_metrics("offset")["rpe_10m_pairs"] == 0


def test_exact_path_agrees_with_an_independent_computation(tmp_path):
    truth = truth_poses()
    # noise, a drift in heading, stamps between the truth's (interpolated), a NaN and poses
    # outside the truth's span
    rng = np.random.default_rng(3)
    estimates = []
    for k, (t, x, y, yaw) in enumerate(truth[:-1]):
        drift = 0.02 * k / len(truth)
        estimates.append((t + 37_000_000, x + 0.03 * rng.standard_normal() + drift,
                          y + 0.03 * rng.standard_normal(), yaw + drift + 0.01 * k % 0.2))
    estimates[10] = (estimates[10][0], math.nan, 0.0, 0.0)
    estimates.append((truth[-1][0] + 1, 1.0, 1.0, 0.0))  # after the truth's end
    write_run(str(tmp_path), estimates=estimates)
    run = Run(str(tmp_path))
    ref, count = reference_metrics(truth, estimates)
    m = run.trajectory_metrics("offset")
    assert m["samples"] == count == len(truth) - 2
    assert m["samples_without_truth"] == 1
    for key, value in ref.items():
        ours = m[key]
        assert (ours is None) == (value is None), key
        if value is not None:  # rounded to 1e-6 m or 1e-8 rad: half a step apart at most
            tolerance = (0.5e-6 if key.endswith("_m") else 0.5e-8) + 1e-12
            assert abs(ours - value) <= tolerance, (key, ours, value)
    matched = run.matched("offset")
    assert len(matched) == count
    assert matched["t_ns"].dtype == np.int64
    assert not np.isnan(matched["x"]).any()


def test_interpolation_between_truth_stamps(tmp_path):
    truth = [(0, 0.0, 0.0, 3.0), (100_000_000, 1.0, 2.0, -3.0)]
    write_run(str(tmp_path))
    write(os.path.join(tmp_path, "ground_truth.tum"), "".join(tum_line(*p) + "\n" for p in truth))
    write(os.path.join(tmp_path, "offset.tum"), tum_line(25_000_000, 0.0, 0.0, 0.0) + "\n" +
          tum_line(100_000_000, 1.0, 2.0, -3.0) + "\n")
    row = Run(str(tmp_path)).matched("offset").iloc[0]
    yaw_a = normalize_angle(2 * math.atan2(float(f"{math.sin(1.5):.9f}"),
                                           float(f"{math.cos(1.5):.9f}")))
    yaw_b = normalize_angle(2 * math.atan2(float(f"{math.sin(-1.5):.9f}"),
                                           float(f"{math.cos(-1.5):.9f}")))
    assert row["truth_x"] == 0.0 + 0.25 * (1.0 - 0.0)
    assert row["truth_y"] == 0.0 + 0.25 * (2.0 - 0.0)
    # the shorter arc: from 3 rad through pi to -3 rad
    assert row["truth_yaw"] == normalize_angle(yaw_a + 0.25 * normalize_angle(yaw_b - yaw_a))
    assert row["truth_yaw"] > 3.0


def test_trajectory_columns_are_exact(tmp_path):
    write_run(str(tmp_path))
    write(os.path.join(tmp_path, "offset.tum"),
          "# c\n12.300000001 1.000000 -2.000000 0.000000 0.000000000 0.000000000 0.479425539 "
          "0.877582562\n13.000000000 nan nan 0.000000 nan nan nan nan\n")
    trajectory = Run(str(tmp_path)).trajectory("offset")
    assert list(trajectory.columns) == ["t_ns", "t", "x", "y", "z", "qx", "qy", "qz", "qw", "yaw"]
    assert trajectory["t_ns"].dtype == np.int64
    assert trajectory["t_ns"].tolist() == [12_300_000_001, 13_000_000_000]
    assert trajectory["yaw"][0] == normalize_angle(2 * math.atan2(0.479425539, 0.877582562))
    assert math.isnan(trajectory["x"][1])


# ------------------------------------------------------------------------------------------------
# Run's other files and the readers' errors

def test_run_reads_every_file(tmp_path):
    write_run(str(tmp_path), pipelines=("b_second", "a_first"))
    run = Run(str(tmp_path))
    assert run.pipelines == ["b_second", "a_first"]  # metrics.json's order, not sorted
    assert run.metric("a_first", "samples") == 201
    assert run.expectations["passed"].tolist() == [True]
    assert len(run.truth) == 201 and run.truth["t_ns"].iloc[-1] == 20_000_000_000
    cov = run.covariance("a_first")
    assert len(cov.columns) == 10 + 12 + 4
    assert cov["var_x_m2"][0] == 4e-2 and cov["var_yaw_rad2"][0] == 1e-4
    assert cov["cov_xy_m2"][0] == 1e-3 and cov["Pt13"][0] == 0.0
    errors = run.errors("a_first")
    assert errors["nees"][0] == 0.25 and math.isnan(errors["nees"][1])
    nis = run.nis("a_first")
    assert nis["type"].tolist() == ["lamp", "door_plate"] and nis["accepted"].tolist() == [True,
                                                                                           False]
    landmarks = run.landmarks("a_first")
    assert landmarks["id"].tolist() == [3] and landmarks["cov_xy"][0] == 0.001
    assert math.isnan(landmarks["cov_zz"][0])
    assert run.detections("a_first").empty
    assert run.events["type"].tolist() == ["slip", "path_done"]
    assert run.events["t_ns"].dtype == np.int64
    assert run.world["distractors"] == [{"center": (2.0, -1.19), "class": "poster"}]
    assert run.timing == {"sim_seconds": 20.0} and run.provenance == {"version": "test"}
    assert "duration_s" in run.scenario_text
    scenario = run.scenario
    assert scenario == {"seed": 7, "duration_s": 20} or scenario == run.scenario_text
    with pytest.raises(KeyError):
        run.trajectory("nobody")
    with pytest.raises(ValueError):
        run.rpe("a_first", 2)


@pytest.mark.parametrize("name,text,message", [
    ("ground_truth.tum", "0.000000000 1 2 3\n", r"ground_truth.tum:1: expected 8 fields"),
    ("ground_truth.tum", "# c\n0.1234567891 0 0 0 0 0 0 1\n",
     r"ground_truth.tum:2: t: expected seconds with at most nine decimals"),
    ("ground_truth.tum", "0.1 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n",
     r"ground_truth.tum:2: t: 0.1 is not after"),
    ("ground_truth.tum", "0.1 0 0x1 0 0 0 0 1\n", r"ground_truth.tum:1: y: not a number"),
    ("ground_truth.tum", "0.1 0 nan 0 0 0 0 1\n", r"ground_truth.tum:1: y: not finite"),
    ("offset_nis.csv", "t,type,dof,nis,accepted\n1.0,lamp,0,1.0,1\n",
     r"offset_nis.csv:2: dof: 0 is outside"),
    ("offset_nis.csv", "t,type,dof,nis\n", r"offset_nis.csv:1: the header has no column"),
    ("events.json", '{"seed": 1, "events": [{"t": 1, "t_ns": 5, "type": "slip"},\n'
     '{"t": 0, "t_ns": 1, "type": "slip"}]}', r"events.json:2: events\[1\].t_ns: 1 is before"),
    ("metrics.json", '{"pipelines": {"a b": {}}}', r"metrics.json:1: pipelines.a b: a pipeline "
     "name must be a plain file stem"),
    ("metrics.json", '{"pipelines":\n {"a": [}}', r"metrics.json:2: column \d+: invalid JSON"),
    ("offset_cov.txt", "0.1 0 0 0 0 0 0 1\n", r"offset_cov.txt:1: expected 20 fields"),
])
def test_malformed_files_name_their_line(tmp_path, name, text, message):
    write_run(str(tmp_path))
    write(os.path.join(tmp_path, name), text)
    run = None
    with pytest.raises(InputError, match=message):
        run = Run(str(tmp_path))
        run.nis("offset")
        run.events  # noqa: B018
        run.covariance("offset")
        run.ate("offset")
    assert run is None or name != "metrics.json"


def test_a_folder_without_metrics_is_no_run(tmp_path):
    with pytest.raises(InputError, match="metrics.json: missing"):
        Run(str(tmp_path))
    with pytest.raises(InputError, match="is not a directory"):
        Run(str(tmp_path / "nowhere"))


def test_read_world_rejects_a_distractor_without_center(tmp_path):
    path = os.path.join(tmp_path, "world.json")
    write_json(path, {"distractors": [{"id": 1, "class": "poster"}]})
    with pytest.raises(InputError, match=r"world.json:\d+: distractors\[0\]: needs center"):
        files.read_world(path)


# ------------------------------------------------------------------------------------------------
# Study

def write_study(study_dir):
    """Two sweep points (robot.odometry.random_k_m), two seeds, pipelines a and b; p001 seed 2
    failed. Run metrics: ate_rmse_m = 0.1 * (point + 1) * seed for a, half of it for b."""
    write_json(os.path.join(study_dir, "study.json"), {
        "schema_version": 1, "build": "test", "runs_per_point": 2, "first_seed": 1,
        "run_timeout_s": 3600, "divergence_nees": 100, "may_diverge": [], "time_step_s": 1.0,
        "pipelines": ["a", "b"], "metrics": [], "vary": ["robot.odometry.random_k_m"],
        "points": [{"id": "p000", "vary": {"robot.odometry.random_k_m": "1e-05"},
                    "scenario": "points/p000.yaml", "scenario_sha256": "x"},
                   {"id": "p001", "vary": {"robot.odometry.random_k_m": "0.001"},
                    "scenario": "points/p001.yaml", "scenario_sha256": "y"}],
        "expectations": [], "plugins": []})
    for p, pid in enumerate(["p000", "p001"]):
        for seed in (1, 2):
            if pid == "p001" and seed == 2:
                write_json(os.path.join(study_dir, "status", pid, "seed_2.json"), {
                    "point": pid, "seed": 2, "outcome": "failed", "detail": "exit 1",
                    "exit_code": 1, "signal": 0, "wall_seconds": 3.5, "peak_rss_mib": 100.0})
                continue
            ate = 0.1 * (p + 1) * seed
            write_json(os.path.join(study_dir, "runs", pid, f"seed_{seed}", "metrics.json"), {
                "pipelines": {"a": {"ate_rmse_m": ate, "nis": {"lamp": {"mean": 1.0}},
                                    "rpe_10m_trans_rmse_m": None},
                              "b": {"ate_rmse_m": ate / 2, "health": {"failed": 0}}}})
    write(os.path.join(study_dir, "summary.csv"),
          "point,robot.odometry.random_k_m,pipeline,metric,n,mean,std,median,p95,min,max,ci_low,"
          "ci_high\np000,1e-05,a,ate_rmse_m,2,0.15,0.0707106781,0.15,0.195,0.1,0.2,0.1,0.2\n"
          "p001,0.001,b,ate_rmse_m,1,0.1,,0.1,0.1,0.1,0.1,0.1,0.1\n")
    write(os.path.join(study_dir, "paired.csv"),
          "point,robot.odometry.random_k_m,a,b,metric,n,diff,diff_ci_low,diff_ci_high,ratio,"
          "ratio_ci_low,ratio_ci_high,a_lower,p_sign,p_wilcoxon\n"
          "p000,1e-05,a,b,ate_rmse_m,2,0.075,0.05,0.1,2,2,2,0,0.5,0.5\n")


def test_study_tables_and_comparison(tmp_path):
    write_study(str(tmp_path))
    study = Study(str(tmp_path))
    assert study.pipelines == ["a", "b"] and study.seeds == [1, 2]
    assert study.points["robot.odometry.random_k_m"].tolist() == [1e-05, 0.001]
    runs = study.runs
    assert len(runs) == 2 * 2 * 2
    assert list(runs.columns[:5]) == ["point", "seed", "robot.odometry.random_k_m", "pipeline",
                                      "status"]
    assert runs["status"].tolist().count("failed") == 2
    a = runs[(runs["pipeline"] == "a") & (runs["point"] == "p001") & (runs["seed"] == 1)]
    assert a["ate_rmse_m"].iloc[0] == 0.2 and a["nis.lamp.mean"].iloc[0] == 1.0
    assert math.isnan(a["rpe_10m_trans_rmse_m"].iloc[0])
    assert study.status["outcome"].tolist() == ["failed"]
    compared = study.compare("a", "b")
    assert len(compared) == 3  # the failed run is left out
    assert list(compared.columns) == ["point", "seed", "robot.odometry.random_k_m", "a", "b",
                                      "diff"]
    assert compared["diff"].tolist() == [0.05, 0.1, 0.1]
    assert len(study.compare("a", "b", point="p001")) == 1
    summary = study.summary
    assert summary["n"].tolist() == [2, 1] and math.isnan(summary["std"][1])
    assert summary["robot.odometry.random_k_m"].tolist() == [1e-05, 0.001]
    assert study.paired["diff"].tolist() == [0.075]
    run = study.run("p000", 2)
    assert run.metric("a", "ate_rmse_m") == 0.2
    with pytest.raises(KeyError):
        study.run("p009", 1)


def test_study_errors_name_the_file(tmp_path):
    write_study(str(tmp_path))
    write(os.path.join(tmp_path, "summary.csv"), "point,x,pipeline,metric\n")
    with pytest.raises(InputError, match=r"summary.csv:1: expected the header"):
        Study(str(tmp_path)).summary  # noqa: B018
    write_study(str(tmp_path))
    with open(os.path.join(tmp_path, "paired.csv"), "a") as f:
        f.write("p000,1e-05,a,b,ate_rmse_m,two,0,0,0,0,0,0,0,0,0\n")
    with pytest.raises(InputError, match=r"paired.csv:3: n: expected an integer"):
        Study(str(tmp_path)).paired  # noqa: B018
    write_json(os.path.join(tmp_path, "study.json"), {"runs_per_point": 0})
    with pytest.raises(InputError, match=r"study.json:1: runs_per_point"):
        Study(str(tmp_path))


# ------------------------------------------------------------------------------------------------
# Dataset

def png(path, width=4, height=3, value=(10, 20, 30)):
    """An 8-bit RGB PNG, written without any imaging library."""
    raw = b"".join(b"\x00" + bytes(value) * width for _ in range(height))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))

    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" +
                chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def test_dataset_layout(tmp_path):
    root = str(tmp_path)
    write_json(os.path.join(root, "dataset.json"), {
        "format": "corridorsim dataset", "format_version": 1, "worlds": 1, "frames_per_world": 2,
        "cameras": ["lateral"]})
    for f in range(2):
        png(os.path.join(root, "lateral", "images", f"w000_f000{f}.png"))
        write_json(os.path.join(root, "lateral", "truth", f"w000_f000{f}.json"), {"frame": f})
    frames = Dataset(root).frames("lateral")  # before annotations.json: from the truth files
    assert frames["frame_index"].tolist() == [0, 1]
    write_json(os.path.join(root, "lateral", "annotations.json"), {
        "images": [{"id": 1, "file_name": "images/w000_f0000.png", "width": 4, "height": 3,
                    "world_index": 0, "frame_index": 0, "world_seed": 5},
                   {"id": 2, "file_name": "images/w000_f0001.png", "width": 4, "height": 3,
                    "world_index": 0, "frame_index": 1, "world_seed": 5}],
        "categories": [{"id": 1, "name": "door_plate"}, {"id": 3, "name": "lamp"}],
        "annotations": [{"id": 1, "image_id": 2, "category_id": 1, "bbox": [1, 1, 2, 1],
                         "area": 2, "iscrowd": 0, "room_number": "101", "distance_m": 1.5}]})
    dataset = Dataset(root)
    assert dataset.layout == "dataset" and dataset.cameras == ["lateral"]
    frames = dataset.frames("lateral")
    assert frames["image_id"].tolist() == [1, 2]
    assert frames["truth_path"][1].endswith(os.path.join("truth", "w000_f0001.json"))
    image = dataset.image("lateral", 1)
    assert image.shape == (3, 4, 3)
    assert image[0, 0, 0] in (10, pytest.approx(10 / 255))  # OpenCV, or matplotlib's floats
    assert dataset.truth("lateral", 1) == {"frame": 1}
    annotations = dataset.annotations("lateral")
    assert annotations["category"].tolist() == ["door_plate"]
    assert annotations["room_number"].tolist() == ["101"] and annotations["w"][0] == 2.0
    with pytest.raises(KeyError):
        dataset.frames("front")


def test_export_layout(tmp_path):
    root = str(tmp_path)
    write(os.path.join(root, "tum_rgbd", "rgb.txt"),
          "# a\n# b\n# c\n0.300000000 rgb/300000000.png\n0.600000000 rgb/600000000.png\n")
    write(os.path.join(root, "tum_rgbd", "depth.txt"), "# a\n0.300000000 depth/300000000.png\n")
    write(os.path.join(root, "euroc", "mav0", "cam1", "data.csv"),
          "#timestamp [ns],filename\n300000000,300000000.png\n")
    write_json(os.path.join(root, "coco", "plates.json"), {
        "images": [{"id": 1, "file_name": "tum_rgbd/rgb/300000000.png", "width": 4, "height": 3},
                   {"id": 2, "file_name": "euroc/mav0/cam1/data/300000000.png", "width": 4,
                    "height": 3}],
        "categories": [{"id": 1, "name": "door_plate", "supercategory": "sign"}],
        "annotations": [{"id": 1, "image_id": 2, "category_id": 1, "bbox": [0.5, 0.5, 1, 1],
                         "area": 1, "iscrowd": 0,
                         "attributes": {"room_number": "7", "plate_id": 4}}]})
    dataset = Dataset(root)
    assert dataset.layout == "export" and dataset.cameras == ["front", "lateral"]
    front = dataset.frames("front")
    assert front["t_ns"].tolist() == [300_000_000, 600_000_000]
    assert front["file_name"][0] == "tum_rgbd/rgb/300000000.png"
    assert front["depth_path"][0].endswith("depth/300000000.png") and front["depth_path"][1] is None
    assert dataset.frames("lateral")["labels_path"][0].endswith(
        os.path.join("labels", "lateral", "300000000.png"))
    assert dataset.annotations("front").empty
    lateral = dataset.annotations("lateral")
    assert lateral["attributes.room_number"].tolist() == ["7"]


def test_export_named_cameras(tmp_path):
    """The scenario's named cameras: euroc/mav0/cam2/, ... as cameras.yaml names them, a depth
    camera's depth/ through its depth.csv (docs/export.md)."""
    root = str(tmp_path)
    write(os.path.join(root, "euroc", "mav0", "cameras.yaml"),
          "# comment\ncam1: lateral\ncam3: right2\ncam2: left1\n")
    for cam in ("cam1", "cam2", "cam3"):
        write(os.path.join(root, "euroc", "mav0", cam, "data.csv"),
              "#timestamp [ns],filename\n0,0.png\n100000000,100000000.png\n")
    write(os.path.join(root, "euroc", "mav0", "cam2", "depth.csv"),
          "#timestamp [ns],filename\n0,0.png\n100000000,100000000.png\n")
    dataset = Dataset(root)
    assert dataset.cameras == ["lateral", "left1", "right2"]
    left = dataset.frames("left1")
    assert left["file_name"].tolist() == ["euroc/mav0/cam2/data/0.png",
                                          "euroc/mav0/cam2/data/100000000.png"]
    assert left["depth_path"][1] == os.path.join(root, "euroc/mav0/cam2/depth/100000000.png")
    assert left["labels_path"][0].endswith(os.path.join("labels", "left1", "0.png"))
    assert dataset.frames("right2")["depth_path"].tolist() == [None, None]
    assert dataset.coco("left1") is None and dataset.annotations("left1").empty
    for bad in ("cam2: left1\ncam2: other\n", "cam2 left1\n", "cam2: Left\n"):
        write(os.path.join(root, "euroc", "mav0", "cameras.yaml"), bad)
        with pytest.raises(InputError, match="cameras.yaml"):
            Dataset(root)


def test_coco_references_are_checked(tmp_path):
    path = os.path.join(tmp_path, "c.json")
    write_json(path, {"images": [], "categories": [{"id": 1, "name": "x"}],
                      "annotations": [{"id": 1, "image_id": 4, "category_id": 1,
                                       "bbox": [0, 0, 1, 1]}]})
    with pytest.raises(InputError, match=r"annotations\[0\].image_id: no image 4"):
        dataset_files.read_coco(path)


# ------------------------------------------------------------------------------------------------
# The package

def test_import_corridorsim_does_not_load_pandas():
    code = ("import sys, corridorsim; assert 'pandas' not in sys.modules; "
            "assert 'corridorsim.analysis' not in sys.modules; run = corridorsim.Run; "
            "assert 'pandas' in sys.modules and run.__name__ == 'Run'; "
            "assert 'Study' in dir(corridorsim)")
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert corridorsim.Dataset is analysis.Dataset
    with pytest.raises(AttributeError):
        corridorsim.Nothing  # noqa: B018
