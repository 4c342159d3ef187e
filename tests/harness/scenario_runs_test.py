"""CI scenario tests (CTest label `scenario`): `corridorsim run` on shortened scenarios.

Usage: scenario_runs_test.py CORRIDORSIM SOURCE_DIR WORK_DIR [TestCase.test_name ...]

- the odometry pipeline's error lies within what its noise model predicts, and its NEES stays
  inside the chi-square band when Q matches the simulated noise (over many seeds: a single run's
  NEES over time is strongly correlated, so the band is judged on the average over seeds);
- two runs of one scenario give byte-identical trajectories, metrics and exported datasets;
- a failing expectation fails the run (exit code 3) with a readable report;
- P1's and P3's comparisons on shortened corridors;
- laser_slam against dead reckoning on a shortened loop, twice: the same bytes;
- every shipped scenario loads and its world, path and pipelines build (`run --check`).
"""

import csv
import filecmp
import json
import math
import os
import shutil
import subprocess
import sys
import unittest

# What these runs and studies check is their results: plots/ and the pages are left out
# (scripts.plot_run, viewer.browser and viewer.odd_data test those).
NO_EXTRAS = ["--no-plots", "--no-viewer"]

CORRIDORSIM, SOURCE_DIR, WORK_DIR = sys.argv[1:4]
DATA = os.path.join(SOURCE_DIR, "tests", "data", "scenarios")

# Two-sided 99 % chi-square bounds of the average of M independent NEES values of 3 dof, i.e.
# chi2(3M) / M, for M = 16 (chi2(48): 0.5 % = 25.25, 99.5 % = 78.23).
SEEDS = 16
AVG_NEES_BAND = (25.25 / SEEDS, 78.23 / SEEDS)
# chi2(3) 99.9 % quantile: one run's final NEES above it is a model violation at 0.1 %.
NEES_3DOF_999 = 16.27


def run(*args, check=True):
    result = subprocess.run([CORRIDORSIM, *args], capture_output=True, text=True, check=False)
    if check and result.returncode != 0:
        raise AssertionError(f"corridorsim {' '.join(args)} exited {result.returncode}:\n"
                             f"{result.stdout}\n{result.stderr}")
    return result


def fresh(name):
    path = os.path.join(WORK_DIR, name)
    shutil.rmtree(path, ignore_errors=True)
    return path


def run_short(test, scenario, name):
    """`corridorsim run` of tests/data/scenarios/<scenario> into WORK_DIR/<name>, which must pass
    its expectations: the run folder and its metrics.json's pipelines."""
    out = fresh(name)
    result = run("run", os.path.join(DATA, scenario), "--out", out, *NO_EXTRAS, check=False)
    test.assertEqual(result.returncode, 0, result.stdout + result.stderr)
    with open(os.path.join(out, "metrics.json")) as f:
        return out, json.load(f)["pipelines"]


def read_errors(path):
    """Rows of <pipeline>_errors.csv; rows without a NEES (zero covariance at the start) dropped."""
    with open(path, newline="") as f:
        rows = [{k: float(v) if v != "" else float("nan") for k, v in row.items()}
                for row in csv.DictReader(f)]
    return [r for r in rows if r["nees"] == r["nees"]]


class OdometryConsistency(unittest.TestCase):
    runs = None

    @classmethod
    def setUpClass(cls):
        # One run per seed of the shortened default scenario (no cameras: nothing reads them).
        cls.runs = []
        scenario = os.path.join(DATA, "odometry_consistency.yaml")
        for seed in range(1, SEEDS + 1):
            out = fresh(f"consistency/{seed}")
            run("run", scenario, "--seed", str(seed), "--out", out, *NO_EXTRAS)
            cls.runs.append(read_errors(os.path.join(out, "odometry_errors.csv")))

    def test_final_error_lies_within_what_the_noise_model_predicts(self):
        for seed, rows in enumerate(self.runs, start=1):
            last = rows[-1]
            self.assertGreater(last["sigma_x_m"], 0)
            self.assertLess(last["nees"], NEES_3DOF_999,
                            f"seed {seed}: final error ({last['ex_m']:.3f}, {last['ey_m']:.3f} m, "
                            f"{last['eyaw_rad']:.4f} rad) is outside its covariance")

    def test_nees_averaged_over_seeds_stays_in_the_chi_square_band(self):
        n = min(len(r) for r in self.runs)
        self.assertGreater(n, 100)
        # Ten checkpoints spread over the run, from a tenth of it on (at the start P is tiny and
        # the encoders' quantisation, outside the model, dominates).
        for k in range(1, 11):
            i = k * (n - 1) // 10
            average = sum(r[i]["nees"] for r in self.runs) / len(self.runs)
            t = self.runs[0][i]["t"]
            self.assertGreater(average, AVG_NEES_BAND[0], f"t = {t} s: average NEES {average:.2f}")
            self.assertLess(average, AVG_NEES_BAND[1], f"t = {t} s: average NEES {average:.2f}")


class Determinism(unittest.TestCase):
    def test_two_runs_give_byte_identical_trajectories_metrics_and_export(self):
        scenario = os.path.join(DATA, "short_with_cameras.yaml")
        outs = []
        for name in ("a", "b"):
            out, export = fresh(f"determinism/{name}"), fresh(f"determinism/{name}_export")
            run("run", scenario, "--out", out, "--export", export, *NO_EXTRAS)
            outs.append((out, export))
        (a, a_export), (b, b_export) = outs
        compared = 0
        for root, _, files in os.walk(a):
            for f in files:
                # Wall-clock seconds, by design not reproducible: timing.json, the Harris
                # baseline's frame times (P1 Fig. 16) and viewer.html, which plots them.
                if f in ("timing.json", "viewer.html") or f.endswith("_frame_times.csv"):
                    continue
                path_a = os.path.join(root, f)
                path_b = os.path.join(b, os.path.relpath(path_a, a))
                self.assertTrue(filecmp.cmp(path_a, path_b, shallow=False), f"{f} differs")
                compared += 1
        self.assertGreaterEqual(compared, 8)
        exported = 0
        for root, _, files in os.walk(a_export):
            for f in files:
                path_a = os.path.join(root, f)
                path_b = os.path.join(b_export, os.path.relpath(path_a, a_export))
                self.assertTrue(filecmp.cmp(path_a, path_b, shallow=False),
                                f"export {os.path.relpath(path_a, a_export)} differs")
                exported += 1
        self.assertGreater(exported, 20)  # images of three cameras, indexes, labels


class Expectations(unittest.TestCase):
    def test_a_failing_expectation_fails_the_run_with_a_readable_report(self):
        scenario = os.path.join(fresh("expectation"), "failing.yaml")
        os.makedirs(os.path.dirname(scenario))
        with open(scenario, "w") as f:
            f.write(f"include: {os.path.join(DATA, 'odometry_consistency.yaml')}\n"
                    "duration_s: 10\n"
                    "expectations:\n"
                    "  - odometry.ate_rmse_m < 0.000000001\n"
                    "  - odometry.ate_rmse_m < 100\n")
        result = run("run", scenario, "--out", os.path.dirname(scenario) + "/out", *NO_EXTRAS,
                     check=False)
        self.assertEqual(result.returncode, 3, result.stdout + result.stderr)
        self.assertRegex(result.stdout, r"FAIL\s+odometry\.ate_rmse_m < 0\.000000001\s+measured \d")
        self.assertRegex(result.stdout, r"PASS\s+odometry\.ate_rmse_m < 100\s+measured \d")
        with open(os.path.dirname(scenario) + "/out/metrics.json") as f:
            metrics = json.load(f)
        self.assertEqual([e["passed"] for e in metrics["expectations"]], [False, True])


class P1(unittest.TestCase):
    """P1's comparison on a shortened corridor (tests/data/scenarios/p1_short.yaml): its
    expectations assert the accuracy the issue asks for, scaled to the shorter corridor."""

    def test_p1_beats_its_baselines_and_maps_every_plate(self):
        out, metrics = run_short(self, "p1_short.yaml", "p1")
        p1, odometry, harris = metrics["p1_vp_doorplate"], metrics["odometry"], metrics["p1_harris"]
        self.assertLessEqual(p1["ate_rmse_m"], 0.5 * odometry["ate_rmse_m"])
        self.assertLess(p1["ate_rmse_m"], harris["ate_rmse_m"])
        plates = p1["map"]["door_plate"]
        self.assertEqual(plates["matched"], plates["observed"])
        self.assertEqual(plates["spurious"], 0)
        self.assertEqual(plates["room_number_accuracy"], 1.0)
        with open(os.path.join(out, "world.json")) as f:
            world = json.load(f)
        with open(os.path.join(out, "p1_vp_doorplate_landmarks.json")) as f:
            landmarks = json.load(f)
        truth = {p["room_number"]: p["center"] for p in world["door_plates"]}
        mapped = {l["label"]: l["position_in_world"] for l in landmarks if l["type"] == "door_plate"}
        self.assertEqual(sorted(mapped), sorted(truth))
        for room, p in mapped.items():
            error = math.hypot(p[0] - truth[room][0], p[1] - truth[room][1])
            self.assertLessEqual(error, 0.2, f"room {room}: {error:.3f} m from its plate")
        for name in ("p1_vp_doorplate.bt", "p1_vp_doorplate_semantic.json",
                     "p1_harris_frame_times.csv"):
            self.assertTrue(os.path.isfile(os.path.join(out, "maps", name)), name)


class P3(unittest.TestCase):
    """P3's comparison (Fig. 18) on a shortened corridor (tests/data/scenarios/p3_short.yaml):
    corners + lamps within 0.1 m over the whole run and at most half the ATE of corners alone,
    corners alone better than dead reckoning, the lamps detected and associated as the issue
    asks, a filter without numerical trouble."""

    def test_p3_lamps_and_corners_beat_corners_alone(self):
        out, metrics = run_short(self, "p3_short.yaml", "p3")
        upward, corners, odometry = metrics["p3_upward"], metrics["p3_corners"], metrics["odometry"]
        self.assertLessEqual(upward["ate_max_m"], 0.1)
        # Half the ATE of corners alone is asserted on the full 40 m corridor below: on this 20 m
        # one, sub-pixel corners alone stay within 0.015-0.05 m (seeds 1-4) and the ratio is
        # 0.39-1.0 (docs/p3.md).
        self.assertLess(upward["ate_rmse_m"], corners["ate_rmse_m"])
        self.assertLess(corners["ate_rmse_m"], odometry["ate_rmse_m"])
        lamps = upward["detection"]["lamp"]
        self.assertGreaterEqual(lamps["recall"], 0.95)
        self.assertGreaterEqual(lamps["precision"], 0.99)
        self.assertLessEqual(lamps["mean_center_error_px"], 2.0)
        self.assertGreaterEqual(upward["data_association"]["lamp"]["precision"], 0.99)
        self.assertEqual(upward["map"]["lamp"]["spurious"], 0)
        for pipeline in (upward, corners):
            self.assertEqual(pipeline["health"]["non_positive_covariance"], 0)
            self.assertEqual(pipeline["health"]["rejected_updates"], 0)
        # The landmarks file holds corners and lamps as world points with covariances.
        with open(os.path.join(out, "p3_upward_landmarks.json")) as f:
            landmarks = json.load(f)
        types = {l["type"] for l in landmarks}
        self.assertLessEqual({"corner", "lamp"}, types)
        self.assertLessEqual(types, {"corner", "lamp", "door"})  # open doors of this corridor

    def test_full_scenarios_seed_1(self):
        """P3 Fig. 18 on the shipped 40 m scenarios, seed 1, from their metric references
        (tests/data/metrics/), which scenario.metrics_unchanged.<name> holds this build to byte for
        byte: p3_upward within 0.1 m, half the ATE of corners alone in environment A, lamp and
        door association at the issue's 0.99."""
        for name in ("p3_lamps", "p3_doors"):
            with open(os.path.join(SOURCE_DIR, "tests", "data", "metrics", name + ".json")) as f:
                metrics = json.load(f)["pipelines"]
            upward, corners = metrics["p3_upward"], metrics["p3_corners"]
            self.assertLessEqual(upward["ate_max_m"], 0.1, name)
            self.assertLess(upward["ate_rmse_m"], corners["ate_rmse_m"], name)
            self.assertLess(corners["ate_rmse_m"], metrics["odometry"]["ate_rmse_m"], name)
            for kind in ("lamp", "door"):
                self.assertGreaterEqual(upward["data_association"][kind]["precision"], 0.99,
                                        f"{name} {kind}")
            if name == "p3_lamps":
                self.assertLessEqual(upward["ate_rmse_m"], 0.5 * corners["ate_rmse_m"])


class P3Doors(unittest.TestCase):
    """P3's doors (section III) on a shortened environment B
    (tests/data/scenarios/p3_doors_short.yaml): open doors registered as landmarks with both
    columns right, closed doors, the cabinet and the bookshelf never, door associations right."""

    def test_open_doors_become_landmarks_and_nothing_else_does(self):
        out, metrics = run_short(self, "p3_doors_short.yaml", "p3_doors")
        upward = metrics["p3_upward"]
        doors = upward["map"]["door"]
        self.assertGreaterEqual(doors["open_seen"], 2)
        self.assertGreaterEqual(doors["open_recall"], 0.8)
        self.assertGreaterEqual(doors["open_precision"], 0.95)
        self.assertEqual(doors["closed_registered"], 0)
        self.assertEqual(doors["non_door_registered"], 0)
        self.assertEqual(doors["duplicates"], 0)
        self.assertLessEqual(doors["open_column_rmse_m"], 0.25)
        # The issue's target is 0.99 (asserted on the full scenarios' seed 1 in P3 above, and met
        # over ten seeds of each: scripts/p3_study.py). On this short run it is 0.975 today: 7 of
        # 276 associations (0.36 % each) are of door 11's candidates pairing a line 0.1 m inside
        # the room with its column b, as its landmark does (registered 0.1 m off), just past the
        # metric's 0.1 rad. This guards the measured level less two associations.
        self.assertGreaterEqual(upward["data_association"]["door"]["precision"], 0.97)
        self.assertLess(upward["ate_rmse_m"], metrics["odometry"]["ate_rmse_m"])
        self.assertEqual(upward["health"]["non_positive_covariance"], 0)
        # Door landmarks carry their two columns (P3 eq. 11) with covariances.
        with open(os.path.join(out, "p3_upward_landmarks.json")) as f:
            landmarks = json.load(f)
        for door in (l for l in landmarks if l["type"] == "door"):
            self.assertEqual([p["role"] for p in door["points"]], ["column_a", "column_b"])
        # Each registration with the particle filter's samples at that moment (P3 Fig. 9), near
        # the door's columns then.
        with open(os.path.join(out, "maps", "p3_upward_doors.json")) as f:
            registered = json.load(f)
        self.assertEqual(registered["format"], "corridorsim.upward_doors")
        self.assertEqual(len(registered["doors"]), doors["estimated"])
        for door in registered["doors"]:
            self.assertGreater(door["hausdorff_px"], 5.0)  # the open-door test's threshold
            self.assertEqual(len(door["particles"]), 200)
            n = len(door["particles"])
            mean = [sum(p[k] for p in door["particles"]) / n for k in range(5)]
            for k in range(4):
                self.assertLess(abs(mean[k] - door["columns_m"][k // 2][k % 2]), 0.3)
            self.assertTrue(1.9 <= mean[4] <= 2.4)  # a door's height (the verifier's bounds)
        # The map divided at the doors (P2 Fig. 12): the corridor and a room behind each door,
        # every point landmark in exactly one area, most of them where they truly are.
        with open(os.path.join(out, "maps", "p3_upward_areas.json")) as f:
            division = json.load(f)
        self.assertEqual(division["format"], "corridorsim.upward_areas")
        areas = division["areas"]
        self.assertEqual([a["kind"] for a in areas], ["corridor"] + ["room"] * doors["estimated"])
        self.assertEqual(sorted(a["door_landmark_id"] for a in areas[1:]),
                         sorted(d["landmark_id"] for d in registered["doors"]))
        points = sorted(l["id"] for l in landmarks if l["type"] != "door")
        self.assertEqual(sorted(i for a in areas for i in a["landmark_ids"]), points)
        for room in areas[1:]:
            self.assertEqual(len(room["polygon_m"]), 4)
        self.assertEqual(upward["map"]["area"]["rooms_behind_open_doors"], doors["open_registered"])
        self.assertGreaterEqual(upward["map"]["area"]["assignment_accuracy"], 0.9)


class LaserSlam(unittest.TestCase):
    """laser_slam on a shortened loop (tests/data/scenarios/laser_short.yaml, 44 m): its
    expectations hold, it beats dead reckoning, and a second run writes the same bytes (Ceres
    runs on one thread)."""

    def test_laser_slam_beats_odometry_and_repeats_byte_for_byte(self):
        out, metrics = run_short(self, "laser_short.yaml", "laser/a")
        laser, odometry = metrics["laser_slam"], metrics["odometry"]
        self.assertLess(laser["ate_rmse_m"], odometry["ate_rmse_m"] / 5)
        self.assertEqual(laser["health"]["rejected_updates"], 0)
        self.assertTrue(os.path.getsize(os.path.join(out, "maps", "laser_slam.pgm")) > 1000)
        again, _ = run_short(self, "laser_short.yaml", "laser/b")
        for f in ("laser_slam.tum", "laser_slam_cov.txt", "metrics.json",
                  os.path.join("maps", "laser_slam.pgm")):
            self.assertTrue(filecmp.cmp(os.path.join(out, f), os.path.join(again, f),
                                        shallow=False), f"{f} differs")


class ShippedScenarios(unittest.TestCase):
    def test_every_shipped_scenario_loads_and_builds(self):
        folder = os.path.join(SOURCE_DIR, "scenarios")
        names = sorted(f for f in os.listdir(folder) if f.endswith(".yaml"))
        self.assertGreaterEqual(len(names), 11)
        for name in names:
            result = run("run", os.path.join(folder, name), "--check", check=False)
            self.assertEqual(result.returncode, 0, f"{name}: {result.stdout}{result.stderr}")


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], *sys.argv[4:]])
