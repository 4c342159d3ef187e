"""corridorsim's outputs for notebooks and scripts: a run folder (`Run`), a study folder (`Study`)
and a dataset (`Dataset`, in corridorsim.dataset) as pandas DataFrames (docs/analysis.md).

    import corridorsim
    run = corridorsim.Run("out/run")
    run.ate("p3_upward") == run.metrics["pipelines"]["p3_upward"]["ate_rmse_m"]   # True

Every file is read through corridorsim.files' strict readers: a missing or malformed file raises
files.InputError naming the file and, where it can, the line. Files are read when first asked
for and kept.

Exactness. metrics.json's trajectory metrics are computed by the runner from the poses as the
run's TUM files hold them (harness/metrics/trajectory.h PoseAsWritten). `Run.trajectory_metrics`
repeats the runner's arithmetic operation by operation in Python floats (IEEE doubles, sequential
sums, the same libm functions) and rounds as the runner does, so `Run.ate`, `Run.rpe` and
`Run.final_error` equal metrics.json's numbers, float for float (scripts/check_analysis.py checks
every pipeline of every shipped scenario).

Units: metres, seconds, radians; world frame W (docs/frames.md).
"""

import bisect
import math
import os

import numpy as np
import pandas as pd

from . import files, study_files
from .dataset import Dataset
from .files import InputError

__all__ = ["Run", "Study", "Dataset", "InputError", "normalize_angle", "round_to_step",
           "yaw_from_quaternion", "RPE_DISTANCES_M"]

TWO_PI = 2.0 * math.pi
RPE_DISTANCES_M = (1, 5, 10)  # harness/metrics/registry.h kRpeDistancesM
# Rounding steps per unit of metrics.json (common/io/stable_json.h json_steps).
STEPS_PER_METRE = 1e6
STEPS_PER_RAD = 1e8
MAX_SCENARIO_BYTES = 16 << 20


# ------------------------------------------------------------------------------------------------
# The runner's arithmetic, operation by operation (common/pose.cpp, harness/metrics/)

def round_to_step(value, steps):
    """common/io/stable_json.cpp RoundToStep: std::round(value * steps) / steps + 0.0 (halves go
    away from zero, as C's round; not Python's round(), which goes to even; -0 becomes 0)."""
    x = value * steps
    if not math.isfinite(x):
        return x / steps + 0.0
    a = abs(x)
    r = math.floor(a)
    if a - r >= 0.5:  # exact: the fraction of a double is a double
        r += 1
    return math.copysign(float(r), x) / steps + 0.0


def normalize_angle(a):
    """common/pose.cpp NormalizeAngle: a wrapped to (-pi, pi]."""
    if not math.isfinite(a):
        return math.nan
    w = math.remainder(a, TWO_PI)
    return w + TWO_PI if w <= -math.pi else w


def yaw_from_quaternion(qz, qw):
    """The planar yaw of a TUM line's quaternion as the runner reads it back: NormalizeAngle(2
    atan2(qz, qw)) (harness/metrics/trajectory.cpp PoseAsWritten)."""
    return normalize_angle(2.0 * math.atan2(qz, qw))


def _se2_mul(a, b):
    """SE2 a * b (poses as (x, y, yaw) tuples): R(a.yaw) b.t + a.t, a.yaw + b.yaw."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return ((c * b[0] + (-s) * b[1]) + a[0], (s * b[0] + c * b[1]) + a[1],
            normalize_angle(a[2] + b[2]))


def _se2_inverse(a):
    """SE2 a^-1: -(R^T t), -yaw."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-(c * a[0] + s * a[1]), -((-s) * a[0] + c * a[1]), normalize_angle(-a[2]))


def _norm(x, y):
    """Eigen's norm() of a 2-vector."""
    return math.sqrt(x * x + y * y)


class _Stats:
    """harness/metrics/stats.h Stats: count, sequential sum and sum of squares, maximum."""

    def __init__(self):
        self.count, self.sum, self.sum_sq, self.max = 0, 0.0, 0.0, 0.0

    def add(self, v):
        self.count += 1
        self.sum += v
        self.sum_sq += v * v
        self.max = max(self.max, v)  # std::max(max, v): keeps max when v is NaN

    def rms(self):
        return None if self.count == 0 else math.sqrt(self.sum_sq / float(self.count))

    def mean(self):
        return None if self.count == 0 else self.sum / float(self.count)

    def maximum(self):
        return None if self.count == 0 else self.max


def _rounded(value, steps):
    return None if value is None else round_to_step(value, steps)


def _poses(columns):
    """(t_ns list, [(x, y, yaw)]) from read_tum_exact's columns: the poses as the runner reads
    them back."""
    yaw = [yaw_from_quaternion(qz, qw) for qz, qw in zip(columns["qz"], columns["qw"])]
    return columns["t_ns"], list(zip(columns["x"], columns["y"], yaw))


def match_to_truth(truth, estimates):
    """harness/metrics/trajectory.cpp MatchToTruth: every estimate (file order) with a finite
    pose and truth at its stamp (exact on the truth's stamps, interpolated between them, none
    outside). truth, estimates: (t_ns list, [(x, y, yaw)]), the truth's stamps increasing.
    Returns {stamps, estimates, truths, without_truth, non_finite}."""
    truth_t, truth_p = truth
    out = {"stamps": [], "estimates": [], "truths": [], "without_truth": 0, "non_finite": 0}
    for stamp, pose in zip(*estimates):
        if not (math.isfinite(pose[0]) and math.isfinite(pose[1]) and math.isfinite(pose[2])):
            out["non_finite"] += 1
            continue
        k = bisect.bisect_left(truth_t, stamp)
        if k == len(truth_t):
            out["without_truth"] += 1
            continue
        if truth_t[k] == stamp:
            at = truth_p[k]
        elif k == 0:
            out["without_truth"] += 1
            continue
        else:
            a, b = truth_p[k - 1], truth_p[k]
            t = float(stamp - truth_t[k - 1]) / float(truth_t[k] - truth_t[k - 1])
            at = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]),
                  normalize_angle(a[2] + t * normalize_angle(b[2] - a[2])))
        out["stamps"].append(stamp)
        out["estimates"].append(pose)
        out["truths"].append(at)
    return out


def _travelled(truths):
    travelled = [0.0] * len(truths)
    for i in range(1, len(truths)):
        travelled[i] = travelled[i - 1] + _norm(truths[i][0] - truths[i - 1][0],
                                                truths[i][1] - truths[i - 1][1])
    return travelled


def _align_positions(estimates, truths):
    """harness/metrics/trajectory.cpp AlignPositions: truth ~ result * estimate (x, y, yaw)."""
    mex = mey = mtx = mty = 0.0
    for e, t in zip(estimates, truths):
        mex += e[0]
        mey += e[1]
        mtx += t[0]
        mty += t[1]
    n = float(len(estimates))
    mex, mey, mtx, mty = mex / n, mey / n, mtx / n, mty / n
    sum_dot = sum_cross = 0.0
    for e, t in zip(estimates, truths):
        ax, ay, bx, by = e[0] - mex, e[1] - mey, t[0] - mtx, t[1] - mty
        sum_dot += ax * bx + ay * by
        sum_cross += ax * by - ay * bx
    yaw = 0.0 if (sum_dot == 0.0 and sum_cross == 0.0) else math.atan2(sum_cross, sum_dot)
    rotation = (0.0, 0.0, normalize_angle(yaw))
    c, s = math.cos(rotation[2]), math.sin(rotation[2])
    rx = (c * mex + (-s) * mey) + 0.0
    ry = (s * mex + c * mey) + 0.0
    return (mtx - rx, mty - ry, normalize_angle(yaw))


def trajectory_metrics(matched):
    """harness/metrics/trajectory.cpp AddTrajectoryMetrics on match_to_truth's result:
    metrics.json's trajectory keys (dotted: 'alignment.x_m'), rounded as the runner rounds them;
    None where metrics.json has null (an RPE distance without pairs); only the two counts when
    nothing was matched."""
    estimates, truths = matched["estimates"], matched["truths"]
    out = {"samples": len(estimates), "samples_without_truth": matched["without_truth"]}
    if not estimates:
        return out
    m = lambda v: _rounded(v, STEPS_PER_METRE)  # noqa: E731
    rad = lambda v: _rounded(v, STEPS_PER_RAD)  # noqa: E731
    travelled = _travelled(truths)
    out["distance_travelled_m"] = m(travelled[-1])

    ate, ate_yaw = _Stats(), _Stats()
    for e, t in zip(estimates, truths):
        ate.add(_norm(e[0] - t[0], e[1] - t[1]))
        ate_yaw.add(abs(normalize_angle(e[2] - t[2])))
    out.update({"ate_rmse_m": m(ate.rms()), "ate_mean_m": m(ate.mean()),
                "ate_max_m": m(ate.maximum()), "ate_yaw_rmse_rad": rad(ate_yaw.rms())})

    align = _align_positions(estimates, truths)
    c, s = math.cos(align[2]), math.sin(align[2])
    aligned = _Stats()
    for e, t in zip(estimates, truths):
        x = (c * e[0] + (-s) * e[1]) + align[0]
        y = (s * e[0] + c * e[1]) + align[1]
        aligned.add(_norm(x - t[0], y - t[1]))
    out.update({"ate_aligned_rmse_m": m(aligned.rms()), "ate_aligned_mean_m": m(aligned.mean()),
                "ate_aligned_max_m": m(aligned.maximum()), "alignment.x_m": m(align[0]),
                "alignment.y_m": m(align[1]), "alignment.yaw_rad": rad(align[2])})

    n = len(estimates)
    for distance in RPE_DISTANCES_M:
        trans, yaw = _Stats(), _Stats()
        j = 0
        for i in range(n):
            j = max(j, i + 1)
            while j < n and travelled[j] - travelled[i] < distance:
                j += 1
            if j >= n:
                break
            truth_motion = _se2_mul(_se2_inverse(truths[i]), truths[j])
            estimate_motion = _se2_mul(_se2_inverse(estimates[i]), estimates[j])
            error = _se2_mul(_se2_inverse(truth_motion), estimate_motion)
            trans.add(_norm(error[0], error[1]))
            yaw.add(abs(error[2]))
        prefix = f"rpe_{distance}m_"
        out[prefix + "trans_rmse_m"] = m(trans.rms())
        out[prefix + "yaw_rmse_rad"] = rad(yaw.rms())
        out[prefix + "pairs"] = trans.count

    e, t = estimates[-1], truths[-1]
    out["final_position_error_m"] = m(_norm(e[0] - t[0], e[1] - t[1]))
    out["final_yaw_error_rad"] = rad(abs(normalize_angle(e[2] - t[2])))
    return out


# ------------------------------------------------------------------------------------------------
# Small helpers

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


# ------------------------------------------------------------------------------------------------
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
