"""Strict readers of a detector dataset (`corridorsim dataset`, docs/datasets.md) and of a run's
`--export` (docs/export.md): the manifest, COCO labels and the frame lists. Errors are
files.InputError with the path and line."""

import json
import re

from .files import (MAX_FILE_BYTES, MAX_POSES, MAX_TEXT_CHARS, InputError, JsonReader,
                    data_lines, finite_numbers, is_integer, load_json, load_json_fast,
                    read_stamp_ns, read_text, text_list)

MAX_COCO_ITEMS = 10_000_000    # images or annotations of one COCO file
MAX_FILE_NAME_CHARS = 255
SENSOR_NAME = re.compile(r"[a-z][a-z0-9_]{0,31}")  # a scenario's sensor names (docs/sensors.md)
MAX_EXPORT_CAMERAS = 64  # cam<N> folders of an export (a scenario has at most 16 cameras)

# ------------------------------------------------------------------------------------------------
# Datasets (docs/datasets.md, docs/export.md)


def check_relative_file(path, line, name, where):
    """A file name inside the dataset: relative, no '..', at most MAX_FILE_NAME_CHARS."""
    if (not isinstance(name, str) or not name or len(name) > MAX_FILE_NAME_CHARS or
            name.startswith("/") or "\\" in name or ".." in name.split("/")):
        raise InputError(path, line, f"{where}: expected a relative file name inside the folder, "
                         f"got {json.dumps(name)[:60]}")
    return name


def read_dataset_manifest(path):
    """dataset.json of `corridorsim dataset` (docs/datasets.md) as parsed, after checking format,
    format_version, cameras, worlds and frames_per_world."""
    root = load_json(path)
    r = JsonReader(path)
    if root.get("format") != "corridorsim dataset":
        r.fail(root, "format", f"expected 'corridorsim dataset', got "
               f"{json.dumps(root.get('format'))[:40]}")
    if root.get("format_version") != 1:
        r.fail(root, "format_version", "expected 1")
    # A camera's name as a scenario's sensors: may give it (docs/sensors.md).
    cameras = text_list(r, root, "cameras", "", SENSOR_NAME, 16)
    if not cameras:
        r.fail(root, "cameras", "no cameras")
    for key, hi in [("worlds", 100_000), ("frames_per_world", 100_000)]:
        value = root.get(key)
        if not (is_integer(value) and 1 <= value <= hi):
            r.fail(root, key, f"expected an integer in [1, {hi}]")
    return root


def read_coco(path):
    """A COCO detection file (a dataset's <camera>/annotations.json, an export's coco/plates.json)
    as parsed, after checking images [{id, file_name, width, height}], categories [{id, name}] and
    annotations [{id, image_id, category_id, bbox [x, y, w, h]}] (ids unique, references
    resolved, boxes finite with w, h >= 0)."""
    root = load_json_fast(path, "object", MAX_FILE_BYTES)

    def fail(where, message):
        raise InputError(path, None, f"{where}: {message}")

    lists = {}
    for key in ["images", "annotations", "categories"]:
        value = root.get(key)
        if not isinstance(value, list):
            fail(key, "expected an array")
        if len(value) > MAX_COCO_ITEMS:
            fail(key, f"more than {MAX_COCO_ITEMS} entries")
        if not all(isinstance(v, dict) for v in value):
            fail(key, "expected objects")
        lists[key] = value

    def ids(key):
        seen = set()
        for i, item in enumerate(lists[key]):
            v = item.get("id")
            if not is_integer(v) or v in seen:
                fail(f"{key}[{i}].id",
                     f"expected an integer id used once, got {json.dumps(v)[:40]}")
            seen.add(v)
        return seen

    image_ids, category_ids = ids("images"), ids("categories")
    ids("annotations")
    for i, image in enumerate(lists["images"]):
        check_relative_file(path, None, image.get("file_name"), f"images[{i}].file_name")
        for key in ["width", "height"]:
            if not (is_integer(image.get(key)) and 0 < image[key] <= 100_000):
                fail(f"images[{i}].{key}", "expected a positive integer")
    for i, category in enumerate(lists["categories"]):
        if not isinstance(category.get("name"), str) or len(category["name"]) > MAX_TEXT_CHARS:
            fail(f"categories[{i}].name", "expected a name")
    for i, a in enumerate(lists["annotations"]):
        if a.get("image_id") not in image_ids:
            fail(f"annotations[{i}].image_id", f"no image {json.dumps(a.get('image_id'))[:40]}")
        if a.get("category_id") not in category_ids:
            fail(f"annotations[{i}].category_id",
                 f"no category {json.dumps(a.get('category_id'))[:40]}")
        box = a.get("bbox")
        if not (finite_numbers(box, 4) and box[2] >= 0 and box[3] >= 0):
            fail(f"annotations[{i}].bbox", f"expected [x, y, w, h] with w, h >= 0, got "
                 f"{json.dumps(box)[:60]}")
    return root


def _add_frame(out, path, number, stamp_key, stamp, file_name):
    """Appends (stamp, file name) to a frame list read from `path`, line `number`: stamps strictly
    increasing, at most MAX_POSES frames, the name a relative file."""
    if out and stamp <= out[-1][0]:
        raise InputError(path, number, f"{stamp_key}: not after the previous frame's")
    if len(out) == MAX_POSES:
        raise InputError(path, number, f"more than {MAX_POSES} frames")
    out.append((stamp, check_relative_file(path, number, file_name, "filename")))


def read_tum_file_list(path):
    """An export's tum_rgbd/rgb.txt or depth.txt: '#' comments, then `t filename` per frame, as
    [(t_ns, file name)] (t exact from its nine decimals)."""
    out = []
    for number, fields in data_lines(path):
        if len(fields) != 2:
            raise InputError(path, number, f"expected 't filename', got {len(fields)} fields")
        stamp = read_stamp_ns(path, number, fields[0])
        _add_frame(out, path, number, "t", stamp, fields[1])
    return out


def read_euroc_file_list(path):
    """An export's euroc/mav0/camN/data.csv: `#timestamp [ns],filename`, then `<t_ns>,<file>` per
    frame, as [(t_ns, file name)]."""
    out = []
    lines = read_text(path).splitlines()
    if not lines or not lines[0].startswith("#timestamp"):
        raise InputError(path, 1, "expected the header '#timestamp [ns],filename'")
    for number, line in enumerate(lines[1:], start=2):
        line = line.strip()
        if not line:
            continue
        fields = [f.strip() for f in line.split(",")]
        if len(fields) != 2 or not re.fullmatch(r"[0-9]{1,19}", fields[0]):
            raise InputError(path, number, "expected '<t_ns>,<file name>'")
        stamp = int(fields[0])
        _add_frame(out, path, number, "timestamp", stamp, fields[1])
    return out


def read_euroc_camera_list(path):
    """An export's euroc/mav0/cameras.yaml: '#' comments, then `cam<N>: <camera name>` per
    exported camera (docs/export.md), as [(N, name)] in the file's order; numbers and names
    unique."""
    out = []
    for number, line in enumerate(read_text(path).splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        m = re.fullmatch(r"cam([0-9]{1,2}):\s*(\S+)", line)
        if m is None or SENSOR_NAME.fullmatch(m.group(2)) is None:
            raise InputError(path, number, "expected 'cam<N>: <camera name>'")
        cam, name = int(m.group(1)), m.group(2)
        if any(cam == c or name == n for c, n in out):
            raise InputError(path, number, f"cam{cam} or '{name}' is named twice")
        if len(out) == MAX_EXPORT_CAMERAS:
            raise InputError(path, number, f"more than {MAX_EXPORT_CAMERAS} cameras")
        out.append((cam, name))
    return out
