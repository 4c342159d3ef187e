"""Tests scripts/plot_run.py on a synthetic run folder: every plot is written as a valid PNG,
reruns give the same bytes, absent metrics skip their plots, and a missing or malformed input
exits 1 naming the file and line.

    python3 tests/scripts/plot_run_test.py         (CTest: scripts.plot_run)
"""

import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts",
                      "plot_run.py")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def small_world(length_m):
    """A straight corridor 2.4 m wide as ground_truth.json lays it out: two side walls, an open
    door with its plate and a lit round lamp (plus, for a long corridor, more doors, plates and
    lamps every 4 m, alternating states, panels and off lamps)."""
    world = {
        "seed": 1, "layout": "straight",
        "door_plates": [{"id": 5, "door_id": 4, "room_number": "101", "center": [4.4, 1.19, 1.6],
                         "normal": [0.0, -1.0, 0.0], "size": [0.3, 0.12]}],
        "lamps": [{"id": 6, "shape": "circular", "center": [5.0, 0.0, 2.495], "radius": 0.3,
                   "on": True}],
        "doors": [{"id": 4, "state": "open", "wall_id": 3, "column_a": [3.0, 1.2],
                   "column_b": [3.9, 1.2], "top_height": 2.1, "width": 0.9,
                   "column_width": 0.1, "inward_normal": [0.0, -1.0], "room_number": "101"}],
        "corridor_segments": [{"id": 1, "start": [0.0, 0.0], "end": [length_m, 0.0],
                               "direction": [1.0, 0.0], "width": 2.4, "height": 2.5}],
        "walls": [
            {"id": 2, "start": [0.0, -1.2], "end": [length_m, -1.2], "inward_normal": [0.0, 1.0],
             "segment_id": 1, "side_wall": True},
            {"id": 3, "start": [length_m, 1.2], "end": [0.0, 1.2], "inward_normal": [0.0, -1.0],
             "segment_id": 1, "side_wall": True},
        ],
        "reflectors": [], "corner_points": [], "distractors": [],
    }
    states = ["closed", "empty", "open"]
    for k, x in enumerate(range(8, int(length_m) - 2, 4)):
        side = 1.0 if k % 2 else -1.0
        world["doors"].append({"id": 100 + k, "state": states[k % 3], "column_a": [x, 1.2 * side],
                               "column_b": [x + 0.9, 1.2 * side], "room_number": str(102 + k)})
        world["door_plates"].append({"id": 200 + k, "room_number": str(102 + k),
                                     "center": [x + 1.3, 1.19 * side, 1.6],
                                     "normal": [0.0, -side, 0.0]})
        lamp = {"id": 300 + k, "center": [x + 1.0, 0.0, 2.495], "on": k % 4 != 3}
        lamp.update({"shape": "panel", "size": [0.6, 1.2]} if k % 2 else
                    {"shape": "circular", "radius": 0.3})
        world["lamps"].append(lamp)
    return world


def write_run(run_dir, length_m=10.0):
    """A run of the odometry pipeline driving the corridor's centre line at 0.3 m/s: the truth is
    straight, the estimate's heading drifts to 0.05 rad at the end with a growing covariance."""
    os.makedirs(run_dir, exist_ok=True)
    with open(os.path.join(run_dir, "world.json"), "w") as f:
        json.dump(small_world(length_m), f, indent=2)
    duration_s = (length_m - 1.0) / 0.3
    steps = int(duration_s / 0.1)
    truth, odometry, errors = ["# ground truth"], [], ["t,ex_m,ey_m,eyaw_rad,sigma_x_m,"
                                                       "sigma_y_m,sigma_yaw_rad,nees"]
    x_est = y_est = 0.0
    for i in range(steps + 1):
        t = 0.1 * i
        x, yaw_est = 0.5 + 0.3 * t, 0.05 * t / duration_s
        if i > 0:
            x_est += 0.03 * math.cos(yaw_est)
            y_est += 0.03 * math.sin(yaw_est)
        else:
            x_est = x
        truth.append(f"{t:.3f} {x:.6f} 0 0 0 0 0 1")
        odometry.append(f"{t:.3f} {x_est:.6f} {y_est:.6f} 0 0 0 {math.sin(yaw_est / 2):.9f} "
                        f"{math.cos(yaw_est / 2):.9f}")
        ex, ey, eyaw = x_est - x, y_est, yaw_est
        sx, sy, syaw = (0.01 + 0.02 * t / duration_s, 0.01 + 0.5 * t / duration_s,
                       0.005 + 0.03 * t / duration_s)
        nees = (ex / sx) ** 2 + (ey / sy) ** 2 + (eyaw / syaw) ** 2
        errors.append(f"{t:.3f},{ex:.6f},{ey:.6f},{eyaw:.6f},{sx:.6f},{sy:.6f},{syaw:.6f},"
                      f"{nees:.6f}")
    for name, lines in [("ground_truth.tum", truth), ("odometry.tum", odometry),
                        ("odometry_errors.csv", errors)]:
        with open(os.path.join(run_dir, name), "w") as f:
            f.write("\n".join(lines) + "\n")
    metrics = {
        "pipelines": {"odometry": {
            "ate_rmse_m": 0.21, "ate_aligned_rmse_m": 0.05, "final_position_error_m": 0.4,
            "nees_mean": 2.1, "nees_in_band_fraction": 0.93, "nees_band": [0.2158, 9.3484],
            "detectors": {"door_plate": {"precision": 0.9, "recall": 0.75, "accuracy": 0.8},
                          "lamp": {"precision": 1.0, "recall": 0.5, "accuracy": None}},
        }},
        "expectations": [
            {"text": "odometry final position error below 1 m", "measured": 0.4, "passed": True},
            {"text": "NEES mean inside the 3-dof band", "measured": 2.1, "passed": False},
        ],
    }
    with open(os.path.join(run_dir, "metrics.json"), "w") as f:
        json.dump(metrics, f, indent=2)


LANDMARK_LABEL_MATHTEXT = r"$\q$"  # would stop matplotlib's mathtext parser unless escaped


def sym(c):
    """A 3x3 covariance (m^2) as nested lists from its x-y block (sxx, sxy, syy) and 0.01 for z."""
    sxx, sxy, syy = c
    return [[sxx, sxy, 0.0], [sxy, syy, 0.0], [0.0, 0.0, 0.01]]


def write_slam_outputs(run_dir, name="odometry"):
    """The SLAM files of pipeline `name` for the world of write_run: <name>_landmarks.json (plates
    with their room numbers, one still initialising along its viewing ray; a door with its two
    columns; lamps; 300 corners; a vanishing point 1000 m down the corridor; one landmark whose
    x-y covariance is not positive semi-definite and one with a null entry),
    <name>_detections.csv (every type, associated, new and unassociated, scores for plates,
    corners and the vanishing point; one label quoted) and maps/<name>_frame_times.csv."""
    with open(os.path.join(run_dir, "world.json")) as f:
        world = json.load(f)
    landmarks = []

    def add(kind, position, covariance, status="converged", label="", points=None):
        entry = {"id": len(landmarks), "type": kind, "status": status, "label": label,
                 "position_in_world": position, "covariance": covariance}
        if points is not None:
            entry["points"] = points
        landmarks.append(entry)

    add("vanishing_point", [1000.0, 2.0, 1.2], [[100.0, 0, 0], [0, 4.0, 0], [0, 0, 4.0]])
    for k, plate in enumerate(world["door_plates"]):
        x, y, z = plate["center"]
        if k == 1:
            add("door_plate", [x + 0.2, y - 0.4, z], sym((0.02, 0.0, 0.9)), "initializing",
                plate["room_number"])
        else:
            add("door_plate", [x + 0.05 * k, y - 0.03, z], sym((0.004, 0.001, 0.002)),
                label=LANDMARK_LABEL_MATHTEXT if k == 2 else plate["room_number"])
    door = world["doors"][0]
    add("door", [3.45, 1.21, 1.05], sym((0.01, 0.0, 0.004)), points=[
        {"role": "column_a", "position_in_world": door["column_a"] + [1.05],
         "covariance": sym((0.006, 0.0, 0.003))},
        {"role": "column_b", "position_in_world": door["column_b"] + [1.05],
         "covariance": sym((0.006, 0.002, 0.003))}])
    for lamp in world["lamps"][:6]:
        add("lamp", lamp["center"], sym((0.003, 0.0, 0.003)))
    length = world["walls"][0]["end"][0]
    for k in range(300):
        x = 0.2 + (length - 0.4) * k / 299.0
        add("corner", [x, 1.18 if k % 2 else -1.18, 0.3 + 0.007 * k],
            sym((0.002 + 0.0001 * (k % 7), 0.0005 * ((k % 5) - 2), 0.001 + 0.0002 * (k % 3))),
            "initializing" if k % 11 == 0 else "converged")
    add("lamp", [8.0, 0.3, 2.49], sym((0.5, 0.9, 0.5)))  # not positive semi-definite
    add("corner", [9.0, -1.1, 0.5], [[0.01, None, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]])
    with open(os.path.join(run_dir, f"{name}_landmarks.json"), "w") as f:
        json.dump(landmarks, f, indent=2)

    header = ("stamp_s,camera,type,u_px,v_px,box_min_x_px,box_min_y_px,box_max_x_px,"
              "box_max_y_px,plate_box,radius_px,label,open,score,recognition_score,landmark_id,"
              "new_landmark")
    rows, frames = [header], ["stamp_s,landmarks,frame_ms"]
    plates = [lm for lm in landmarks if lm["type"] == "door_plate"]
    for i in range(int((length - 1.0) / 0.3 / 0.3)):
        t = 0.3 * i
        rows.append(f"{t:.9f},front,vanishing_point,{320 + 5 * math.sin(t):.4f},240.0000,"
                    f",,,,,,,,{20 + i % 9}.000000,,0,0")
        for c in range(5):
            corner_id = (i * 5 + c) % 300 + 1 + len(plates) + 7
            new = 1 if i * 5 + c < 300 else 0
            associated = corner_id if (i + c) % 4 else -1
            rows.append(f"{t:.9f},front,corner,{40 + 120 * c + i % 37:.4f},{100 + 30 * c:.4f},"
                        f",,,,,,,,{10.0 ** (2 + (i * 5 + c) % 40 / 10.0):.6f},,"
                        f"{associated},{new if associated >= 0 else 0}")
        plate = plates[(i // 10) % len(plates)]
        if i % 10 < 4:
            read = i % 10 != 3
            label = plate["label"] if read else ""
            if (i // 10) % 7 == 5 and read:
                label = '"10,1"'  # a label with a comma, quoted as CSV requires
            associated = plate["id"] if (i // 10) % 5 else -1
            new = 1 if i % 10 == 0 and associated >= 0 else 0
            recognition = "0.910000" if read else ""
            rows.append(f"{t:.9f},lateral,door_plate,{300 + 40 * (i % 10):.4f},200.0000,"
                        f"{280 + 40 * (i % 10):.4f},190.0000,{330 + 40 * (i % 10):.4f},"
                        f"210.0000,number_region,,{label},,{1.5 - 0.4 * (i % 10):.6f},"
                        f"{recognition},{associated},{new}")
        if i % 6 == 0:
            rows.append(f"{t:.9f},upward,lamp,{320 + i % 50:.4f},240.0000,,,,,,18.5000,,,,,"
                        f"{len(plates) + 2 + (i // 6) % 6},0")
        if i % 15 == 0:
            rows.append(f"{t:.9f},front,door,{100 + i % 40:.4f},200.0000,80.0000,100.0000,"
                        f"140.0000,380.0000,,,,1,,,{len(plates) + 1},0")
        frames.append(f"{t:.9f},{min(300, 5 * i)},{2.0 + 0.004 * min(300, 5 * i) ** 2:.3f}")
    with open(os.path.join(run_dir, f"{name}_detections.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    os.makedirs(os.path.join(run_dir, "maps"), exist_ok=True)
    with open(os.path.join(run_dir, "maps", f"{name}_frame_times.csv"), "w") as f:
        f.write("\n".join(frames) + "\n")


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True,
                          timeout=120)


def png_size(path):
    """(width, height) from a PNG's IHDR chunk; fails the test if the file is not a PNG."""
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != PNG_SIGNATURE or head[12:16] != b"IHDR":
        raise AssertionError(f"{path} is not a PNG")
    return struct.unpack(">II", head[16:24])


class PlotRunTest(unittest.TestCase):
    EXPECTED = ["trajectories.png", "errors_odometry.png", "nees_odometry.png", "detectors.png",
                "summary.png"]

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="plot_run_test_")
        cls.run_dir = os.path.join(cls.tmp, "run")
        write_run(cls.run_dir)
        cls.result = run_script(cls.run_dir)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def copy_run(self, name):
        """A fresh copy of the good run folder (without plots) to break."""
        target = os.path.join(self.tmp, name)
        shutil.copytree(self.run_dir, target, ignore=shutil.ignore_patterns("plots"))
        return target

    def assert_fails(self, run_dir, pattern):
        result = run_script(run_dir)
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertRegex(result.stderr, pattern)
        self.assertFalse(os.path.exists(os.path.join(run_dir, "plots")),
                         "a bad input must leave no plots")
        return result

    def test_writes_every_plot_as_a_png(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        printed = self.result.stdout.splitlines()
        self.assertEqual([os.path.basename(p) for p in printed], self.EXPECTED)
        for path in printed:
            self.assertTrue(os.path.isfile(path), path)
            width, height = png_size(path)
            self.assertTrue(500 <= width <= 4000 and 200 <= height <= 4000, (path, width, height))
            self.assertGreater(os.path.getsize(path), 10_000, path)
        self.assertEqual(sorted(os.listdir(os.path.join(self.run_dir, "plots"))),
                         sorted(self.EXPECTED), "no temporary files are left")

    def test_rerun_gives_identical_bytes(self):
        plots = os.path.join(self.run_dir, "plots")
        before = {}
        for name in self.EXPECTED:
            with open(os.path.join(plots, name), "rb") as f:
                before[name] = f.read()
        again = self.copy_run("again")
        self.assertEqual(run_script(again).returncode, 0)
        for name, data in before.items():
            with open(os.path.join(again, "plots", name), "rb") as f:
                self.assertEqual(f.read(), data, name)

    def test_long_corridor_is_split_into_panels(self):
        run_dir = os.path.join(self.tmp, "long")
        write_run(run_dir, length_m=55.0)
        result = run_script(run_dir)
        self.assertEqual(result.returncode, 0, result.stderr)
        width, height = png_size(os.path.join(run_dir, "plots", "trajectories.png"))
        # One 55 m x 3 m panel would be about 16 in x 0.9 in; three panels stack to ~9 in.
        self.assertGreater(height, 0.4 * width, (width, height))

    def test_absent_metrics_skip_their_plots(self):
        run_dir = self.copy_run("no_metrics")
        with open(os.path.join(run_dir, "metrics.json"), "w") as f:
            f.write("{}\n")
        result = run_script(run_dir)
        self.assertEqual(result.returncode, 0, result.stderr)
        # The pipelines come from the *.tum files; detectors and summary have no data.
        self.assertEqual([os.path.basename(p) for p in result.stdout.splitlines()],
                         ["trajectories.png", "errors_odometry.png", "nees_odometry.png"])

    def test_missing_inputs_exit_1_naming_the_file(self):
        for name in ["world.json", "metrics.json", "ground_truth.tum", "odometry.tum",
                     "odometry_errors.csv"]:
            with self.subTest(name=name):
                run_dir = self.copy_run("missing_" + name)
                os.remove(os.path.join(run_dir, name))
                self.assert_fails(run_dir, re.escape(name) + ": missing")

    def test_malformed_lines_exit_1_naming_file_and_line(self):
        def replace_line(text, number, line):
            lines = text.split("\n")
            lines[number - 1] = line
            return "\n".join(lines)

        cases = [
            ("odometry.tum", lambda s: replace_line(s, 3, "0.2 1 2 3 0 0 0"),
             r"odometry\.tum:3: expected 8 numbers"),
            ("ground_truth.tum", lambda s: replace_line(s, 4, "0.2 1 2 three 0 0 0 1"),
             r"ground_truth\.tum:4: not a number"),
            ("odometry_errors.csv", lambda s: replace_line(s, 5, "0.3,x,0,0,1,1,1,0"),
             r"odometry_errors\.csv:5: ex_m: not a number"),
            ("odometry_errors.csv", lambda s: s.replace("ex_m,", "ex,", 1),
             r"odometry_errors\.csv:1: the header has no column 'ex_m'"),
            ("odometry_errors.csv", lambda s: replace_line(s, 2, "0,0,0"),
             r"odometry_errors\.csv:2: expected 8 fields, got 3"),
            ("metrics.json", lambda s: s[:-10], r"metrics\.json:\d+: column \d+: invalid JSON"),
            ("metrics.json", lambda s: s.replace('"ate_rmse_m": 0.21', '"ate_rmse_m": "big"'),
             r"metrics\.json:\d+: pipelines\.odometry\.ate_rmse_m: expected number"),
            ("world.json", lambda s: s.replace('"start": [\n        10.0',
                                               '"start": "x", "a": [\n        10.0', 1),
             r"world\.json:\d+: walls\[1\]\.start: expected \[x, y\]"),
            ("world.json", lambda s: s.replace('"open"', '"ajar"', 1),
             r"world\.json:\d+: doors\[0\]\.state: expected one of"),
        ]
        for k, (name, mutate, pattern) in enumerate(cases):
            with self.subTest(name=name, pattern=pattern):
                run_dir = self.copy_run(f"malformed_{k}")
                path = os.path.join(run_dir, name)
                with open(path) as f:
                    text = f.read()
                broken = mutate(text)
                self.assertNotEqual(broken, text, "the case must change the file")
                with open(path, "w") as f:
                    f.write(broken)
                self.assert_fails(run_dir, pattern)

    def test_json_errors_point_at_the_object(self):
        run_dir = self.copy_run("wall_line")
        path = os.path.join(run_dir, "world.json")
        with open(path) as f:
            lines = f.read().split("\n")
        # Break walls[1]: its "end" becomes a number; the message gives the line of its "{".
        end_line = max(i for i, line in enumerate(lines, 1) if line.strip() == '"end": [')
        lines[end_line - 1] = '        "end": 7, "x": ['
        with open(path, "w") as f:
            f.write("\n".join(lines))
        result = self.assert_fails(run_dir, r"world\.json:\d+: walls\[1\]\.end")
        line = int(re.search(r"world\.json:(\d+):", result.stderr).group(1))
        self.assertEqual(lines[line - 1].strip(), "{")
        self.assertTrue(any('"id": 3' in lines[i] for i in range(line, end_line)))

    def test_bad_command_line_exits_2(self):
        self.assertEqual(run_script().returncode, 2)
        self.assertEqual(run_script(os.path.join(self.tmp, "nowhere")).returncode, 1)


if __name__ == "__main__":
    unittest.main()
