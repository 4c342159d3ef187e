"""Strict readers of a study folder (docs/studies.md "The study folder"): the plan, each run's
status, summary.csv and paired.csv. corridorsim.files has the run folder's; errors are
files.InputError with the path and line."""

import json
import re

from .files import (MAX_CSV_ROWS, PIPELINE_NAME, CsvCells, InputError, JsonReader, is_integer,
                    load_json, read_csv_records, text_list)

# ------------------------------------------------------------------------------------------------
# Studies (docs/studies.md "The study folder")

MAX_POINTS = 1000              # sweep points of a study
MAX_RUNS_PER_POINT = 10_000
POINT_ID = re.compile(r"p[0-9]{3,6}")
STUDY_OUTCOMES = ["finished", "failed", "timed_out"]




def read_study_plan(path):
    """study.json (harness/study/study_plan.cpp PlanJson) as {runs_per_point, first_seed, pipelines,
    metrics, vary: [key], points: [{id, vary: {key: value text}}], expectations, may_diverge};
    the full object under `raw`."""
    root = load_json(path)
    r = JsonReader(path)
    runs = root.get("runs_per_point")
    if not (is_integer(runs) and 1 <= runs <= MAX_RUNS_PER_POINT):
        r.fail(root, "runs_per_point", f"expected an integer in [1, {MAX_RUNS_PER_POINT}]")
    first_seed = root.get("first_seed")
    if not (is_integer(first_seed) and 0 <= first_seed and first_seed + runs - 1 < 2**64):
        r.fail(root, "first_seed", "expected a seed in [0, 2^64 - runs_per_point]")
    pipelines = text_list(r, root, "pipelines", "", PIPELINE_NAME, 1000)
    if not pipelines:
        r.fail(root, "pipelines", "no pipelines")
    vary = text_list(r, root, "vary", "")
    points = []
    for name, point in r.items(root, "points"):
        if len(points) == MAX_POINTS:
            r.fail(point, name, f"more than {MAX_POINTS} points")
        pid = r.get(point, "id", "text", name)
        if not (isinstance(pid, str) and POINT_ID.fullmatch(pid)):
            r.fail(point, f"{name}.id", f"expected p000, p001, ..., got {json.dumps(pid)[:40]}")
        if any(p["id"] == pid for p in points):
            r.fail(point, f"{name}.id", f"{pid} twice")
        values = r.get(point, "vary", "object", name) or {}
        if set(values) != set(vary) or not all(isinstance(v, str) for v in values.values()):
            r.fail(point, f"{name}.vary", f"expected a text value for each of {vary}")
        points.append({"id": pid, "vary": dict(values)})
    if not points:
        r.fail(root, "points", "no points")
    return {"runs_per_point": runs, "first_seed": first_seed, "pipelines": pipelines,
            "metrics": text_list(r, root, "metrics", ""), "vary": vary, "points": points,
            "expectations": text_list(r, root, "expectations", ""),
            "may_diverge": text_list(r, root, "may_diverge", ""), "raw": root}


def read_run_status(path):
    """status/<point>/seed_<S>.json (harness/study/study_run.cpp RecordRun) as {point, seed, outcome
    (finished, failed or timed_out), detail, exit_code, signal, wall_seconds, peak_rss_mib}."""
    root = load_json(path)
    r = JsonReader(path)
    outcome = r.get(root, "outcome", "text", "")
    if outcome not in STUDY_OUTCOMES:
        r.fail(root, "outcome", f"expected one of {STUDY_OUTCOMES}, got "
               f"{json.dumps(outcome)[:40]}")
    seed = root.get("seed")
    if not (is_integer(seed) and seed >= 0):
        r.fail(root, "seed", "expected a non-negative integer")
    out = {"point": r.get(root, "point", "text", ""), "seed": seed, "outcome": outcome,
           "detail": str(r.get(root, "detail", "text", "") or "")[:4096]}
    for key in ["exit_code", "signal"]:
        value = root.get(key)
        if value is not None and not is_integer(value):
            r.fail(root, key, "expected an integer")
        out[key] = value
    for key in ["wall_seconds", "peak_rss_mib"]:
        value = r.get(root, key, "number", "")
        out[key] = None if value is None else float(value)
    return out


def read_csv_rows(path, max_rows=MAX_CSV_ROWS):
    """(header, [(line, [cell])]) of a CSV file: every row as long as the header, cells stripped;
    blank rows skipped; quoted cells may hold commas."""
    def check_header(header):
        if len(set(header)) != len(header):
            raise InputError(path, 1, "a column name appears twice")

    header, records = read_csv_records(path, max_rows, check_header)
    return header, [(line, [cell.strip() for cell in row]) for line, row in records]


SUMMARY_CSV_COLUMNS = ["pipeline", "metric", "n", "mean", "std", "median", "p95", "min", "max",
                       "ci_low", "ci_high"]
PAIRED_CSV_COLUMNS = ["a", "b", "metric", "n", "diff", "diff_ci_low", "diff_ci_high", "ratio",
                      "ratio_ci_low", "ratio_ci_high", "a_lower", "p_sign", "p_wilcoxon"]
_STUDY_TEXT_COLUMNS = {"pipeline", "metric", "a", "b"}


def read_study_table(path, columns):
    """summary.csv (columns = SUMMARY_CSV_COLUMNS) or paired.csv (PAIRED_CSV_COLUMNS) of
    harness/study/study_summary.cpp: `point,<swept keys...>,<columns>`. Returns (keys, {column:
    list}): point, the keys' values and the names as text, n as int, the statistics as float
    (NaN for an empty cell: no value)."""
    header, rows = read_csv_rows(path)
    if header[0] != "point" or header[len(header) - len(columns):] != columns:
        raise InputError(path, 1, f"expected the header 'point,<swept keys...>,"
                         f"{','.join(columns)}'")
    keys = header[1:len(header) - len(columns)]
    out = {c: [] for c in header}
    for line, cells in rows:
        c = CsvCells(path, line, dict(zip(header, cells)))
        if not POINT_ID.fullmatch(cells[0]):
            c.fail("point", f"expected p000, p001, ..., got '{cells[0][:40]}'")
        for column, cell in zip(header, cells):
            if column == "point" or column in keys:
                out[column].append(cell)
            elif column in _STUDY_TEXT_COLUMNS:
                if not cell or len(cell) > 256:
                    c.fail(column, "expected a name of 1 to 256 characters")
                out[column].append(cell)
            elif column == "n":
                out[column].append(c.integer("n", 0, 10**9))
            else:
                out[column].append(c.number(column, required=False))
    return keys, out
