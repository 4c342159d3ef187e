"""Small statistics the pages and plots share: the chi-square bands of the consistency tests.

Pure Python (no scipy on Debian's minimal set): the quantile is found by bisection on the
regularized lower incomplete gamma function, to 1e-12 relative, for any positive degrees of
freedom. harness/metrics/stats.h computes the same bands with Boost for metrics.json.
"""

import math

BAND_LOWER_TAIL = 0.025  # two-sided 95 % interval, as harness/metrics/stats.h
BAND_UPPER_TAIL = 0.975
MAX_DOF = 10000


def _lower_gamma_regularized(a, x):
    """P(a, x) = gamma(a, x) / Gamma(a): the series for x < a + 1, the continued fraction
    (Lentz) of Q otherwise (Numerical Recipes, 6.2)."""
    if x <= 0.0:
        return 0.0
    log_prefix = a * math.log(x) - x - math.lgamma(a)
    if x < a + 1.0:
        term = total = 1.0 / a
        n = a
        for _ in range(100000):
            n += 1.0
            term *= x / n
            total += term
            if abs(term) < abs(total) * 1e-16:
                break
        return min(1.0, total * math.exp(log_prefix))
    tiny = 1e-300
    b = x + 1.0 - a
    c = 1.0 / tiny
    d = 1.0 / b
    h = d
    for i in range(1, 100000):
        an = -i * (i - a)
        b += 2.0
        d = an * d + b
        d = tiny if abs(d) < tiny else d
        c = b + an / c
        c = tiny if abs(c) < tiny else c
        d = 1.0 / d
        step = d * c
        h *= step
        if abs(step - 1.0) < 1e-16:
            break
    return max(0.0, 1.0 - h * math.exp(log_prefix))


def chi2_quantile(dof, p):
    """The p-quantile of the chi-square distribution with `dof` (> 0) degrees of freedom."""
    if not (0.0 < dof <= MAX_DOF) or not (0.0 < p < 1.0):
        raise ValueError(f"chi2_quantile: dof {dof} must be in (0, {MAX_DOF}], p {p} in (0, 1)")
    a = dof / 2.0
    lo, hi = 0.0, max(1.0, dof)
    while _lower_gamma_regularized(a, hi / 2.0) < p:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _lower_gamma_regularized(a, mid / 2.0) < p:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-12 * hi:
            break
    return 0.5 * (lo + hi)


def chi2_band(dof):
    """(2.5 %, 97.5 %) quantiles of chi-square with `dof` degrees of freedom: the band of the
    NEES (dof 3: x, y, yaw) and of each landmark type's NIS."""
    return chi2_quantile(dof, BAND_LOWER_TAIL), chi2_quantile(dof, BAND_UPPER_TAIL)
