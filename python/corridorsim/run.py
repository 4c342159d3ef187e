"""corridorsim.Run: a run folder of `corridorsim run` as pandas DataFrames (docs/analysis.md),
read through corridorsim.files' strict readers; its trajectory metrics recomputed by
trajectory_metrics.py equal metrics.json's. corridorsim.analysis re-exports it."""

import math
import os

import numpy as np
import pandas as pd

from . import files
from .files import InputError
from .trajectory_metrics import (RPE_DISTANCES_M, _norm, _poses, _travelled, match_to_truth,
                                 normalize_angle, trajectory_metrics, yaw_from_quaternion)

MAX_SCENARIO_BYTES = 16 << 20


# ------------------------------------------------------------------------------------------------
# Small helpers

def _lookup(obj, dotted):
    """obj['a']['b'] for 'a.b' (None when a part is absent)."""
    for part in dotted.split("."):
        if not isinstance(obj, dict) or part not in obj:
            return None
        obj = obj[part]
    return obj


def _pose_frame(columns, extra=()):
    """A DataFrame t_ns (int64), t, x, y, z, qx, qy, qz, qw, yaw (+ extra) of read_tum_exact's
    columns."""
    frame = pd.DataFrame({"t_ns": np.array(columns["t_ns"], dtype=np.int64),
                          "t": np.array(columns["t"], dtype=float)})
    for name in files.TUM_FIELDS:
        frame[name] = np.array(columns[name], dtype=float)
    frame["yaw"] = np.array([yaw_from_quaternion(qz, qw)
                             for qz, qw in zip(columns["qz"], columns["qw"])], dtype=float)
    for name in extra:
        frame[name] = np.array(columns[name], dtype=float)
    return frame


# ------------------------------------------------------------------------------------------------
# Run

class Run(files.FolderReader):
    """A run folder of `corridorsim run` (README.md's table; docs/metrics.md).

    Attributes (read when first used, then kept):
      path          the folder
      pipelines     the pipelines' names in metrics.json's order (when it has none: the stems of
                    the other *.tum files, sorted)
      metrics       metrics.json as parsed (dict)
      expectations  DataFrame text, measured, passed
      truth         ground_truth.tum as a DataFrame (see trajectory())
      world         world.json's plan (files.read_world: walls, doors, plates, lamps,
                    distractors)
      events        DataFrame of events.json's events: t, t_ns, type, then each kind's own keys
      timing, provenance   timing.json, provenance.json as parsed (dict)
      scenario      scenario.yaml parsed (python3-yaml) or, without yaml, its text
      scenario_text scenario.yaml's text
    """

    def __init__(self, path):
        super().__init__(path)
        self.metrics  # noqa: B018 (read now: a folder without metrics.json is no run)

    def _file(self, name):
        return os.path.join(self.path, name)

    def _pipeline_file(self, name, suffix):
        if name not in self.pipelines:
            raise KeyError(f"{self.path}: no pipeline '{name}' (pipelines: "
                           f"{', '.join(self.pipelines)})")
        return self._file(name + suffix)

    # -- metrics.json ---------------------------------------------------------------------------
    @property
    def metrics(self):
        return self._cached("metrics", lambda: files.read_metrics_full(self._file("metrics.json")))

    @property
    def pipelines(self):
        def names():
            listed = list(self.metrics.get("pipelines") or {})
            if listed:
                return listed
            return sorted(f[:-len(".tum")] for f in os.listdir(self.path)
                          if f.endswith(".tum") and not f.startswith("ground_truth"))
        return self._cached("pipelines", names)

    def metric(self, pipeline, dotted):
        """metrics.json's value of `dotted` ('ate_rmse_m', 'nis.lamp.mean') for `pipeline`; None
        when absent or null."""
        return _lookup((self.metrics.get("pipelines") or {}).get(pipeline, {}), dotted)

    @property
    def expectations(self):
        rows = [{"text": e.get("text"), "measured": e.get("measured"), "passed": e.get("passed")}
                for e in self.metrics.get("expectations") or []]
        return pd.DataFrame(rows, columns=["text", "measured", "passed"])

    # -- trajectories ---------------------------------------------------------------------------
    def _truth_columns(self):
        return self._cached("truth_columns", lambda: files.read_tum_exact(
            self._file("ground_truth.tum"), increasing=True))

    def _estimate_columns(self, name):
        return self._cached(("estimate", name), lambda: files.read_tum_exact(
            self._pipeline_file(name, ".tum"), allow_non_finite=True, allow_empty=True))

    @property
    def truth(self):
        """ground_truth.tum: t_ns (int64, exact), t (s), x, y, z (m), qx, qy, qz, qw, yaw (rad,
        NormalizeAngle(2 atan2(qz, qw)): the truth the runner scores against)."""
        return _pose_frame(self._truth_columns())

    def trajectory(self, name):
        """<name>.tum as a DataFrame: t_ns (int64, exact from the text), t (s), x, y, z (m, as
        written: six decimals), qx, qy, qz, qw, yaw (rad, from the printed quaternion). Rows in
        file order; a pose the pipeline reported as not finite is NaN."""
        return _pose_frame(self._estimate_columns(name))

    def covariance(self, name):
        """<name>_cov.txt (OpenVINS ov_eval): the trajectory's columns plus Pr11 ... Pt33 and, for
        convenience, var_x_m2 (Pt11), cov_xy_m2 (Pt12), var_y_m2 (Pt22), var_yaw_rad2 (Pr33). NaN
        where the pipeline's covariance was not finite."""
        columns = files.read_covariance(self._pipeline_file(name, "_cov.txt"))
        frame = _pose_frame(columns, files.OV_EVAL_COVARIANCE)
        frame["var_x_m2"], frame["cov_xy_m2"] = frame["Pt11"], frame["Pt12"]
        frame["var_y_m2"], frame["var_yaw_rad2"] = frame["Pt22"], frame["Pr33"]
        return frame

    def _matched(self, name):
        def make():
            return match_to_truth(_poses(self._truth_columns()),
                                  _poses(self._estimate_columns(name)))
        return self._cached(("matched", name), make)

    def matched(self, name):
        """The estimates the runner scores, each with the truth at its stamp: t_ns, t (s), x, y,
        yaw, truth_x, truth_y, truth_yaw, ex_m, ey_m (estimate - truth), eyaw_rad (wrapped),
        error_m (planar norm), travelled_m (along the truth). Computed from the TUM files as the
        runner computes them (exact)."""
        m = self._matched(name)
        est, tru = m["estimates"], m["truths"]
        frame = pd.DataFrame({
            "t_ns": np.array(m["stamps"], dtype=np.int64),
            "x": [e[0] for e in est], "y": [e[1] for e in est], "yaw": [e[2] for e in est],
            "truth_x": [t[0] for t in tru], "truth_y": [t[1] for t in tru],
            "truth_yaw": [t[2] for t in tru],
            "ex_m": [e[0] - t[0] for e, t in zip(est, tru)],
            "ey_m": [e[1] - t[1] for e, t in zip(est, tru)],
            "eyaw_rad": [normalize_angle(e[2] - t[2]) for e, t in zip(est, tru)],
            "error_m": [_norm(e[0] - t[0], e[1] - t[1]) for e, t in zip(est, tru)],
            "travelled_m": _travelled(tru)})
        frame.insert(1, "t", frame["t_ns"].to_numpy() / 1e9)
        return frame

    def trajectory_metrics(self, name):
        """metrics.json's trajectory metrics of `name` recomputed from ground_truth.tum and
        <name>.tum (flat dotted keys: samples, samples_without_truth, distance_travelled_m,
        ate_rmse_m, ate_mean_m, ate_max_m, ate_yaw_rmse_rad, ate_aligned_*, alignment.x_m, ...,
        rpe_<d>m_trans_rmse_m, rpe_<d>m_yaw_rmse_rad, rpe_<d>m_pairs, final_position_error_m,
        final_yaw_error_rad), rounded as metrics.json."""
        return self._cached(("trajectory_metrics", name),
                            lambda: trajectory_metrics(self._matched(name)))

    def ate(self, name):
        """ATE RMSE, unaligned (m): equal to metrics.json's ate_rmse_m. None without samples."""
        return self.trajectory_metrics(name).get("ate_rmse_m")

    def ate_aligned(self, name):
        """ATE RMSE after the least-squares SE2 alignment (m): metrics.json's ate_aligned_rmse_m."""
        return self.trajectory_metrics(name).get("ate_aligned_rmse_m")

    def rpe(self, name, distance_m=1, kind="trans"):
        """RPE RMSE over `distance_m` (1, 5 or 10) metres: kind 'trans' (m,
        rpe_<d>m_trans_rmse_m) or 'yaw' (rad, rpe_<d>m_yaw_rmse_rad). None when the run has no
        pair that far apart (metrics.json's null)."""
        if distance_m not in RPE_DISTANCES_M:
            raise ValueError(f"distance_m: expected one of {RPE_DISTANCES_M}, got {distance_m!r}")
        if kind not in ("trans", "yaw"):
            raise ValueError(f"kind: expected 'trans' or 'yaw', got {kind!r}")
        suffix = "trans_rmse_m" if kind == "trans" else "yaw_rmse_rad"
        return self.trajectory_metrics(name).get(f"rpe_{int(distance_m)}m_{suffix}")

    def final_error(self, name):
        """Position error at the last scored sample (m): metrics.json's final_position_error_m."""
        return self.trajectory_metrics(name).get("final_position_error_m")

    # -- the other per-pipeline files -----------------------------------------------------------
    def errors(self, name):
        """<name>_errors.csv: t (s), ex_m, ey_m, eyaw_rad, sigma_x_m, sigma_y_m, sigma_yaw_rad,
        nees (NaN where empty: no finite covariance)."""
        return pd.DataFrame(files.read_errors(self._pipeline_file(name, "_errors.csv")))

    def nis(self, name):
        """<name>_nis.csv: t (s), type, dof, nis, accepted (bool); empty when the file is absent
        (the runner writes it only for a pipeline with landmark updates)."""
        path = self._pipeline_file(name, "_nis.csv")
        if not os.path.exists(path):
            return pd.DataFrame({c: [] for c in files.NIS_COLUMNS})
        return pd.DataFrame(files.read_nis(path))

    def landmarks(self, name):
        """<name>_landmarks.json, the final map: id, type, status, label, x, y, z (m), cov_xx,
        cov_xy, cov_xz, cov_yy, cov_yz, cov_zz (m^2, NaN for a null entry), covariance (3x3
        array) and points (list of {role, position, covariance}); empty when absent."""
        columns = ["id", "type", "status", "label", "x", "y", "z", "cov_xx", "cov_xy", "cov_xz",
                   "cov_yy", "cov_yz", "cov_zz", "covariance", "points"]
        path = self._pipeline_file(name, "_landmarks.json")
        if not os.path.exists(path):
            return pd.DataFrame({c: [] for c in columns})
        rows = []
        for lm in files.read_landmarks(path):
            cov = np.array([[math.nan if v is None else v for v in row]
                            for row in lm["covariance"]], dtype=float)
            rows.append({"id": lm["id"], "type": lm["type"], "status": lm["status"],
                         "label": lm["label"], "x": lm["position"][0], "y": lm["position"][1],
                         "z": lm["position"][2], "cov_xx": cov[0, 0], "cov_xy": cov[0, 1],
                         "cov_xz": cov[0, 2], "cov_yy": cov[1, 1], "cov_yz": cov[1, 2],
                         "cov_zz": cov[2, 2], "covariance": cov, "points": lm["points"]})
        return pd.DataFrame(rows, columns=columns)

    def detections(self, name):
        """<name>_detections.csv: stamp_s, camera, type, u_px, v_px, label, score,
        recognition_score (NaN: none), landmark_id (-1: not associated), new_landmark (bool);
        empty when absent."""
        path = self._pipeline_file(name, "_detections.csv")
        if not os.path.exists(path):
            return pd.DataFrame({c: [] for c in ["stamp_s", "camera", "type", "u_px", "v_px",
                                                 "label", "score", "recognition_score",
                                                 "landmark_id", "new_landmark"]})
        return pd.DataFrame(files.read_detections(path))

    def frame_times(self, name):
        """maps/<name>_frame_times.csv (stamp_s, landmarks, frame_ms) or None when absent."""
        path = os.path.join(self.path, "maps", f"{name}_frame_times.csv")
        return pd.DataFrame(files.read_frame_times(path)) if os.path.exists(path) else None

    # -- run-wide files -------------------------------------------------------------------------
    @property
    def world(self):
        return self._cached("world", lambda: files.read_world(self._file("world.json")))

    @property
    def events(self):
        def make():
            events = files.read_events(self._file("events.json"))["events"]
            frame = pd.DataFrame(events)
            if frame.empty:
                frame = pd.DataFrame({"t": [], "t_ns": [], "type": []})
            frame["t_ns"] = frame["t_ns"].astype(np.int64)
            return frame
        return self._cached("events", make)

    @property
    def timing(self):
        return self._cached("timing", lambda: files.read_json_object(self._file("timing.json")))

    @property
    def provenance(self):
        return self._cached("provenance",
                            lambda: files.read_json_object(self._file("provenance.json")))

    @property
    def scenario_text(self):
        return self._cached("scenario_text", lambda: files.read_text(
            self._file("scenario.yaml"), MAX_SCENARIO_BYTES))

    @property
    def scenario(self):
        def make():
            text = self.scenario_text
            try:
                import yaml
            except ImportError:
                return text
            try:
                return yaml.safe_load(text)
            except yaml.YAMLError as e:
                mark = getattr(e, "problem_mark", None)
                raise InputError(self._file("scenario.yaml"),
                                 None if mark is None else mark.line + 1,
                                 f"not YAML: {getattr(e, 'problem', e)}") from None
        return self._cached("scenario", make)
