"""The series helpers of the run page's data (docs/viewer.md, "The data a page carries"): rounding
(decimals, significant digits; NaN and infinities as null) and the two decimations, a stride that
keeps poses of the file and time buckets that keep every bucket's extremes. Shared by
make_viewer.py and viewer_sensors.py."""

import math


def rounded(values, decimals):
    """A list with each value rounded, NaN and infinities as null."""
    out = []
    for v in values:
        v = float(v)
        out.append(round(v, decimals) if math.isfinite(v) else None)
    return out


def significant(values, digits=4):
    out = []
    for v in values:
        v = float(v)
        out.append(float(f"{v:.{digits}g}") if math.isfinite(v) else None)
    return out


def stride_indices(n, limit):
    """Every k-th index (and the last) so that at most about `limit` remain: what the paths keep,
    so that every pose the page draws is one of the file's."""
    if n <= limit:
        return list(range(n))
    k = math.ceil(n / limit)
    keep = list(range(0, n, k))
    if keep[-1] != n - 1:
        keep.append(n - 1)
    return keep


def extrema_indices(t, columns, limit):
    """Indices that keep each time bucket's first sample and the minimum and maximum of every
    column (NaN ignored): decimation that never hides a peak."""
    n = len(t)
    if n <= limit:
        return list(range(n))
    buckets = max(1, limit // (1 + 2 * max(1, len(columns))))
    t0, t1 = float(t[0]), float(t[-1])
    width = (t1 - t0) / buckets if t1 > t0 else 1.0
    keep = set()
    start = 0
    for b in range(buckets):
        end = start
        edge = t0 + (b + 1) * width
        while end < n and (b == buckets - 1 or float(t[end]) < edge):
            end += 1
        if end > start:
            keep.add(start)
            for column in columns:
                best_lo = best_hi = None
                for i in range(start, end):
                    v = float(column[i])
                    if not math.isfinite(v):
                        continue
                    if best_lo is None or v < float(column[best_lo]):
                        best_lo = i
                    if best_hi is None or v > float(column[best_hi]):
                        best_hi = i
                if best_lo is not None:
                    keep.add(best_lo)
                    keep.add(best_hi)
        start = end
    keep.add(n - 1)
    return sorted(keep)


def pick(values, indices):
    return [values[i] for i in indices]
