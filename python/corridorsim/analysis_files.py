"""The readers corridorsim.analysis needs besides the plots': poses exactly as written (TUM and
ov_eval files with stamps in integer nanoseconds and numbers as the runner parsed them) and whole
JSON files (metrics.json in full, study and status files, events.json). corridorsim.files
re-exports every name."""

import json
import math
import re

from .readers import (InputError, JsonReader, data_lines, finite_float, is_integer, load_json,
                      no_json_constant, read_short_text, read_text)


# ------------------------------------------------------------------------------------------------
# Poses exactly as written (corridorsim.analysis scores these; harness/metrics/trajectory.h
# PoseAsWritten)

MAX_POSES = 2_000_000          # lines of one TUM or ov_eval file
MAX_JSON_BYTES = 64 << 20      # metrics.json, study.json, status files (docs/studies.md "Bounds")
MAX_EVENTS = 1_000_000

TUM_FIELDS = ["x", "y", "z", "qx", "qy", "qz", "qw"]
# <pipeline>_cov.txt (harness/run/run_io.cpp OvEvalLine): the TUM line, then the upper triangles
# of the rotation (roll, pitch, yaw) and position covariances as OpenVINS ov_eval reads them;
# corridorsim fills Pr33 (yaw, rad^2), Pt11, Pt12, Pt22 (x-y block, m^2) and writes 0 elsewhere.
OV_EVAL_COVARIANCE = ["Pr11", "Pr12", "Pr13", "Pr22", "Pr23", "Pr33",
                      "Pt11", "Pt12", "Pt13", "Pt22", "Pt23", "Pt33"]

_STAMP = re.compile(r"([0-9]{1,12})(?:\.([0-9]{1,9}))?")
_NUMBER = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]{1,3})?"
                     r"|[-+]?(?:nan|inf|infinity)", re.IGNORECASE)


def parse_stamp_ns(text):
    """Integer nanoseconds from seconds written with at most nine decimals ('12.300000000'), exact
    (never through a double); None when the text is not such a stamp."""
    m = _STAMP.fullmatch(text)
    if m is None:
        return None
    return int(m.group(1)) * 1_000_000_000 + int((m.group(2) or "").ljust(9, "0"))


def read_stamp_ns(path, number, text):
    """parse_stamp_ns of the stamp `text` on line `number` of `path`; InputError when it is not
    one."""
    stamp = parse_stamp_ns(text)
    if stamp is None:
        raise InputError(path, number, "t: expected seconds with at most nine decimals, got "
                         f"'{text[:40]}'")
    return stamp


def parse_number(text):
    """float(text) for a plain decimal number, nan or inf (no underscores, hex or spaces, which
    Python's float() would take); None otherwise. The value is the one C's strtod gives."""
    return float(text) if _NUMBER.fullmatch(text) else None


def _read_pose_lines(path, extra, what, allow_non_finite, increasing, allow_empty=False):
    """The lines of a TUM-like file: `t tx ty tz qx qy qz qw` plus the names in `extra`, as
    {t_ns: [int], t: [float], x, y, z, qx, qy, qz, qw, *extra: [float]}."""
    names = TUM_FIELDS + extra
    out = {"t_ns": [], "t": []}
    out.update({n: [] for n in names})
    fields_wanted = 1 + len(names)
    for number, fields in data_lines(path):
        if len(fields) != fields_wanted:
            raise InputError(path, number, f"expected {fields_wanted} fields '{what}', "
                             f"got {len(fields)}")
        if len(out["t_ns"]) == MAX_POSES:
            raise InputError(path, number, f"more than {MAX_POSES} poses")
        stamp = read_stamp_ns(path, number, fields[0])
        if increasing and out["t_ns"] and stamp <= out["t_ns"][-1]:
            raise InputError(path, number, f"t: {fields[0]} is not after the previous stamp")
        values = []
        for name, field in zip(names, fields[1:]):
            value = parse_number(field)
            if value is None:
                raise InputError(path, number, f"{name}: not a number: '{field[:40]}'")
            if not allow_non_finite and not math.isfinite(value):
                raise InputError(path, number, f"{name}: not finite: '{field[:40]}'")
            values.append(value)
        out["t_ns"].append(stamp)
        out["t"].append(float(fields[0]))
        for name, value in zip(names, values):
            out[name].append(value)
    if not out["t_ns"] and not allow_empty:
        raise InputError(path, None, "has no poses")
    return out


def read_tum_exact(path, allow_non_finite=False, increasing=False, allow_empty=False):
    """A TUM trajectory exactly as written: {t_ns: [int] (exact from the text), t: [float] (s),
    x, y, z, qx, qy, qz, qw: [float]} in file order. `allow_non_finite`: an estimate may be
    'nan' (the runner writes the pose a pipeline reported); `increasing`: stamps must increase
    (the truth); `allow_empty`: a pipeline that gave no estimate has a file of comments only."""
    return _read_pose_lines(path, [], "t tx ty tz qx qy qz qw", allow_non_finite, increasing,
                            allow_empty)


def read_covariance(path):
    """<pipeline>_cov.txt (OpenVINS ov_eval, 20 columns: harness/run/run_io.cpp OvEvalLine) as
    read_tum_exact's columns plus OV_EVAL_COVARIANCE's (rad^2, m^2; NaN where the pipeline
    reported a non-finite covariance)."""
    return _read_pose_lines(path, OV_EVAL_COVARIANCE, "t tx ty tz qx qy qz qw Pr11 ... Pt33",
                            allow_non_finite=True, increasing=False, allow_empty=True)


# ------------------------------------------------------------------------------------------------
# Whole JSON files

def load_json_fast(path, top="object", max_bytes=MAX_JSON_BYTES):
    """json.loads of a file of at most `max_bytes` (C parser: for large files; values do not know
    their lines, a syntax error names its line). NaN and Infinity literals, and numbers beyond a
    double (1e999), are refused."""
    text = read_text(path, max_bytes)
    try:
        root = json.loads(text, parse_constant=no_json_constant, parse_float=finite_float)
    except json.JSONDecodeError as e:
        raise InputError(path, e.lineno, f"column {e.colno}: invalid JSON: {e.msg}") from None
    except (ValueError, RecursionError) as e:
        raise InputError(path, None, f"invalid JSON: {e}") from None
    if not isinstance(root, dict if top == "object" else list):
        raise InputError(path, 1, f"the top level is not a JSON {top}")
    return root


PIPELINE_NAME = re.compile(r"[A-Za-z0-9_+-][A-Za-z0-9_.+-]{0,127}")


def read_metrics_full(path, fast=False):
    """The whole metrics.json (docs/metrics.md) as parsed, after checking its frame: an object
    whose `pipelines` (when present) is an object of objects keyed by plain file stems; the key
    order is the file's (the runner's pipeline order). `fast`: the C parser (errors then name the
    line of a syntax error only), for the many files of a study."""
    root = load_json_fast(path) if fast else load_json(path, max_bytes=MAX_JSON_BYTES)
    r = JsonReader(path)
    pipelines = r.get(root, "pipelines", "object", "")
    for name, entry in (pipelines or {}).items():
        if not PIPELINE_NAME.fullmatch(name):
            r.fail(pipelines, f"pipelines.{name}", "a pipeline name must be a plain file stem")
        if not isinstance(entry, dict):
            r.fail(pipelines, f"pipelines.{name}", "expected an object")
    for name, item in r.items(root, "expectations"):
        r.get(item, "text", "text", name)
        r.get(item, "passed", "bool", name)
    return root


def read_json_object(path, max_bytes=MAX_JSON_BYTES):
    """A JSON file whose top level is an object (timing.json, provenance.json, summary.json ...),
    as parsed."""
    return load_json_fast(path, "object", max_bytes)


def read_events(path):
    """events.json (harness/run/truth_recorder.cpp EventLog::Json) as {seed, duration_s, events:
    [{t (s), t_ns (int), type, ...the event's own keys}]} in stamp order."""
    root = load_json(path)
    r = JsonReader(path)
    seed = root.get("seed")
    if not (is_integer(seed) and seed >= 0):
        r.fail(root, "seed", f"expected a non-negative integer, got {json.dumps(seed)[:40]}")
    duration = r.get(root, "duration_s", "number", "")
    events = r.get(root, "events", "array", "")
    if events is None:
        r.fail(root, "events", "missing")
    if len(events) > MAX_EVENTS:
        r.fail(events, "events", f"more than {MAX_EVENTS} events")
    out = []
    for name, event in r.items(root, "events"):
        t_ns = event.get("t_ns")
        if not (is_integer(t_ns) and t_ns >= 0):
            r.fail(event, f"{name}.t_ns", f"expected a non-negative integer, got "
                   f"{json.dumps(t_ns)[:40]}")
        if out and t_ns < out[-1]["t_ns"]:
            r.fail(event, f"{name}.t_ns", f"{t_ns} is before the previous event's")
        if r.get(event, "t", "number", name) is None:
            r.fail(event, f"{name}.t", "missing")
        read_short_text(r, event, "type", name, required=True)
        out.append(dict(event))
    return {"seed": seed, "duration_s": None if duration is None else float(duration),
            "events": out}


def text_list(r, obj, key, where, pattern=None, limit=100_000):
    """A JSON array of strings (each matching `pattern` when given), at most `limit`."""
    value = r.get(obj, key, "array", where)
    if value is None:
        r.fail(obj, f"{where}{key}", "missing")
    if len(value) > limit or not all(isinstance(v, str) and len(v) <= 256 for v in value):
        r.fail(obj, f"{where}{key}", f"expected at most {limit} names")
    if pattern is not None:
        for v in value:
            if not pattern.fullmatch(v):
                r.fail(obj, f"{where}{key}", f"'{v[:40]}' is not a plain name")
    return list(value)
