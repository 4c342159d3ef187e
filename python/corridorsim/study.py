"""corridorsim.Study: a study folder of `corridorsim study` as pandas DataFrames (docs/analysis.md):
the plan, the runs with their metrics, the status files, summary.csv and paired.csv, each run as
a corridorsim.Run. corridorsim.analysis re-exports it."""

import math
import os

import numpy as np
import pandas as pd

from . import files, study_files
from .run import Run


def _flatten(obj, prefix=""):
    """{dotted key: value} of the numbers (int, float), booleans and nulls (NaN) of a JSON object,
    nested objects joined with '.'; arrays and text are left out."""
    out = {}
    for key, value in obj.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(_flatten(value, name + "."))
        elif value is None:
            out[name] = math.nan
        elif isinstance(value, (bool, int, float)):
            out[name] = value
    return out



# Study

def _typed(values):
    """A swept key's values (text in study.json) as numbers when every one is a plain number."""
    numbers = [files.parse_number(v) for v in values]
    if values and all(n is not None for n in numbers):
        return numbers
    return list(values)


class Study(files.FolderReader):
    """A study folder of `corridorsim study` (docs/studies.md "The study folder").

    Attributes:
      path        the folder
      plan        study.json (study_files.read_study_plan: runs_per_point, first_seed, pipelines,
                  metrics, vary, points, expectations, may_diverge; `raw`: the whole file)
      vary        the swept keys, in the plan's order
      pipelines   the pipelines, in scenario order
      seeds       the seeds of every point: first_seed, first_seed + 1, ...
      points      DataFrame point, then one column per swept key (numbers when every value of
                  the key is one, else text)
      runs        WIDE DataFrame, one row per point, seed and pipeline: point, seed, the swept
                  keys, pipeline, status ('finished': the run folder has metrics.json; else the
                  status file's 'failed' or 'timed_out'; 'not_run': neither, e.g. another
                  shard's), then one column per metric of metrics.json's pipeline object (dotted
                  paths: 'ate_rmse_m', 'nis.lamp.mean', 'health.failed'; NaN where absent or null)
      status      DataFrame of the status files: point, seed, outcome, detail, exit_code,
                  signal, wall_seconds, peak_rss_mib
      summary     summary.csv as a DataFrame (point, swept keys, pipeline, metric, n, mean, std,
                  median, p95, min, max, ci_low, ci_high; NaN: no value)
      paired      paired.csv as a DataFrame (point, swept keys, a, b, metric, n, diff, ...)
      summary_json  summary.json as parsed
    """

    def __init__(self, path):
        super().__init__(path)
        self.plan  # noqa: B018 (read now: a folder without study.json is no study)

    @property
    def plan(self):
        return self._cached("plan", lambda: study_files.read_study_plan(
            os.path.join(self.path, "study.json")))

    @property
    def vary(self):
        return list(self.plan["vary"])

    @property
    def pipelines(self):
        return list(self.plan["pipelines"])

    @property
    def seeds(self):
        first = self.plan["first_seed"]
        return [first + i for i in range(self.plan["runs_per_point"])]

    @property
    def points(self):
        def make():
            points = self.plan["points"]
            frame = pd.DataFrame({"point": [p["id"] for p in points]})
            for key in self.vary:
                frame[key] = _typed([p["vary"][key] for p in points])
            return frame
        return self._cached("points", make)

    def _point_id(self, point):
        ids = [p["id"] for p in self.plan["points"]]
        if isinstance(point, (int, np.integer)) and not isinstance(point, bool):
            if not 0 <= point < len(ids):
                raise KeyError(f"{self.path}: no point {point} (the study has {len(ids)})")
            return ids[point]
        if point not in ids:
            raise KeyError(f"{self.path}: no point {point!r} (points: {', '.join(ids[:10])}"
                           f"{', ...' if len(ids) > 10 else ''})")
        return point

    def run_folder(self, point, seed):
        return os.path.join(self.path, "runs", self._point_id(point), f"seed_{int(seed)}")

    def run(self, point, seed):
        """The Run of `point` (its id 'p000' or its index) and `seed`."""
        return Run(self.run_folder(point, seed))

    def _status_file(self, pid, seed):
        return os.path.join(self.path, "status", pid, f"seed_{seed}.json")

    @property
    def status(self):
        def make():
            rows = []
            for p in self.plan["points"]:
                for seed in self.seeds:
                    path = self._status_file(p["id"], seed)
                    if os.path.exists(path):
                        rows.append(study_files.read_run_status(path))
                        rows[-1]["point"] = p["id"]
            return pd.DataFrame(rows, columns=["point", "seed", "outcome", "detail", "exit_code",
                                               "signal", "wall_seconds", "peak_rss_mib"])
        return self._cached("status", make)

    @property
    def runs(self):
        def make():
            points = self.points
            rows = []
            for index, p in enumerate(self.plan["points"]):
                keys = {key: points[key].iloc[index] for key in self.vary}
                for seed in self.seeds:
                    folder = self.run_folder(p["id"], seed)
                    metrics_path = os.path.join(folder, "metrics.json")
                    per_pipeline = {}
                    if os.path.exists(metrics_path):
                        status = "finished"
                        metrics = files.read_metrics_full(metrics_path, fast=True)
                        per_pipeline = metrics.get("pipelines") or {}
                    elif os.path.exists(self._status_file(p["id"], seed)):
                        status = study_files.read_run_status(self._status_file(p["id"], seed))["outcome"]
                    else:
                        status = "not_run"
                    for name in self.pipelines:
                        row = {"point": p["id"], "seed": seed, **keys, "pipeline": name,
                               "status": status}
                        for metric, value in _flatten(per_pipeline.get(name, {})).items():
                            if metric not in row:
                                row[metric] = value
                        rows.append(row)
            frame = pd.DataFrame(rows)
            frame["seed"] = frame["seed"].astype(np.uint64 if self.seeds[-1] >= 2**63
                                                 else np.int64)
            return frame
        return self._cached("runs", make)

    def _table(self, name, columns):
        keys, table = study_files.read_study_table(os.path.join(self.path, name), columns)
        frame = pd.DataFrame(table)
        for key in keys:
            frame[key] = _typed(list(frame[key]))
        frame["n"] = frame["n"].astype(np.int64)
        return frame

    @property
    def summary(self):
        return self._cached("summary", lambda: self._table("summary.csv",
                                                           study_files.SUMMARY_CSV_COLUMNS))

    @property
    def paired(self):
        return self._cached("paired", lambda: self._table("paired.csv", study_files.PAIRED_CSV_COLUMNS))

    @property
    def summary_json(self):
        return self._cached("summary_json", lambda: files.read_json_object(
            os.path.join(self.path, "summary.json"), files.MAX_FILE_BYTES))

    def compare(self, a, b, metric="ate_rmse_m", point=None):
        """Pipeline `a` against `b` on `metric`, paired per seed: one row per point and seed where
        both finished with a finite value: point, seed, the swept keys, <a>, <b> (the values) and
        diff = a - b. `point`: only that point (id or index)."""
        for name in (a, b):
            if name not in self.pipelines:
                raise KeyError(f"{self.path}: no pipeline '{name}' (pipelines: "
                               f"{', '.join(self.pipelines)})")
        if a == b:
            raise ValueError("compare: a and b are the same pipeline")
        runs = self.runs
        if metric not in runs.columns:
            raise KeyError(f"{self.path}: no run has the metric '{metric}'")
        runs = runs[runs["status"] == "finished"]
        if point is not None:
            runs = runs[runs["point"] == self._point_id(point)]
        index = ["point", "seed"] + self.vary
        values = {name: runs[runs["pipeline"] == name].set_index(index)[metric]
                  for name in (a, b)}
        frame = pd.concat(values, axis=1).reset_index()
        frame[a] = pd.to_numeric(frame[a], errors="coerce")
        frame[b] = pd.to_numeric(frame[b], errors="coerce")
        frame = frame[np.isfinite(frame[a]) & np.isfinite(frame[b])].reset_index(drop=True)
        frame["diff"] = frame[a] - frame[b]
        return frame
