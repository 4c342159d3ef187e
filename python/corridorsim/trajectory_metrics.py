"""The runner's trajectory metrics repeated in Python (docs/analysis.md "Exactness"): matching
estimates to the truth by stamp, ATE (plain and aligned), RPE over 1, 5 and 10 m, the final
error, operation by operation as common/pose.cpp and harness/metrics/ do them (IEEE doubles,
sequential sums, the same libm functions) and rounded as metrics.json rounds, so that
corridorsim.Run's numbers equal metrics.json's float for float."""

import bisect
import math

TWO_PI = 2.0 * math.pi
RPE_DISTANCES_M = (1, 5, 10)  # harness/metrics/registry.h kRpeDistancesM
# Rounding steps per unit of metrics.json (common/io/stable_json.h json_steps).
STEPS_PER_METRE = 1e6
STEPS_PER_RAD = 1e8


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
