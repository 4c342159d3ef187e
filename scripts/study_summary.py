"""plot_study.py's input: a study's summary.json (harness/study/study_summary.cpp, schema_version
1) read and checked before anything is drawn (plot_study.py's docstring says what it holds), and
frame_times.csv. A missing or malformed file raises InputError naming the file and the key."""

import json
import math
import os

import numpy as np

SCHEMA_VERSION = 1
ATE = "ate_rmse_m"
NEES_DOF = 3  # x, y, yaw (the producer's kPoseDof; summary.json's nees.dof overrides it)
AXES = [("x_m", "x error [m]"), ("y_m", "y error [m]"), ("yaw_rad", "yaw error [rad]")]
SERIES_KEYS = ["t", "runs_with_nees", "anees", "band_low", "band_high", "position_error_rms_m",
               "position_sigma_rms_m", "error_x_mean_m", "error_y_mean_m", "runs_with_error"] + \
    [f"{kind}_rms_{axis}" for axis, _ in AXES for kind in ("error", "sigma")]

# Bounds on what summary.json may hold (the producer's are far below: harness/study/study_file.h).
MAX_SUMMARY_BYTES = 1 << 30
MAX_POINTS = 10_000
MAX_PIPELINES = 64
MAX_SEEDS = 100_000
MAX_SERIES = 1_000_000
MAX_TEXT_CHARS = 200
MAX_ABS_VALUE = 1e100   # larger magnitudes (a diverged filter's) are skipped like nulls: beyond
                        # it matplotlib's axis arithmetic overflows


class InputError(Exception):
    """A missing or malformed input: the file and what is wrong."""

    def __init__(self, path, message):
        super().__init__(message)
        self.path, self.message = path, message

    def __str__(self):
        return f"{self.path}: {self.message}"


# ------------------------------------------------------------------------------------------------
# Reading summary.json

def load_json(path):
    if not os.path.isfile(path):
        raise InputError(path, "missing")
    try:
        if os.path.getsize(path) > MAX_SUMMARY_BYTES:
            raise InputError(path, f"larger than {MAX_SUMMARY_BYTES >> 20} MiB")
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(path, f"cannot be read: {e}") from None
    try:
        # NaN and Infinity are not JSON; the producer writes null for them, and so do we.
        root = json.loads(text, parse_constant=lambda _: None)
    except json.JSONDecodeError as e:
        raise InputError(path, f"line {e.lineno} column {e.colno}: invalid JSON: {e.msg}") \
            from None
    except RecursionError:
        raise InputError(path, "invalid JSON: nested too deeply") from None
    except ValueError as e:  # e.g. an integer of more digits than Python converts
        raise InputError(path, f"invalid JSON: {str(e)[:80]}") from None
    if not isinstance(root, dict):
        raise InputError(path, "the top level is not a JSON object")
    return root


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def shown(value):
    try:
        return json.dumps(value)[:40]
    except (TypeError, ValueError):
        return type(value).__name__


class Checker:
    """Typed access to summary.json's keys; errors name the file and the key's path."""

    def __init__(self, path):
        self.path = path

    def fail(self, where, message):
        raise InputError(self.path, f"{where}: {message}" if where else message)

    def get(self, obj, key, kind, where, required=False):
        """obj[key] if it is of `kind` ('object', 'array', 'number', 'integer', 'text'); None when
        absent or null (an error when `required`)."""
        name = f"{where}.{key}" if where else key
        value = obj.get(key)
        if value is None:
            if required:
                self.fail(name, "missing")
            return None
        ok = {
            "object": isinstance(value, dict),
            "array": isinstance(value, list),
            "number": is_number(value),
            "integer": isinstance(value, int) and not isinstance(value, bool),
            "text": isinstance(value, str) or is_number(value),
        }[kind]
        if not ok:
            self.fail(name, f"expected {'an' if kind[0] in 'aeio' else 'a'} {kind}, "
                      f"got {shown(value)}")
        return value

    def text(self, obj, key, where, required=False):
        value = self.get(obj, key, "text", where, required)
        if value is None:
            return None
        value = str(value)
        if len(value) > MAX_TEXT_CHARS:
            self.fail(f"{where}.{key}", f"longer than {MAX_TEXT_CHARS} characters")
        return value

    def numbers(self, obj, key, where, length=None, limit=MAX_SERIES, of="times"):
        """obj[key] as a float array (NaN for null, non-finite or beyond MAX_ABS_VALUE); None when
        absent. `length`:
        the array must have that many entries (as many as the `of`)."""
        name = f"{where}.{key}"
        values = self.get(obj, key, "array", where)
        if values is None:
            return None
        if len(values) > limit:
            self.fail(name, f"more than {limit} entries")
        if length is not None and len(values) != length:
            self.fail(name, f"has {len(values)} entries, expected {length} (as many as the "
                      f"{of})")
        if all(type(v) in (float, int) or v is None for v in values):  # the common case, fast
            try:
                out = np.array(values, dtype=float)  # None becomes NaN
                out[~(np.abs(out) <= MAX_ABS_VALUE)] = math.nan
                return out
            except OverflowError:
                pass  # an integer beyond a double: the loop below
        out = np.full(len(values), math.nan)
        for i, v in enumerate(values):
            if v is None:
                continue
            if not is_number(v):
                self.fail(f"{name}[{i}]", f"expected a number or null, got {shown(v)}")
            try:
                out[i] = float(v)
            except OverflowError:
                pass  # an integer beyond a double: not finite, skipped as null
        out[~(np.abs(out) <= MAX_ABS_VALUE)] = math.nan
        return out


def finite(value):
    """value as a float when it is a number within MAX_ABS_VALUE, else None."""
    if value is None:
        return None
    try:
        v = float(value)
    except OverflowError:
        return None
    return v if abs(v) <= MAX_ABS_VALUE else None


def read_pipeline(c, entry, where):
    """One pipeline at one point."""
    if not isinstance(entry, dict):
        c.fail(where, "expected an object")
    p = {"finished": None, "diverged": set(), "seeds": np.zeros(0), "ate": np.zeros(0),
         "ate_mean": None, "ate_ci": None, "nees_average": None, "nees_in_band": None,
         "nees_dof": NEES_DOF, "series": None}
    runs = c.get(entry, "runs", "object", where)
    if runs is not None:
        p["finished"] = c.get(runs, "finished", "integer", f"{where}.runs")
        diverged = c.numbers(runs, "diverged_seeds", f"{where}.runs", limit=MAX_SEEDS)
        if diverged is not None:
            p["diverged"] = {float(s) for s in diverged if np.isfinite(s)}
    values = c.get(entry, "values", "object", where)
    if values is not None:
        seeds = c.numbers(values, "seed", f"{where}.values", limit=MAX_SEEDS)
        if seeds is None:
            seeds = np.zeros(0) if values.get(ATE) is None else None
        ate = c.numbers(values, ATE, f"{where}.values",
                        length=None if seeds is None else len(seeds), limit=MAX_SEEDS,
                        of="seeds")
        if seeds is None:  # ate_rmse_m without its seeds
            c.fail(f"{where}.values.seed", "missing (ate_rmse_m is there)")
        p["seeds"], p["ate"] = seeds, np.zeros(0) if ate is None else ate
    metrics = c.get(entry, "metrics", "object", where)
    if metrics is not None:
        ate = c.get(metrics, ATE, "object", f"{where}.metrics")
        if ate is not None:
            w = f"{where}.metrics.{ATE}"
            p["ate_mean"] = finite(c.get(ate, "mean", "number", w))
            lo = finite(c.get(ate, "ci_low", "number", w))
            hi = finite(c.get(ate, "ci_high", "number", w))
            if lo is not None and hi is not None:
                if lo > hi:
                    c.fail(w, f"ci_low {lo:.9g} is above ci_high {hi:.9g}")
                p["ate_ci"] = (lo, hi)
    if p["ate_mean"] is None and np.isfinite(p["ate"]).any():
        p["ate_mean"] = float(np.nanmean(p["ate"]))
    nees = c.get(entry, "nees", "object", where)
    if nees is not None:
        for key, out in [("average", "nees_average"), ("in_band_fraction", "nees_in_band")]:
            p[out] = finite(c.get(nees, key, "number", f"{where}.nees"))
        dof = c.get(nees, "dof", "integer", f"{where}.nees")
        if dof is not None:
            if not 1 <= dof <= 1000:
                c.fail(f"{where}.nees.dof", f"expected 1 to 1000, got {dof}")
            p["nees_dof"] = dof
    p["nis"] = {}
    nis = c.get(entry, "nis", "object", where) or {}
    if len(nis) > MAX_PIPELINES:
        c.fail(f"{where}.nis", f"more than {MAX_PIPELINES} landmark types")
    for kind, entry_of_type in nis.items():
        w = f"{where}.nis.{kind}"
        if not isinstance(entry_of_type, dict):
            c.fail(w, "expected an object")
        ns = c.get(entry_of_type, "series", "object", w)
        if ns is None:
            continue
        t = c.numbers(ns, "t", f"{w}.series")
        if t is None:
            continue
        p["nis"][str(kind)[:MAX_TEXT_CHARS]] = {"t": t, **{
            key: c.numbers(ns, key, f"{w}.series", length=len(t), of="times")
            for key in ("anis", "band_low", "band_high")}}
    series = c.get(entry, "series", "object", where)
    if series is not None:
        w = f"{where}.series"
        t = c.numbers(series, "t", w)
        if t is None:
            t = np.zeros(0)
            if any(series.get(k) for k in SERIES_KEYS[1:]):
                c.fail(f"{w}.t", "missing (the other series are there)")
        s = {"t": t}
        for key in SERIES_KEYS[1:]:
            values = c.numbers(series, key, w, length=len(t))
            s[key] = np.full(len(t), math.nan) if values is None else values
        p["series"] = s
    return p


def read_summary(study_dir):
    """Reads and checks summary.json; raises InputError on the first problem."""
    if not os.path.isdir(study_dir):
        raise InputError(study_dir, "is not a directory")
    path = os.path.join(study_dir, "summary.json")
    root = load_json(path)
    c = Checker(path)
    version = c.get(root, "schema_version", "integer", "")
    if version is not None and version != SCHEMA_VERSION:
        c.fail("schema_version", f"{version} is not supported (this script reads "
               f"{SCHEMA_VERSION})")
    vary = c.get(root, "vary", "array", "") or []
    for i, key in enumerate(vary):
        if not isinstance(key, str) or not key or len(key) > MAX_TEXT_CHARS:
            c.fail(f"vary[{i}]", f"expected a key name, got {shown(key)}")
    if len(set(vary)) != len(vary):
        c.fail("vary", "names a key twice")
    names = c.get(root, "pipelines", "array", "")
    if names is not None:
        for i, name in enumerate(names):
            if not isinstance(name, str) or len(name) > MAX_TEXT_CHARS:
                c.fail(f"pipelines[{i}]", f"expected a pipeline name, got {shown(name)}")
        names = list(dict.fromkeys(names))
    raw_points = c.get(root, "points", "array", "", required=True)
    if not raw_points:
        c.fail("points", "empty")
    if len(raw_points) > MAX_POINTS:
        c.fail("points", f"more than {MAX_POINTS} points")
    points, seen_names = [], []
    for i, item in enumerate(raw_points):
        where = f"points[{i}]"
        if not isinstance(item, dict):
            c.fail(where, "expected an object")
        pid = c.text(item, "id", where, required=True)
        values = c.get(item, "vary", "object", where) or {}
        point_vary = {}
        for key in vary:
            value = values.get(key)
            if value is None or isinstance(value, (dict, list, bool)):
                c.fail(f"{where}.vary", f"no value (YAML text) for the swept key '{key}'"
                       if value is None else f"{key}: expected YAML text, got {shown(value)}")
            point_vary[key] = str(value)[:MAX_TEXT_CHARS]
        entries = c.get(item, "pipelines", "object", where, required=True)
        pipelines = {}
        for name, entry in entries.items():
            if len(name) > MAX_TEXT_CHARS:
                c.fail(f"{where}.pipelines", f"a pipeline name is longer than {MAX_TEXT_CHARS} "
                       "characters")
            pipelines[name] = read_pipeline(c, entry, f"{where}.pipelines.{name}")
            if name not in seen_names:
                seen_names.append(name)
        points.append({"id": pid, "vary": point_vary, "pipelines": pipelines})
    names = (names or []) + [n for n in seen_names if n not in (names or [])]
    if not names:
        c.fail("pipelines", "no pipeline, at the top level or at any point")
    if len(names) > MAX_PIPELINES:
        c.fail("pipelines", f"more than {MAX_PIPELINES} pipelines")
    return {"vary": vary, "pipelines": names, "points": points}


def read_frame_times(study_dir):
    """STUDY_DIR/frame_times.csv (harness/study/study_finish.cpp, WriteFrameTimes: point, pipeline,
    landmarks_low, landmarks_high, frames, mean_ms, median_ms, p95_ms), or None when the study
    has none (no pipeline of its runs records frame costs). Raises InputError when malformed."""
    path = os.path.join(study_dir, "frame_times.csv")
    if not os.path.isfile(path):
        return None
    header = "point,pipeline,landmarks_low,landmarks_high,frames,mean_ms,median_ms,p95_ms"
    rows = []
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read(64 << 20).splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(path, f"cannot read: {e}")
    if not lines or lines[0] != header:
        raise InputError(path, f"line 1: expected the header '{header}'")
    for number, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        try:
            if len(cells) != 8:
                raise ValueError("8 fields expected")
            low, high, frames = int(cells[2]), int(cells[3]), int(cells[4])
            mean, median, p95 = (float(c) for c in cells[5:8])
            if not all(math.isfinite(v) and 0 <= v <= MAX_ABS_VALUE for v in (mean, median, p95)):
                raise ValueError("a time out of range")
        except ValueError as e:
            raise InputError(path, f"line {number}: {e}")
        rows.append({"point": cells[0], "pipeline": cells[1], "low": low, "high": high,
                     "frames": frames, "mean": mean, "median": median, "p95": p95})
    return rows
