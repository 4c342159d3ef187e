#!/usr/bin/python3
"""Writes RUN_DIR/viewer.html: one self-contained page (data, uPlot, our script and styles
inlined) that shows a run with one time cursor (docs/viewer.md).

    make_viewer.py RUN_DIR [--out FILE] [--budget-mb MB]

Reads the run folder through corridorsim.files (the strict readers of plot_run.py). Exit 0:
written; 2: a file of the run folder is malformed (path:line: message) or a bad argument; 1: the
page could not be written. corridorsim run calls it after the results (an extra: exit 4 there).
"""

import argparse
import base64
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import system_python  # noqa: E402

system_python.use_corridorsim_with("files", "stats")
from corridorsim import files  # noqa: E402
from corridorsim.stats import chi2_band  # noqa: E402
from pages import fill_page, keep_path_bytes, make_page, page_json  # noqa: E402
from viewer_series import (extrema_indices, pick, rounded, significant,  # noqa: E402
                           stride_indices)
from viewer_sensors import read_sensors, sensors_json  # noqa: E402

SCHEMA = 1
# Samples per series before decimation starts (paths, error plots); halved until the page fits.
START_POINTS = 6000
MIN_POINTS = 250
DEFAULT_BUDGET_MB = 10.0   # without frames (docs/viewer.md); frames have their own budget
FRAMES_BUDGET_MB = 40.0    # the most `run --keep-frames` may keep, and so inline
NEES_DOF = 3
MAX_TEXT = 200             # characters of an event's or a failure's text
M, RAD, S = 4, 5, 4        # decimals of metres, radians, seconds in the page
# Significant digits of covariances: an elongated ellipse (odometry's, eigenvalue ratio ~4000)
# keeps its minor axis to 1e-5 m with 7; 4 moved it by 1.4 %.
COV_DIGITS = 7


def yaw_of(qz, qw):
    return 2.0 * math.atan2(qz, qw)


def world_json(world):
    xs, ys = [], []
    walls = []
    for a, b in world["walls"]:
        walls.append(rounded([a[0], a[1], b[0], b[1]], M))
        xs += [a[0], b[0]]
        ys += [a[1], b[1]]
    doors = [{"a": rounded(d["a"], M), "b": rounded(d["b"], M), "state": d["state"],
              "room": d["room"]} for d in world["doors"]]
    plates = [{"center": rounded(p["center"], M),
               "normal": rounded(p["normal"], M) if p["normal"] is not None else None,
               "room": p["room"]} for p in world["plates"]]
    lamps = []
    for lamp in world["lamps"]:
        extent = lamp["extent"]
        lamps.append({"center": rounded(lamp["center"], M), "shape": lamp["shape"],
                      "extent": (round(extent, M) if lamp["shape"] == "circular"
                                 else rounded(extent, M)),
                      "on": bool(lamp["on"])})
    distractors = [{"center": rounded(d["center"], M), "class": d["class"]}
                   for d in world.get("distractors", [])]
    for item in plates + lamps + distractors:
        xs.append(item["center"][0])
        ys.append(item["center"][1])
    bounds = [min(xs), min(ys), max(xs), max(ys)] if xs else [0.0, 0.0, 1.0, 1.0]
    return {"bounds": rounded(bounds, M), "walls": walls, "doors": doors, "plates": plates,
            "lamps": lamps, "distractors": distractors}


def tum_stamp_keys(path):
    """The stamps of a TUM file as their exact text (the page matches files by it)."""
    keys = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                keys.append(line.split()[0])
    return keys


def read_covariances(path, count):
    """_cov.txt's position covariance (Pt11, Pt12, Pt22: columns 14, 15, 17) per line."""
    cxx, cxy, cyy = [], [], []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, start=1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            fields = line.split()
            if len(fields) != 20:
                raise files.InputError(path, number, f"expected 20 fields (ov_eval), got "
                                       f"{len(fields)}")
            try:
                cxx.append(float(fields[14]))
                cxy.append(float(fields[15]))
                cyy.append(float(fields[17]))
            except ValueError:
                raise files.InputError(path, number, "not a number in the line") from None
    if len(cxx) != count:
        raise files.InputError(path, None, f"has {len(cxx)} estimates, the .tum {count}")
    return cxx, cxy, cyy


def read_nis(path, limit):
    """<pipeline>_nis.csv by landmark type: t, nis, accepted (decimated by extrema)."""
    by_type = {}
    for line, cells in files.read_csv_table(path, ["t", "type", "dof", "nis", "accepted"]):
        c = files.CsvCells(path, line, cells)
        t = c.number("t", lo=0.0)
        kind = c.text("type", required=True)
        dof = c.integer("dof", 1, 64)
        nis = c.number("nis", required=False)
        accepted = c.choice("accepted", ["0", "1"]) == "1"
        entry = by_type.setdefault(kind, {"dof": dof, "t": [], "nis": [], "accepted": []})
        if entry["dof"] != dof:
            c.fail("dof", f"type {kind} had {entry['dof']} degrees of freedom before, now {dof}")
        entry["t"].append(t)
        entry["nis"].append(nis)
        entry["accepted"].append(1 if accepted else 0)
    out = {}
    for kind, entry in sorted(by_type.items()):
        keep = extrema_indices(entry["t"], [entry["nis"]], limit)
        out[kind] = {"dof": entry["dof"], "band": significant(chi2_band(entry["dof"])),
                     "t": rounded(pick(entry["t"], keep), S),
                     "nis": significant(pick(entry["nis"], keep)),
                     "accepted": pick(entry["accepted"], keep)}
    return out


def read_detection_rows(path):
    """The detections the page uses (stamp, camera, type, pixel, box, label, landmark), each
    checked as read_detections checks it (one pass: the file is the page's largest input)."""
    used = ["stamp_s", "camera", "type", "u_px", "v_px", "label", "landmark_id"]
    out = []
    for line, cells in files.read_csv_table(path, used + files.BOX_COLUMNS):
        c = files.CsvCells(path, line, cells)
        box = [c.number(b, required=False) for b in files.BOX_COLUMNS]
        if all(math.isnan(b) for b in box):
            box = None
        elif any(math.isnan(b) for b in box) or box[0] > box[2] or box[1] > box[3]:
            c.fail("box_min_x_px", "a box needs min x <= max x and min y <= max y, all four or "
                   "none")
        out.append({"t": round(c.number("stamp_s", lo=0.0), 6),
                    "camera": c.text("camera", required=True)[:MAX_TEXT],
                    "type": c.choice("type", files.LANDMARK_TYPES),
                    "u": round(c.number("u_px"), 1), "v": round(c.number("v_px"), 1),
                    "box": rounded(box, 1) if box else None,
                    "label": (c.text("label", required=False) or "")[:MAX_TEXT],
                    "landmark": c.integer("landmark_id", -1, 2**31 - 1)})
    return out


def truth_landmarks(world):
    """(type, position, label) of what a map may hold: plates, lamps, door columns."""
    out = []
    for plate in world["plates"]:
        out.append(("door_plate", plate["center"], plate["room"]))
    for lamp in world["lamps"]:
        out.append(("lamp", lamp["center"], None))
    for door in world["doors"]:
        mid = ((door["a"][0] + door["b"][0]) / 2.0, (door["a"][1] + door["b"][1]) / 2.0)
        out.append(("door", mid, door["room"]))
    return out


TRUTH_GATE_M = 1.0  # a landmark farther than this from every true one of its type has none


def landmark_rows(landmarks, detections, world):
    """The final map with when each landmark was first seen, its nearest true landmark of its
    type (within TRUTH_GATE_M) and whether it is wrong: no true landmark near, or a plate whose
    room number differs from the true plate's."""
    first_seen = {}
    for d in detections:
        if d["landmark"] >= 0:
            first_seen[d["landmark"]] = min(first_seen.get(d["landmark"], math.inf), d["t"])
    truths = truth_landmarks(world)
    rows = []
    for lm in landmarks:
        x, y = lm["position"][0], lm["position"][1]
        cov = lm["covariance"]
        best, best_d = None, math.inf
        for kind, pos, label in truths:
            if kind != lm["type"]:
                continue
            dist = math.hypot(pos[0] - x, pos[1] - y)
            if dist < best_d:
                best, best_d = (pos, label), dist
        truth = best if best is not None and best_d <= TRUTH_GATE_M else None
        comparable = lm["type"] in ("door_plate", "lamp", "door")
        wrong = comparable and (truth is None or (
            lm["type"] == "door_plate" and lm["label"] and truth[1] is not None
            and lm["label"] != truth[1]))
        seen = first_seen.get(lm["id"])
        rows.append({"id": lm["id"], "type": lm["type"], "status": lm["status"],
                     "label": (lm["label"] or "")[:MAX_TEXT],
                     "x": round(x, M), "y": round(y, M),
                     "cxx": significant([cov[0][0]], COV_DIGITS)[0],
                     "cxy": significant([cov[0][1]], COV_DIGITS)[0],
                     "cyy": significant([cov[1][1]], COV_DIGITS)[0],
                     "first_seen": round(seen, S) if seen is not None else None,
                     "truth": rounded(truth[0], M) if truth else None, "wrong": bool(wrong)})
    return rows


def event_rows(path):
    """events.json as (rows for the page, {pipeline: its failure's text})."""
    if not os.path.exists(path):
        return [], {}
    root = files.load_json(path)
    items = root.get("events", []) if isinstance(root, dict) else root
    out, failures = [], {}
    for item in items if isinstance(items, list) else []:
        if not isinstance(item, dict) or not isinstance(item.get("t"), (int, float)):
            continue
        kind = str(item.get("type", "event"))
        rest = ", ".join(f"{k} {json.dumps(v)}" for k, v in item.items()
                         if k not in ("t", "t_ns", "type"))
        out.append({"t": round(float(item["t"]), S), "type": kind[:MAX_TEXT],
                    "text": rest[:MAX_TEXT]})
        if kind == "pipeline_failed" and isinstance(item.get("pipeline"), str):
            failures[item["pipeline"]] = (f"{item.get('call', '')} threw at t = "
                                          f"{float(item['t']):.3f} s: "
                                          f"{item.get('reason', '')}")[:MAX_TEXT]
    return out, failures


def expectation_rows(metrics):
    out = []
    for item in metrics.get("expectations", []) if isinstance(metrics, dict) else []:
        if isinstance(item, dict):
            out.append({"text": str(item.get("expectation", item.get("text", "")))[:MAX_TEXT],
                        "measured": item.get("measured"), "passed": bool(item.get("passed"))})
    return out


def cost_section(value, depth=0):
    """A pipeline's section of timing.json as the page carries it: objects of numbers (4
    significant digits), nulls and objects, keys cut to MAX_TEXT characters; anything else, or
    nesting deeper than 3, is left out."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return significant([value])[0]
    if isinstance(value, dict) and depth < 3:
        return {str(k)[:MAX_TEXT]: cost_section(v, depth + 1) for k, v in list(value.items())[:256]
                if v is None or isinstance(v, (dict, int, float)) and not isinstance(v, bool)}
    return None


def read_costs(run_dir):
    """{pipeline: its timing.json section (stage_seconds, cpu_*, an external one's `protocol`)}:
    what the page shows as the pipeline's cost; {} without timing.json (a hand-made folder)."""
    path = os.path.join(run_dir, "timing.json")
    if not os.path.exists(path):
        return {}
    pipelines = files.read_json_object(path).get("pipelines")
    if not isinstance(pipelines, dict):
        return {}
    return {name: cost_section(section) for name, section in pipelines.items()
            if isinstance(section, dict)}


def read_frames(run_dir):
    """frames/frames.csv (`corridorsim run --keep-frames`): camera,t_ns,file,scale,width,height
    per kept JPEG; the images are inlined as base64."""
    index = os.path.join(run_dir, "frames", "frames.csv")
    if not os.path.exists(index):
        return {}, 0
    out, total = {}, 0
    columns = ["camera", "t_ns", "file", "scale", "width", "height"]
    for line, cells in files.read_csv_table(index, columns):
        c = files.CsvCells(index, line, cells)
        camera = c.text("camera", required=True)
        t_ns = c.integer("t_ns", 0, 2**62)
        name = c.text("file", required=True)
        if "/" in name or name.startswith("."):
            c.fail("file", "must name a file in frames/")
        scale = c.number("scale", lo=1e-3, hi=1.0)
        width = c.integer("width", 1, 10000)
        height = c.integer("height", 1, 10000)
        path = os.path.join(run_dir, "frames", name)
        size = os.path.getsize(path)
        total += size
        if total > FRAMES_BUDGET_MB * 1e6:
            raise files.InputError(index, line, f"the kept frames pass {FRAMES_BUDGET_MB} MB")
        with open(path, "rb") as f:
            data = base64.b64encode(f.read()).decode("ascii")
        cam = out.setdefault(camera, {"width": width, "height": height, "scale": scale,
                                      "t": [], "jpeg": []})
        cam["t"].append(round(t_ns * 1e-9, 6))
        cam["jpeg"].append(data)
    return out, total


def build_data(run_dir, points, frame_stamps):
    """The page's data; `frame_stamps`: {camera: set of kept frame stamps (s, 6 decimals)}, the
    detections the page keeps (it draws them on those frames only)."""
    metrics_path = os.path.join(run_dir, "metrics.json")
    files.read_metrics(metrics_path)  # every check
    metrics = files.load_json(metrics_path)
    world = files.read_world(os.path.join(run_dir, "world.json"))
    truth = files.read_tum(os.path.join(run_dir, "ground_truth.tum"))
    truth_keys = tum_stamp_keys(os.path.join(run_dir, "ground_truth.tum"))
    truth_index = {k: i for i, k in enumerate(truth_keys)}
    truth_yaw = [yaw_of(r[6], r[7]) for r in truth]
    keep = stride_indices(len(truth), points)
    events, failures = event_rows(os.path.join(run_dir, "events.json"))
    costs = read_costs(run_dir)
    data = {
        "schema": SCHEMA,
        "scenario": "", "seed": None,
        "duration_s": round(float(truth[-1][0]), S),
        "world": world_json(world),
        "truth": {"t": rounded(pick(truth[:, 0], keep), S),
                  "x": rounded(pick(truth[:, 1], keep), M),
                  "y": rounded(pick(truth[:, 2], keep), M),
                  "yaw": rounded(pick(truth_yaw, keep), RAD)},
        "pipelines": [],
        "events": events,
        "expectations": expectation_rows(metrics),
    }
    scenario_path = os.path.join(run_dir, "scenario.yaml")
    if os.path.exists(scenario_path):
        with open(scenario_path, encoding="utf-8", errors="replace") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key == "name":
                    data["scenario"] = value.strip().strip("'\"")[:MAX_TEXT]
                elif key == "seed":
                    try:
                        data["seed"] = int(value.strip())
                    except ValueError:
                        pass
    data["title"] = f"{data['scenario'] or os.path.basename(os.path.abspath(run_dir))}" + (
        f" seed {data['seed']}" if data["seed"] is not None else "")

    for name, section in metrics.get("pipelines", {}).items():
        failed = None
        if isinstance(section, dict) and section.get("health", {}).get("failed"):
            failed = failures.get(name, "failed (events.json says no more)")
        entry = {"name": name, "failed": failed, "metrics": section, "path": None,
                 "truth_at": None, "errors": None, "nees_band": significant(chi2_band(NEES_DOF)),
                 "nis": {}, "frame_ms": None, "cost": costs.get(name), "landmarks": [],
                 "detections": []}
        data["pipelines"].append(entry)
        tum_path = os.path.join(run_dir, f"{name}.tum")
        if failed is not None or not os.path.exists(tum_path):
            continue
        path = files.read_tum(tum_path)
        keys = tum_stamp_keys(tum_path)
        cxx, cxy, cyy = read_covariances(os.path.join(run_dir, f"{name}_cov.txt"), len(path))
        keep = stride_indices(len(path), points)
        yaw = [yaw_of(r[6], r[7]) for r in path]
        entry["path"] = {"t": rounded(pick(path[:, 0], keep), S),
                         "x": rounded(pick(path[:, 1], keep), M),
                         "y": rounded(pick(path[:, 2], keep), M),
                         "yaw": rounded(pick(yaw, keep), RAD),
                         "cxx": significant(pick(cxx, keep), COV_DIGITS),
                         "cxy": significant(pick(cxy, keep), COV_DIGITS),
                         "cyy": significant(pick(cyy, keep), COV_DIGITS)}
        at = [truth_index.get(keys[i]) for i in keep]
        entry["truth_at"] = {
            "x": [round(float(truth[i][1]), M) if i is not None else None for i in at],
            "y": [round(float(truth[i][2]), M) if i is not None else None for i in at],
            "yaw": [round(truth_yaw[i], RAD) if i is not None else None for i in at]}
        errors = files.read_errors(os.path.join(run_dir, f"{name}_errors.csv"))
        columns = [c for c in ("ex_m", "ey_m", "eyaw_rad", "nees") if c in errors]
        ekeep = extrema_indices(errors["t"], [errors[c] for c in columns], points)
        names = {"ex_m": "ex", "ey_m": "ey", "eyaw_rad": "eyaw", "sigma_x_m": "sx",
                 "sigma_y_m": "sy", "sigma_yaw_rad": "syaw", "nees": "nees"}
        entry["errors"] = {"t": rounded(pick(errors["t"], ekeep), S)}
        for column, short in names.items():
            if column in errors:
                values = pick(errors[column], ekeep)
                entry["errors"][short] = (significant(values) if short == "nees"
                                          else rounded(values, RAD if "yaw" in column else M))
        nis_path = os.path.join(run_dir, f"{name}_nis.csv")
        if os.path.exists(nis_path):
            entry["nis"] = read_nis(nis_path, points)
        times_path = os.path.join(run_dir, "maps", f"{name}_frame_times.csv")
        if os.path.exists(times_path):
            times = files.read_frame_times(times_path)
            tkeep = extrema_indices(times["stamp_s"], [times["frame_ms"]], points)
            entry["frame_ms"] = {"t": rounded(pick(times["stamp_s"], tkeep), S),
                                 "ms": significant(pick(times["frame_ms"], tkeep)),
                                 "landmarks": [int(v) for v in pick(times["landmarks"], tkeep)]}
        detections_path = os.path.join(run_dir, f"{name}_detections.csv")
        detections = (read_detection_rows(detections_path)
                      if os.path.exists(detections_path) else [])
        entry["detections"] = [d for d in detections
                               if d["t"] in frame_stamps.get(d["camera"], ())]
        landmarks_path = os.path.join(run_dir, f"{name}_landmarks.json")
        if os.path.exists(landmarks_path):
            entry["landmarks"] = landmark_rows(files.read_landmarks(landmarks_path),
                                               detections, world)
    return data


def render(data_json, title):
    return fill_page("viewer.html", "viewer.js", data_json, title)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir")
    parser.add_argument("--out", help="the page (default RUN_DIR/viewer.html)")
    parser.add_argument("--budget-mb", type=float, default=DEFAULT_BUDGET_MB,
                        help="the page's size without frames, MB (default %(default)s)")
    args = parser.parse_args(argv)
    keep_path_bytes(sys.stdout)
    if not (0.1 <= args.budget_mb <= 1000.0):
        print("make_viewer.py: --budget-mb must be in [0.1, 1000]", file=sys.stderr)
        return 2
    out = args.out or os.path.join(args.run_dir, "viewer.html")
    made = {}

    def build():
        if not os.path.isdir(args.run_dir):
            raise files.InputError(args.run_dir, None, "is not a directory")
        frames, frames_bytes = read_frames(args.run_dir)
        frame_stamps = {camera: set(f["t"]) for camera, f in frames.items()}
        points = START_POINTS
        sensors = False  # sensors/, read once (on the truth's time span) and cut to each size
        while True:
            data = build_data(args.run_dir, points, frame_stamps)
            if sensors is False:
                truth_t = data["truth"]["t"]
                sensors = read_sensors(args.run_dir, (truth_t[0], truth_t[-1]), START_POINTS)
            if sensors is not None:  # a run without IMUs and scanners: the page as before
                data["sensors"] = sensors_json(sensors, points)
            text = page_json(data)
            if len(text.encode("utf-8")) <= args.budget_mb * 1e6 or points <= MIN_POINTS:
                break
            points //= 2
        if frames:
            data["frames"] = frames
            text = page_json(data)
        else:
            data["frames"] = {}
            text = text[:-1] + ',"frames":{}}'
        made.update(points=points, frames_bytes=frames_bytes if frames else None)
        made["page"] = render(text, data["title"])
        return made["page"]

    code = make_page("make_viewer.py", args.run_dir, out, build,
                     (OSError, RuntimeError, ValueError, KeyError, IndexError, TypeError))
    if code == 0:
        print(f"wrote {out} ({len(made['page'].encode('utf-8')) / 1e6:.2f} MB, "
              f"{made['points']} points per series"
              + (f", frames {made['frames_bytes'] / 1e6:.1f} MB"
                 if made["frames_bytes"] is not None else "") + ")")
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
