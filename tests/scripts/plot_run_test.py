"""Tests scripts/plot_run.py on synthetic run folders: every plot is written as a valid PNG,
reruns give the same bytes, absent metrics and files skip their plots (a folder without
landmarks, detections and frame times plots as before them), and a missing or malformed input
exits 1 naming the file and line (and the key or column).

    python3 tests/scripts/plot_run_test.py         (CTest: scripts.plot_run)
"""

import importlib.util
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import textwrap
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
    # The door's particle cloud at registration (200 samples about its columns) and the map
    # divided at it: a room behind it holding two lamps, the rest in the corridor.
    door_id = next(lm["id"] for lm in landmarks if lm["type"] == "door")
    (xa, ya), (xb, yb) = door["column_a"], door["column_b"]
    particles = [[xa + 0.02 * math.sin(k), ya + 0.03 * math.cos(k), xb + 0.02 * math.cos(k),
                  yb + 0.03 * math.sin(k), 2.0 + 0.001 * k] for k in range(200)]
    with open(os.path.join(run_dir, "maps", f"{name}_doors.json"), "w") as f:
        json.dump({"format": "corridorsim.upward_doors", "version": 1, "frame": "world",
                   "particle": ["x_a_m", "y_a_m", "x_b_m", "y_b_m", "top_height_m"],
                   "doors": [{"landmark_id": door_id, "registered_s": 3.2, "hausdorff_px": 9.5,
                              "top_height_m": 2.0, "columns_m": [[xa, ya], [xb, yb]],
                              "particles": particles}]}, f, indent=2)
    lamps = [lm["id"] for lm in landmarks if lm["type"] == "lamp"]
    room = lamps[:2]
    with open(os.path.join(run_dir, "maps", f"{name}_areas.json"), "w") as f:
        json.dump({"format": "corridorsim.upward_areas", "version": 1, "frame": "world",
                   "room_depth_m": 6.0, "room_reach_m": 2.0, "min_depth_m": 0.15,
                   "areas": [{"id": 0, "kind": "corridor", "door_landmark_id": None,
                              "polygon_m": None,
                              "landmark_ids": [lm["id"] for lm in landmarks
                                               if lm["id"] not in room and
                                               lm["type"] not in ("door", "vanishing_point")]},
                             {"id": 1, "kind": "room", "door_landmark_id": door_id,
                              "polygon_m": [[xa - 2, ya], [xb + 2, yb], [xb + 2, yb + 4],
                                            [xa - 2, ya + 4]],
                              "landmark_ids": room}]}, f, indent=2)


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


def replace_line(text, number, line):
    lines = text.split("\n")
    lines[number - 1] = line
    return "\n".join(lines)


def edit_json(change):
    """A mutate for break_files: the file's JSON value, changed in place by `change`, written
    back indented."""
    def mutate(text):
        value = json.loads(text)
        change(value)
        return json.dumps(value, indent=2)
    return mutate


class RunFolderCase(unittest.TestCase):
    """A synthetic run folder (run_dir, in a temporary folder named TEMP_PREFIX...) that the
    subclass's write_files fills, plotted once in setUpClass (result), and helpers to break copies
    of it."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix=cls.TEMP_PREFIX)
        cls.run_dir = os.path.join(cls.tmp, "run")
        cls.write_files(cls.run_dir)
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

    def break_files(self, cases):
        """Each (file, mutate, pattern) case on a fresh copy: the script exits 1 with a message
        matching pattern and writes no plots."""
        for k, (name, mutate, pattern) in enumerate(cases):
            with self.subTest(name=name, pattern=pattern):
                run_dir = self.copy_run(f"{self._testMethodName}_{k}")
                path = os.path.join(run_dir, name)
                with open(path) as f:
                    text = f.read()
                broken = mutate(text)
                self.assertNotEqual(broken, text, "the case must change the file")
                with open(path, "w") as f:
                    f.write(broken)
                self.assert_fails(run_dir, pattern)

    def assert_expected_pngs(self):
        """The script exited 0 and printed the paths of EXPECTED, in order, each a PNG."""
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        printed = self.result.stdout.splitlines()
        self.assertEqual([os.path.basename(p) for p in printed], self.EXPECTED)
        self.assert_pngs(printed)

    def assert_pngs(self, printed):
        for path in printed:
            self.assertTrue(os.path.isfile(path), path)
            width, height = png_size(path)
            self.assertTrue(500 <= width <= 4000 and 200 <= height <= 4000, (path, width, height))
            self.assertGreater(os.path.getsize(path), 10_000, path)


class PlotRunTest(RunFolderCase):
    """A run folder without landmarks, detections or frame times: the plots as before them."""
    EXPECTED = ["trajectories.png", "errors_odometry.png", "nees_odometry.png", "detectors.png",
                "summary.png"]

    TEMP_PREFIX = "plot_run_test_"

    @staticmethod
    def write_files(run_dir):
        write_run(run_dir)

    def test_writes_every_plot_as_a_png(self):
        self.assert_expected_pngs()
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
        self.break_files(cases)

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



def plot_python():
    """An interpreter that imports matplotlib, to load the script as a module (the script
    re-runs itself under /usr/bin/python3 when run, but a module import cannot)."""
    if importlib.util.find_spec("matplotlib") and importlib.util.find_spec("numpy"):
        return sys.executable
    return "/usr/bin/python3"


class SlamPlotsTest(RunFolderCase):
    """A 55 m run folder with the odometry pipeline's landmarks, detections and frame times."""
    NEW = ["landmarks_odometry.png", "doors_odometry.png", "areas_odometry.png",
           "detections_odometry.png", "frame_time_odometry.png"]
    EXPECTED = (["trajectories.png", "errors_odometry.png", "nees_odometry.png"] + NEW +
                ["detectors.png", "summary.png"])
    LANDMARKS = "odometry_landmarks.json"
    DETECTIONS = "odometry_detections.csv"
    FRAME_TIMES = os.path.join("maps", "odometry_frame_times.csv")
    DOORS = os.path.join("maps", "odometry_doors.json")
    AREAS = os.path.join("maps", "odometry_areas.json")

    TEMP_PREFIX = "plot_run_slam_test_"

    @staticmethod
    def write_files(run_dir):
        write_run(run_dir, length_m=55.0)
        write_slam_outputs(run_dir)

    def test_writes_the_landmark_detection_and_frame_time_plots(self):
        self.assert_expected_pngs()
        plots = os.path.join(self.run_dir, "plots")
        # The vanishing point 1000 m away is listed, not drawn: the map keeps the plan's panels.
        plan_w, plan_h = png_size(os.path.join(plots, "trajectories.png"))
        map_w, map_h = png_size(os.path.join(plots, "landmarks_odometry.png"))
        self.assertEqual(map_w, plan_w)
        self.assertLess(abs(map_h - plan_h), 0.3 * plan_h, (plan_h, map_h))
        # One row of panels per detection type (5 types, about 3 in each).
        width, height = png_size(os.path.join(plots, "detections_odometry.png"))
        self.assertGreater(height, 1300, (width, height))

    def test_rerun_gives_identical_bytes(self):
        again = self.copy_run("again")
        self.assertEqual(run_script(again).returncode, 0)
        for name in self.NEW:
            with open(os.path.join(self.run_dir, "plots", name), "rb") as f:
                first = f.read()
            with open(os.path.join(again, "plots", name), "rb") as f:
                self.assertEqual(f.read(), first, name)

    def test_each_plot_only_with_its_data(self):
        run_dir = self.copy_run("frame_times_only")
        os.remove(os.path.join(run_dir, self.LANDMARKS))
        path = os.path.join(run_dir, self.DETECTIONS)
        with open(path) as f:
            header = f.readline()
        with open(path, "w") as f:
            f.write(header)  # a header and no detections
        result = run_script(run_dir)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual([os.path.basename(p) for p in result.stdout.splitlines()],
                         ["trajectories.png", "errors_odometry.png", "nees_odometry.png",
                          "doors_odometry.png", "frame_time_odometry.png", "detectors.png",
                          "summary.png"])  # the areas need the landmarks

    def test_malformed_landmarks_exit_1_naming_file_line_and_key(self):
        f = r"odometry_landmarks\.json:\d+: "
        self.break_files([
            (self.LANDMARKS, lambda s: s[:-20], f + r"column \d+: invalid JSON"),
            (self.LANDMARKS, lambda s: '{"landmarks": ' + s + "}",
             r"odometry_landmarks\.json:1: the top level is not a JSON array"),
            (self.LANDMARKS, edit_json(lambda a: a[3].update(type="window")),
             f + r"\[3\]\.type: expected one of"),
            (self.LANDMARKS, edit_json(lambda a: a[1].update(status="lost")),
             f + r"\[1\]\.status: expected one of"),
            (self.LANDMARKS, edit_json(lambda a: a[0]["covariance"].pop()),
             f + r"\[0\]\.covariance: expected 3 rows of 3 numbers"),
            (self.LANDMARKS, edit_json(lambda a: a[5].update(position_in_world=[1, "2", 3])),
             f + r"\[5\]\.position_in_world: expected \[x, y, z\]"),
            (self.LANDMARKS, edit_json(lambda a: a[2].update(id=1)),
             f + r"\[2\]\.id: 1 is not above the previous id 1"),
            (self.LANDMARKS, edit_json(lambda a: a[14]["points"][1].update(covariance=[[1]])),
             f + r"\[14\]\.points\[1\]\.covariance: expected 3 rows"),
            (self.LANDMARKS, edit_json(lambda a: a[4].update(label=["1", "2"])),
             f + r"\[4\]\.label: expected text"),
        ])

    def test_malformed_door_and_area_maps_exit_1_naming_file_line_and_key(self):
        d = r"maps/odometry_doors\.json:\d+: "
        a = r"maps/odometry_areas\.json:\d+: "
        self.break_files([
            (self.DOORS, edit_json(lambda r: r.update(format="corridorsim.doors")),
             d + r"format: expected 'corridorsim.upward_doors'"),
            (self.DOORS, edit_json(lambda r: r.update(version=2)), d + r"version: expected 1"),
            (self.DOORS, edit_json(lambda r: r["doors"][0]["particles"][7].pop()),
             d + r"doors\[0\]\.particles\[7\]: expected \[x_a, y_a, x_b, y_b, top_height\]"),
            (self.DOORS, edit_json(lambda r: r["doors"][0].update(columns_m=[[1, 2]])),
             d + r"doors\[0\]\.columns_m: expected"),
            (self.AREAS, edit_json(lambda r: r["areas"][1].update(kind="office")),
             a + r"areas\[1\]\.kind: expected corridor or room"),
            (self.AREAS, edit_json(lambda r: r["areas"][1].update(polygon_m=None)),
             a + r"areas\[1\]\.polygon_m: a room needs"),
            (self.AREAS, edit_json(lambda r: r["areas"][0].update(landmark_ids=[1, "2"])),
             a + r"areas\[0\]\.landmark_ids: expected landmark ids"),
        ])

    def test_landmark_errors_point_at_the_object(self):
        run_dir = self.copy_run("landmark_line")
        path = os.path.join(run_dir, self.LANDMARKS)
        with open(path) as f:
            text = f.read()
        with open(path, "w") as f:
            f.write(text.replace('"type": "door"', '"type": 7', 1))
        result = self.assert_fails(run_dir, r"odometry_landmarks\.json:\d+: \[14\]\.type")
        line = int(re.search(r"odometry_landmarks\.json:(\d+):", result.stderr).group(1))
        lines = text.split("\n")
        self.assertEqual(lines[line - 1].strip(), "{")
        self.assertEqual(lines[line].strip(), '"id": 14,')

    def test_malformed_detections_exit_1_naming_file_line_and_column(self):
        def cell(line, column, value):
            def mutate(text):
                lines = text.split("\n")
                fields = lines[line - 1].split(",")
                fields[column] = value
                lines[line - 1] = ",".join(fields)
                return "\n".join(lines)
            return mutate

        f = r"odometry_detections\.csv:"
        multi_line_label = ('0.1,lateral,door_plate,300,200,280,190,330,210,number_region,,'
                            '"1\n2",,1.5,0.9,-1,0')

        def insert_then_break(text):
            lines = text.split("\n")
            lines.insert(1, multi_line_label)  # physical lines 2 and 3
            fields = lines[3].split(",")      # the fourth record, on physical line 5
            fields[2] = "window"
            lines[3] = ",".join(fields)
            return "\n".join(lines)

        self.break_files([
            (self.DETECTIONS, cell(3, 2, "window"), f + r"3: type: expected one of"),
            (self.DETECTIONS, cell(4, 15, "x"), f + r"4: landmark_id: expected an integer"),
            (self.DETECTIONS, cell(5, 15, "-2"), f + r"5: landmark_id: -2 is outside"),
            (self.DETECTIONS, cell(2, 0, "nan"), f + r"2: stamp_s: not finite"),
            (self.DETECTIONS, cell(2, 3, ""), f + r"2: u_px: missing"),
            (self.DETECTIONS, cell(3, 16, "2"), f + r"3: new_landmark: expected one of"),
            (self.DETECTIONS, lambda s: s.replace(",-1,0\n", ",-1,1\n", 1),
             f + r"\d+: new_landmark: a new landmark needs a landmark_id"),
            (self.DETECTIONS, lambda s: s.replace(",score,", ",confidence,", 1),
             f + r"1: the header has no column 'score'"),
            (self.DETECTIONS, lambda s: replace_line(s, 2, "0,front,corner"),
             f + r"2: expected 17 fields, got 3"),
            (self.DETECTIONS, insert_then_break, f + r"5: type: expected one of"),
        ])
        # Recognition scores (plates only) lie in [0, 1]; a box needs all four sides.
        run_dir = self.copy_run("recognition")
        path = os.path.join(run_dir, self.DETECTIONS)
        with open(path) as fh:
            lines = fh.read().split("\n")
        plate = next(i for i, line in enumerate(lines) if ",door_plate," in line and ",0.91" in line)
        broken = lines[plate].replace(",0.910000,", ",1.5,")
        lines[plate] = broken
        with open(path, "w") as fh:
            fh.write("\n".join(lines))
        self.assert_fails(run_dir, f + f"{plate + 1}: recognition_score: 1.5 is outside")
        fields = broken.replace(",1.5,", ",0.5,").split(",")
        fields[7] = ""
        lines[plate] = ",".join(fields)
        with open(path, "w") as fh:
            fh.write("\n".join(lines))
        self.assert_fails(run_dir, f + f"{plate + 1}: box_min_x_px: a box needs all four")

    def test_malformed_frame_times_exit_1_naming_file_and_line(self):
        f = r"maps/odometry_frame_times\.csv:"
        self.break_files([
            (self.FRAME_TIMES, lambda s: replace_line(s, 4, "0.100000000,5,2.1"),
             f + r"4: stamp_s: 0\.1 is before the previous 0\.3"),
            (self.FRAME_TIMES, lambda s: replace_line(s, 4, "0.900000000,-1,2.1"),
             f + r"4: landmarks: -1 is outside"),
            (self.FRAME_TIMES, lambda s: replace_line(s, 4, "0.900000000,4,fast"),
             f + r"4: frame_ms: not a number"),
            (self.FRAME_TIMES, lambda s: s.split("\n")[0] + "\n",
             r"maps/odometry_frame_times\.csv: has no frames"),
        ])

    def test_ellipse_and_vanishing_point_bearing(self):
        code = textwrap.dedent(f"""
            import importlib.util, json, math
            spec = importlib.util.spec_from_file_location("plot_run", {SCRIPT!r})
            m = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(m)
            c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
            # R diag(4, 1) R^T for a rotation of 30 degrees
            rotated = [[4 * c * c + s * s, 3 * c * s, 0], [3 * c * s, 4 * s * s + c * c, 0],
                       [0, 0, 1]]
            vp = {{"id": 0, "status": "converged", "position": (1000.0, 0.0, 1.0),
                   "covariance": [[1, 0, 0], [0, 4, 0], [0, 0, 1]]}}
            print(json.dumps({{
                "diagonal": m.ellipse_2sigma([[4, 0, 0], [0, 1, 0], [0, 0, 1]]),
                "rotated": m.ellipse_2sigma(rotated),
                "indefinite": m.ellipse_2sigma([[1, 2, 0], [2, 1, 0], [0, 0, 1]]),
                "null": m.ellipse_2sigma([[1, None, 0], [0, 1, 0], [0, 0, 1]]),
                "vp": m.vanishing_point_text(vp),
                "plain": m.plain("$x$"),
            }}))
        """)
        result = subprocess.run([plot_python(), "-c", code], capture_output=True, text=True,
                                timeout=120)
        self.assertEqual(result.returncode, 0, result.stderr)
        out = json.loads(result.stdout)
        k = 2.0 * math.sqrt(5.991)  # full axes of the 95 % ellipse (chi-square 2 dof)
        for key in ["diagonal", "rotated"]:
            width, height, angle = out[key]
            self.assertAlmostEqual(width, k * 2.0, places=9)
            self.assertAlmostEqual(height, k * 1.0, places=9)
        self.assertAlmostEqual(out["diagonal"][2], 0.0, places=9)
        self.assertAlmostEqual(out["rotated"][2], 30.0, places=9)
        self.assertIsNone(out["indefinite"])
        self.assertIsNone(out["null"])
        # sigma_y 2 m at 1000 m: a bearing sigma of 2 mrad, 2 sigma = 0.229 deg.
        self.assertIn("bearing 0.00° ± 0.23° (2σ)", out["vp"])
        self.assertEqual(out["plain"], r"\$x\$")


if __name__ == "__main__":
    unittest.main()
