"""Strict readers of corridorsim's output files: a run folder (README.md "Run folder"), a study
folder (docs/studies.md "Outputs") and a dataset (docs/datasets.md, docs/export.md).

Every reader checks what it reads and raises InputError naming the file and, where it can, the
line (and the key or column) on the first problem; every size and count is bounded. The readers
are shared by scripts/plot_run.py (and the scripts that import it), scripts/make_viewer.py and
corridorsim.analysis (Run, Study, Dataset).

The run folder's files are read here; the reading under them (InputError, JSON with line numbers,
CSV tables and cells, FolderReader) is readers.py, the exact pose and whole-JSON readers the
analysis side adds are analysis_files.py, and both are importable from here under the same names.
Study folders: study_files.py; datasets and exports: dataset_files.py.

Units: metres, seconds, radians, world frame W (docs/frames.md).
"""

import csv
import json
import math
import os
import re

import numpy as np

# The reading machinery (readers.py) and the analysis side's readers (analysis_files.py), under
# their names here as before.
from .analysis_files import (MAX_EVENTS, MAX_JSON_BYTES, MAX_POSES,  # noqa: F401
                             OV_EVAL_COVARIANCE, PIPELINE_NAME, TUM_FIELDS, load_json_fast,
                             parse_number, parse_stamp_ns, read_covariance, read_events,
                             read_json_object, read_metrics_full, read_stamp_ns,
                             read_tum_exact, text_list)
from .readers import (MAX_CSV_ROWS, MAX_FILE_BYTES, MAX_TEXT_CHARS, CsvCells,  # noqa: F401
                      FolderReader, InputError, JsonArray, JsonObject, JsonReader, data_lines,
                      finite_float, is_integer, is_number, load_json, no_json_constant,
                      read_csv_records, read_csv_table, read_short_text, read_text)

# Bounds on what an input may hold (each becomes a loop count or a figure size).
MAX_LANDMARKS = 100_000
MAX_LANDMARK_POINTS = 16
MAX_PARTICLES = 100_000    # samples of one door in maps/<pipeline>_doors.json
MAX_DISTRACTORS = 100_000

# Scalars read_metrics takes from metrics.json's pipelines, with their labels in plot_run's
# summary.png.
SUMMARY_METRICS = [
    ("ate_rmse_m", "ATE RMSE [m]"),
    ("ate_aligned_rmse_m", "ATE RMSE, aligned [m]"),
    ("final_position_error_m", "final position error [m]"),
    ("nees_mean", "mean NEES (3 dof)"),
    ("nees_in_band_fraction", "NEES in 95 % band"),
]
DETECTOR_SCORES = ["precision", "recall", "accuracy"]

# A door's states in ground_truth.json (worlds/world_io.cpp).
DOOR_STATES = ("closed", "open", "empty")

# Landmark and detection types (slam/pipeline.cpp's names) and landmark statuses.
LANDMARK_TYPES = ["door_plate", "door", "lamp", "corner", "vanishing_point"]
LANDMARK_STATUSES = ["initializing", "converged"]


def read_world(path):
    """The plan-view parts of ground_truth.json (schema: worlds/world_io.cpp) as {walls: [(a, b)],
    doors: [{a, b, state, room, footprint}], plates: [{center, normal, room}], lamps: [{center,
    shape, extent, on}], distractors: [{center, class}]}; points are (x, y) in metres."""
    root = load_json(path)
    r = JsonReader(path)
    world = {"walls": [], "doors": [], "plates": [], "lamps": [], "distractors": []}
    for name, wall in r.items(root, "walls"):
        a, b = r.vec2(wall, "start", name), r.vec2(wall, "end", name)
        if a is None or b is None:
            r.fail(wall, name, "needs start and end")
        world["walls"].append((a, b))
    for name, door in r.items(root, "doors"):
        a, b = r.vec2(door, "column_a", name), r.vec2(door, "column_b", name)
        if a is None or b is None:
            r.fail(door, name, "needs column_a and column_b")
        state = r.get(door, "state", "text", name)
        if state is not None and state not in DOOR_STATES:
            r.fail(door, f"{name}.state", f"expected one of {sorted(DOOR_STATES)}, got '{state}'")
        footprint = None
        room = r.get(door, "room", "object", name)
        if room is not None:
            lo, hi = r.vec2(room, "min", f"{name}.room"), r.vec2(room, "max", f"{name}.room")
            if lo is None or hi is None:
                r.fail(room, f"{name}.room", "needs min and max")
            footprint = (lo, hi)
        world["doors"].append({"a": a, "b": b, "state": state,
                               "room": r.get(door, "room_number", "text", name),
                               "footprint": footprint})
    for name, plate in r.items(root, "door_plates"):
        center = r.vec2(plate, "center", name)
        if center is None:
            r.fail(plate, name, "needs center")
        world["plates"].append({"center": center, "normal": r.vec2(plate, "normal", name),
                                "room": r.get(plate, "room_number", "text", name)})
    for name, lamp in r.items(root, "lamps"):
        center = r.vec2(lamp, "center", name)
        if center is None:
            r.fail(lamp, name, "needs center")
        shape = r.get(lamp, "shape", "text", name) or "circular"
        if shape == "circular":
            radius = r.get(lamp, "radius", "number", name)
            if radius is None or radius <= 0:
                r.fail(lamp, name, "a circular lamp needs a positive radius")
            extent = float(radius)
        elif shape == "panel":
            extent = r.vec2(lamp, "size", name)
            if extent is None or min(extent) <= 0:
                r.fail(lamp, name, "a panel lamp needs a positive size [x, y]")
        else:
            r.fail(lamp, f"{name}.shape", f"expected circular or panel, got '{shape}'")
        on = r.get(lamp, "on", "bool", name)
        world["lamps"].append({"center": center, "shape": shape, "extent": extent,
                               "on": True if on is None else on})
    for name, distractor in r.items(root, "distractors"):
        if len(world["distractors"]) == MAX_DISTRACTORS:
            r.fail(distractor, name, f"more than {MAX_DISTRACTORS} distractors")
        center = r.vec2(distractor, "center", name)
        if center is None:
            r.fail(distractor, name, "needs center")
        kind = r.get(distractor, "class", "text", name)
        if kind is None:
            r.fail(distractor, f"{name}.class", "missing")
        kind = str(kind)
        if len(kind) > MAX_TEXT_CHARS:
            r.fail(distractor, f"{name}.class", f"longer than {MAX_TEXT_CHARS} characters")
        world["distractors"].append({"center": center, "class": kind})
    return world


def read_tum(path):
    """TUM trajectory as an (N, 8) array: t tx ty tz qx qy qz qw (s, m, unit quaternion)."""
    rows = []
    for number, fields in data_lines(path):
        if len(fields) != 8:
            raise InputError(path, number, f"expected 8 numbers 't tx ty tz qx qy qz qw', "
                             f"got {len(fields)} fields")
        try:
            values = [float(v) for v in fields]
        except ValueError:
            raise InputError(path, number, "not a number in the line") from None
        if not all(math.isfinite(v) for v in values):
            raise InputError(path, number, "non-finite value")
        rows.append(values)
    if not rows:
        raise InputError(path, None, "has no poses")
    return np.array(rows)


ERROR_COLUMNS_REQUIRED = ["t", "ex_m", "ey_m", "eyaw_rad"]
ERROR_COLUMNS_OPTIONAL = ["sigma_x_m", "sigma_y_m", "sigma_yaw_rad", "nees"]


def read_errors(path):
    """<pipeline>_errors.csv as {column: array}; optional columns absent from the header are
    missing from the result, and empty cells (or 'nan') are NaN."""
    lines = read_text(path).splitlines()
    if not lines or not lines[0].strip():
        raise InputError(path, 1, "missing the header line")
    header = [h.strip() for h in next(csv.reader([lines[0]]))]
    for column in ERROR_COLUMNS_REQUIRED:
        if column not in header:
            raise InputError(path, 1, f"the header has no column '{column}'")
    wanted = [c for c in ERROR_COLUMNS_REQUIRED + ERROR_COLUMNS_OPTIONAL if c in header]
    index = {c: header.index(c) for c in wanted}
    columns = {c: [] for c in wanted}
    for number, row in enumerate(csv.reader(lines[1:]), start=2):
        if not row or all(not cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise InputError(path, number, f"expected {len(header)} fields, got {len(row)}")
        for c in wanted:
            cell = row[index[c]].strip()
            try:
                value = float(cell) if cell else math.nan
            except ValueError:
                raise InputError(path, number, f"{c}: not a number: '{cell}'") from None
            if c == "t" and not math.isfinite(value):
                raise InputError(path, number, "t: must be a finite time in seconds")
            columns[c].append(value)
    return {c: np.array(v, dtype=float) for c, v in columns.items()}


def read_metrics(path):
    """The parts of metrics.json the plots use; every key is optional."""
    root = load_json(path)
    r = JsonReader(path)
    metrics = {"pipelines": {}, "expectations": []}
    pipelines = r.get(root, "pipelines", "object", "") or {}
    for name, entry in pipelines.items():
        where = f"pipelines.{name}"
        if not re.fullmatch(r"[A-Za-z0-9_+-][A-Za-z0-9_.+-]*", name):
            r.fail(pipelines, where, "a pipeline name must be a plain file stem")
        if not isinstance(entry, dict):
            r.fail(pipelines, where, "expected an object")
        m = {key: r.get(entry, key, "number", where) for key, _ in SUMMARY_METRICS}
        band = r.get(entry, "nees_band", "array", where)
        if band is not None:
            if len(band) != 2 or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                         for v in band) or not 0 <= band[0] < band[1]:
                r.fail(band, f"{where}.nees_band", "expected [lo, hi] with 0 <= lo < hi")
            band = (float(band[0]), float(band[1]))
        m["nees_band"] = band
        m["detectors"] = read_detectors(r, entry, where)
        metrics["pipelines"][name] = m
    for name, item in r.items(root, "expectations"):
        text = r.get(item, "text", "text", name)
        measured = item.get("measured")
        if isinstance(measured, (dict, list)):
            r.fail(item, f"{name}.measured", "expected a number or text")
        metrics["expectations"].append({"text": "" if text is None else str(text),
                                         "measured": measured,
                                         "passed": r.get(item, "passed", "bool", name)})
    return metrics


def read_detectors(r, entry, where):
    """[(detector, {score: value})] from `detectors`: an object {name: {precision, recall,
    accuracy}} or an array of such objects, each with a `name` (or `detector`)."""
    detectors = entry.get("detectors")
    if detectors is None:
        return []
    if isinstance(detectors, dict):
        named = list(detectors.items())
    elif isinstance(detectors, list):
        named = []
        for i, d in enumerate(detectors):
            label = d.get("name", d.get("detector")) if isinstance(d, dict) else None
            named.append((str(label) if label is not None else f"detector {i + 1}", d))
    else:
        r.fail(entry, f"{where}.detectors", "expected an object or an array")
    out = []
    for name, d in named:
        if not isinstance(d, dict):
            r.fail(detectors, f"{where}.detectors.{name}", "expected an object")
        scores = {s: r.get(d, s, "number", f"{where}.detectors.{name}") for s in DETECTOR_SCORES}
        if any(v is not None for v in scores.values()):
            out.append((name, scores))
    return out


def read_point3(r, obj, where):
    """position_in_world and covariance of a landmark or one of its points: ((x, y, z) in m,
    3x3 list in m^2 with None for a null or non-finite entry: the writer emits null for NaN, and
    such a covariance is drawn without its ellipse and counted in the figure's title)."""
    position = obj.get("position_in_world")
    if not (isinstance(position, list) and len(position) == 3 and
            all(is_number(v) and math.isfinite(v) for v in position)):
        r.fail(obj, f"{where}.position_in_world",
               f"expected [x, y, z] in metres, got {json.dumps(position)[:40]}")
    covariance = obj.get("covariance")
    if not (isinstance(covariance, list) and len(covariance) == 3 and
            all(isinstance(row, list) and len(row) == 3 and
                all(v is None or is_number(v) for v in row) for row in covariance)):
        r.fail(obj, f"{where}.covariance",
               f"expected 3 rows of 3 numbers (m^2), got {json.dumps(covariance)[:40]}")
    return (tuple(float(v) for v in position),
            [[None if v is None or not math.isfinite(v) else float(v) for v in row]
             for row in covariance])


def read_landmarks(path):
    """<pipeline>_landmarks.json (harness/run/run_io.cpp LandmarksJson) as a list of
    {id, type, status, label, position, covariance, points: [{role, position, covariance}]}."""
    root = load_json(path, top="array")
    r = JsonReader(path)
    if len(root) > MAX_LANDMARKS:
        r.fail(root, "top level", f"more than {MAX_LANDMARKS} landmarks")
    landmarks = []
    for i, item in enumerate(root):
        where = f"[{i}]"
        if not isinstance(item, dict):
            r.fail(root, where, "expected an object")
        lid = r.integer(item, "id", where, minimum=0)
        if landmarks and lid <= landmarks[-1]["id"]:
            r.fail(item, f"{where}.id", f"{lid} is not above the previous id "
                   f"{landmarks[-1]['id']} (the file is in id order, each id once)")
        kind = r.get(item, "type", "text", where)
        if kind not in LANDMARK_TYPES:
            r.fail(item, f"{where}.type", f"expected one of {LANDMARK_TYPES}, got "
                   f"{json.dumps(kind)[:40]}")
        status = r.get(item, "status", "text", where)
        if status not in LANDMARK_STATUSES:
            r.fail(item, f"{where}.status", f"expected one of {LANDMARK_STATUSES}, got "
                   f"{json.dumps(status)[:40]}")
        position, covariance = read_point3(r, item, where)
        points = []
        for name, point in r.items(item, "points"):
            pwhere = f"{where}.{name}"
            if len(points) == MAX_LANDMARK_POINTS:
                r.fail(item, f"{where}.points", f"more than {MAX_LANDMARK_POINTS} points")
            ppos, pcov = read_point3(r, point, pwhere)
            points.append({"role": read_short_text(r, point, "role", pwhere, required=False),
                           "position": ppos, "covariance": pcov})
        landmarks.append({"id": lid, "type": kind, "status": status,
                          "label": read_short_text(r, item, "label", where, required=False),
                          "position": position, "covariance": covariance, "points": points})
    return landmarks


def read_format(r, root, expected):
    """Checks a map file's `format` and `version` (1)."""
    if root.get("format") != expected:
        r.fail(root, "format", f"expected '{expected}', got {json.dumps(root.get('format'))[:40]}")
    if root.get("version") != 1:
        r.fail(root, "version", f"expected 1, got {json.dumps(root.get('version'))[:40]}")


def finite_numbers(value, count):
    return (isinstance(value, list) and len(value) == count and
            all(is_number(v) and math.isfinite(v) for v in value))


def map_items(path, expected, key):
    """A maps/ file whose `format` is `expected` (read_format): its JsonReader and its array `key`
    as (name, object) pairs, failing at the one after MAX_LANDMARKS."""
    root = load_json(path)
    r = JsonReader(path)
    read_format(r, root, expected)

    def items():
        for count, (name, item) in enumerate(r.items(root, key)):
            if count == MAX_LANDMARKS:
                r.fail(item, name, f"more than {MAX_LANDMARKS} {key}")
            yield name, item

    return r, items()


def read_upward_doors(path):
    """maps/<pipeline>_doors.json (slam/p3_upward_pipeline.cpp) as a list of
    {id, columns: ((xa, ya), (xb, yb)), particles: [(xa, ya, xb, yb, h)]}."""
    r, items = map_items(path, "corridorsim.upward_doors", "doors")
    doors = []
    for name, door in items:
        lid = r.integer(door, "landmark_id", name)
        columns = door.get("columns_m")
        if not (isinstance(columns, list) and len(columns) == 2 and
                all(finite_numbers(c, 2) for c in columns)):
            r.fail(door, f"{name}.columns_m", "expected [[x_a, y_a], [x_b, y_b]] in metres")
        particles = r.get(door, "particles", "array", name) or []
        if len(particles) > MAX_PARTICLES:
            r.fail(door, f"{name}.particles", f"more than {MAX_PARTICLES} particles")
        for i, sample in enumerate(particles):
            if not finite_numbers(sample, 5):
                r.fail(door, f"{name}.particles[{i}]",
                       "expected [x_a, y_a, x_b, y_b, top_height] in metres")
        doors.append({"id": lid, "columns": (tuple(columns[0]), tuple(columns[1])),
                      "particles": [tuple(float(v) for v in p) for p in particles]})
    return doors


def read_areas(path):
    """maps/<pipeline>_areas.json (slam/mapping/door_areas.h) as a list of
    {id, kind, door, polygon: [(x, y)] or None, landmarks: set of ids}."""
    r, items = map_items(path, "corridorsim.upward_areas", "areas")
    areas = []
    for name, area in items:
        aid = r.integer(area, "id", name)
        kind = r.get(area, "kind", "text", name)
        if kind not in ("corridor", "room"):
            r.fail(area, f"{name}.kind", f"expected corridor or room, got {json.dumps(kind)[:40]}")
        polygon = r.get(area, "polygon_m", "array", name)
        if kind == "room" and not (polygon and len(polygon) <= 64 and
                                   all(finite_numbers(v, 2) for v in polygon)):
            r.fail(area, f"{name}.polygon_m", "a room needs [[x, y], ...] in metres (at most 64)")
        ids = r.get(area, "landmark_ids", "array", name) or []
        if len(ids) > MAX_LANDMARKS or not all(is_integer(i) for i in ids):
            r.fail(area, f"{name}.landmark_ids", "expected landmark ids (integers)")
        areas.append({"id": aid, "kind": kind, "door": area.get("door_landmark_id"),
                      "polygon": [tuple(v) for v in polygon] if kind == "room" else None,
                      "landmarks": set(ids)})
    return areas


DETECTION_COLUMNS = ["stamp_s", "camera", "type", "u_px", "v_px", "box_min_x_px", "box_min_y_px",
                     "box_max_x_px", "box_max_y_px", "plate_box", "radius_px", "label", "open",
                     "score", "recognition_score", "landmark_id", "new_landmark"]
BOX_COLUMNS = DETECTION_COLUMNS[5:9]


def read_detections(path):
    """<pipeline>_detections.csv (harness/run/run_io.cpp DetectionsCsv) as {column: list}: stamp_s,
    u_px, v_px, score, recognition_score (floats, NaN = no value), camera, type, label (text),
    landmark_id (int, -1 = not associated), new_landmark (bool)."""
    out = {c: [] for c in ["stamp_s", "camera", "type", "u_px", "v_px", "label", "score",
                           "recognition_score", "landmark_id", "new_landmark"]}
    for line, cells in read_csv_table(path, DETECTION_COLUMNS):
        c = CsvCells(path, line, cells)
        stamp = c.number("stamp_s", lo=0.0)
        camera = c.text("camera", required=True)
        kind = c.choice("type", LANDMARK_TYPES)
        u, v = c.number("u_px"), c.number("v_px")
        box = [c.number(b, required=False) for b in BOX_COLUMNS]
        if any(math.isnan(b) for b in box) and not all(math.isnan(b) for b in box):
            c.fail("box_min_x_px", "a box needs all four of min x, min y, max x, max y or none")
        if box[0] > box[2] or box[1] > box[3]:
            c.fail("box_min_x_px", "the box's min lies beyond its max")
        c.choice("plate_box", ["", "number_region", "outline"])
        c.number("radius_px", required=False, lo=0.0)
        label = c.text("label", required=False)
        c.choice("open", ["", "0", "1"])
        score = c.number("score", required=False)
        recognition = c.number("recognition_score", required=False, lo=0.0, hi=1.0)
        landmark_id = c.integer("landmark_id", -1, 2**31 - 1)
        new_landmark = c.choice("new_landmark", ["0", "1"]) == "1"
        if new_landmark and landmark_id < 0:
            c.fail("new_landmark", "a new landmark needs a landmark_id")
        for key, value in [("stamp_s", stamp), ("camera", camera), ("type", kind), ("u_px", u),
                           ("v_px", v), ("label", label), ("score", score),
                           ("recognition_score", recognition), ("landmark_id", landmark_id),
                           ("new_landmark", new_landmark)]:
            out[key].append(value)
    return out


def read_frame_times(path):
    """maps/<pipeline>_frame_times.csv (slam/filter_support.h, FrameCostsCsv) as arrays stamp_s (s,
    non-decreasing: a pipeline that reads two cameras records a frame of each, which may share a
    stamp), landmarks (count) and frame_ms (ms)."""
    out = {"stamp_s": [], "landmarks": [], "frame_ms": []}
    for line, cells in read_csv_table(path, list(out)):
        c = CsvCells(path, line, cells)
        stamp = c.number("stamp_s", lo=0.0)
        if out["stamp_s"] and stamp < out["stamp_s"][-1]:
            c.fail("stamp_s", f"{stamp:.9g} is before the previous {out['stamp_s'][-1]:.9g}")
        out["stamp_s"].append(stamp)
        out["landmarks"].append(c.integer("landmarks", 0, MAX_LANDMARKS))
        out["frame_ms"].append(c.number("frame_ms", lo=0.0))
    if not out["stamp_s"]:
        raise InputError(path, None, "has no frames")
    return {k: np.array(v, dtype=float) for k, v in out.items()}


def read_optional(path, reader):
    """reader(path) when the file exists, else None."""
    return reader(path) if os.path.exists(path) else None


def read_run(run_dir):
    """Reads and checks every input; raises InputError on the first problem."""
    if not os.path.isdir(run_dir):
        raise InputError(run_dir, None, "is not a directory")
    run = {
        "world": read_world(os.path.join(run_dir, "world.json")),
        "metrics": read_metrics(os.path.join(run_dir, "metrics.json")),
        "truth": read_tum(os.path.join(run_dir, "ground_truth.tum")),
        "pipelines": {},
    }
    names = list(run["metrics"]["pipelines"])
    if not names:
        names = sorted(f[:-len(".tum")] for f in os.listdir(run_dir)
                       if f.endswith(".tum") and f != "ground_truth.tum")
    for name in names:
        run["pipelines"][name] = {
            "trajectory": read_tum(os.path.join(run_dir, f"{name}.tum")),
            "errors": read_errors(os.path.join(run_dir, f"{name}_errors.csv")),
            "landmarks": read_optional(os.path.join(run_dir, f"{name}_landmarks.json"),
                                       read_landmarks),
            "detections": read_optional(os.path.join(run_dir, f"{name}_detections.csv"),
                                        read_detections),
            "frame_times": read_optional(os.path.join(run_dir, "maps",
                                                      f"{name}_frame_times.csv"),
                                         read_frame_times),
            "doors": read_optional(os.path.join(run_dir, "maps", f"{name}_doors.json"),
                                   read_upward_doors),
            "areas": read_optional(os.path.join(run_dir, "maps", f"{name}_areas.json"),
                                   read_areas),
        }
    return run


NIS_COLUMNS = ["t", "type", "dof", "nis", "accepted"]
MAX_DOF = 10_000


def read_nis(path):
    """<pipeline>_nis.csv (harness/metrics/consistency.cpp NisSeriesCsv) as {t: [s], type: [text],
    dof: [int], nis: [float], accepted: [bool]}, one entry per landmark update."""
    out = {c: [] for c in NIS_COLUMNS}
    for line, cells in read_csv_table(path, NIS_COLUMNS):
        c = CsvCells(path, line, cells)
        out["t"].append(c.number("t", lo=0.0))
        out["type"].append(c.choice("type", LANDMARK_TYPES))
        out["dof"].append(c.integer("dof", 1, MAX_DOF))
        out["nis"].append(c.number("nis", lo=0.0))
        out["accepted"].append(c.choice("accepted", ["0", "1"]) == "1")
    return out
