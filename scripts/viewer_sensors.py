"""The run folder's sensors/ as viewer.html carries them (docs/viewer.md, "Sensors"; the files:
docs/sensors.md, "In the run folder"): each IMU's gyroscope and accelerometer, measured and exact,
and its true biases, decimated by time buckets that keep every bucket's extremes; each laser
scanner's sweeps (measured and exact ranges, the scanner's true pose at the first and the last
beam), every k-th sweep within a budget of ranges.

The files are read once (read_sensors) and cut to a page's number of points as often as the page's
budget asks (sensors_json). A long run at 1 kHz has millions of IMU rows: they are read in chunks
of CHUNK_ROWS (numpy's loadtxt; a chunk that does not parse is read again line by line to name the
line), so the memory stays bounded and only the retained rows are kept. A file that is malformed
or missing becomes the sensor's `problem`, one line naming the file (and line) that the page
shows; the rest of the page stands, so a broken sensors/ file never costs the run's page."""

import itertools
import math
import os
import re

import numpy as np

from viewer_series import extrema_indices, pick, rounded, significant

# A sensor's name (docs/sensors.md): 1 to 32 of a-z, 0-9 and _, starting with a letter.
NAME = re.compile(r"[a-z][a-z0-9_]{0,31}")
MAX_SENSORS = 8               # of each kind (docs/sensors.md); more files than that are left out
CHUNK_ROWS = 16384            # IMU rows parsed at once (~70 MB of peak memory in all)
MAX_IMU_ROWS = 20_000_000     # 5.5 h at 1 kHz; a longer file is not plotted (a problem)
MAX_SWEEPS = 2_000_000
MAX_BEAMS = 100_000
# Ranges kept per scanner (measured; the exact ones as many again): the page's points times this.
# 6000 points: 96,000 ranges, every sweep of a 27 s run of 361 beams at 10 Hz.
RANGES_PER_POINT = 16
M, S = 4, 4                   # decimals of metres and seconds (as make_viewer.py)
QUATERNION = 6                # decimals of a quaternion's components: 2e-6 rad, 2e-5 m at 10 m
READING_DIGITS = 5            # significant digits of a reading
BIAS_DIGITS = 4

# The page's series of an IMU: group -> [(short name, column of <imu>_imu.csv)], each group
# decimated on its own time axis (one plot each: the extremes of its columns are kept).
IMU_GROUPS = {
    "gyro": [("x", "wx_rad_s"), ("y", "wy_rad_s"), ("z", "wz_rad_s"),
             ("true_x", "true_wx_rad_s"), ("true_y", "true_wy_rad_s"),
             ("true_z", "true_wz_rad_s")],
    "accel": [("x", "ax_m_s2"), ("y", "ay_m_s2"), ("z", "az_m_s2"),
              ("true_x", "true_ax_m_s2"), ("true_y", "true_ay_m_s2"),
              ("true_z", "true_az_m_s2")],
    "bias": [("wx", "bias_wx_rad_s"), ("wy", "bias_wy_rad_s"), ("wz", "bias_wz_rad_s"),
             ("ax", "bias_ax_m_s2"), ("ay", "bias_ay_m_s2"), ("az", "bias_az_m_s2")],
}
IMU_COLUMNS = ["t"] + [c for group in IMU_GROUPS.values() for _, c in group]
SCAN_FIXED = ["t", "angle_min_rad", "angle_increment_rad", "time_increment_s", "scan_time_s",
              "range_min_m", "range_max_m"]
POSE = ["x_m", "y_m", "z_m", "qx", "qy", "qz", "qw"]
TRUTH_FIXED = ["t"] + ["first_" + c for c in POSE] + ["last_" + c for c in POSE]


class Problem(Exception):
    """What the page says instead of a sensor's data: `where: what`."""

    def __init__(self, path, line, message):
        where = path if line is None else f"{path}:{line}"
        super().__init__(f"{where}: {message}")


def data_rows(path):
    """The number of lines after the header (a fast count of newlines, blank lines included)."""
    count, last = 0, b"\n"
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            count += block.count(b"\n")
            last = block[-1:]
    return max(count - 1 + (last != b"\n"), 0)


def header_of(f, path, first):
    """The header's names; Problem unless its first columns are `first`."""
    header = [h.strip() for h in f.readline().split(",")]
    if header[:len(first)] != first:
        raise Problem(path, 1, "the header does not start with " + ",".join(first)
                      + " (docs/sensors.md)")
    return header


def parse_line(path, number, line, width):
    fields = line.split(",")
    if len(fields) != width:
        raise Problem(path, number, f"expected {width} fields, got {len(fields)}")
    try:
        return [float(v) for v in fields]
    except ValueError:
        raise Problem(path, number, "not a number in the line") from None


# ------------------------------------------------------------------------------------ the IMUs

class BucketExtremes:
    """The rows a group keeps over time buckets of [t0, t1] (rows in time order): each bucket's
    first row and the rows of each column's minimum and maximum (extrema_indices, streamed)."""

    def __init__(self, t0, t1, limit, columns):
        self.columns = columns                      # indices into a row of IMU_COLUMNS
        self.buckets = max(1, limit // (1 + 2 * len(columns)))
        self.t0 = t0
        self.width = (t1 - t0) / self.buckets if t1 > t0 else 1.0
        self.first = {}                             # bucket -> row number
        self.low, self.high = {}, {}                # (bucket, column) -> (value, row number)

    def add(self, rows, values):
        """`values`: a chunk's rows (n x len(IMU_COLUMNS)), `rows` their row numbers."""
        ids = np.clip(np.floor((values[:, 0] - self.t0) / self.width), 0,
                      self.buckets - 1).astype(np.int64)
        starts = np.concatenate(([0], np.flatnonzero(np.diff(ids)) + 1, [len(ids)]))
        for a, b in zip(starts[:-1], starts[1:]):
            bucket = int(ids[a])
            self.first.setdefault(bucket, int(rows[a]))
            for c in self.columns:
                segment = values[a:b, c]
                lo, hi = a + int(np.argmin(segment)), a + int(np.argmax(segment))
                key = (bucket, c)
                if key not in self.low or values[lo, c] < self.low[key][0]:
                    self.low[key] = (float(values[lo, c]), int(rows[lo]))
                if key not in self.high or values[hi, c] > self.high[key][0]:
                    self.high[key] = (float(values[hi, c]), int(rows[hi]))

    def kept(self):
        keep = set(self.first.values())
        keep.update(r for _, r in self.low.values())
        keep.update(r for _, r in self.high.values())
        return keep


def imu_chunks(path, f, width, index, first_line):
    """(first row number, values) per chunk of at most CHUNK_ROWS rows: the columns `index` of
    every row, all finite, stamps increasing; Problem naming the line otherwise."""
    number, row, previous = first_line, 0, -math.inf
    while True:
        lines = list(itertools.islice(f, CHUNK_ROWS))
        if not lines:
            return
        values = None
        # loadtxt refuses a row shorter than its last column (width - 1, read for that); with no
        # row shorter, a longer one shows in the chunk's count of commas
        if "".join(lines).count(",") == len(lines) * (width - 1):
            try:
                values = np.loadtxt(lines, delimiter=",", usecols=index + [width - 1],
                                    ndmin=2, comments=None)[:, :len(index)]
            except ValueError:
                values = None
        # (loadtxt skips blank lines: a chunk that comes back shorter has one)
        bad = values is None or len(values) != len(lines) or not np.isfinite(values).all() or \
            values[0, 0] <= previous or (len(values) > 1 and not (np.diff(values[:, 0]) > 0).all())
        if bad:  # again line by line, for the line's number
            rows = []
            for k, line in enumerate(lines):
                if not line.strip():
                    raise Problem(path, number + k, "a blank line")
                full = parse_line(path, number + k, line, width)
                picked = [full[i] for i in index]
                if not all(math.isfinite(v) for v in picked):
                    raise Problem(path, number + k, "a value is not finite")
                if picked[0] <= previous:
                    raise Problem(path, number + k, f"t {picked[0]} is not after the previous "
                                  f"sample's {previous}")
                previous = picked[0]
                rows.append(picked)
            values = np.array(rows)
        previous = float(values[-1, 0])
        yield row, values
        number += len(lines)
        row += len(lines)


def read_imu(path, span, limit):
    """<imu>_imu.csv: {rows, groups: {group: {"t": [...], short: [...]}}} with at most about
    `limit` samples per group (all of them when the file has no more)."""
    count = data_rows(path)
    if count > MAX_IMU_ROWS:
        raise Problem(path, None, f"{count} samples, more than the {MAX_IMU_ROWS} the page reads")
    with open(path, encoding="utf-8") as f:
        header = header_of(f, path, ["t"])
        missing = [c for c in IMU_COLUMNS if c not in header]
        if missing:
            raise Problem(path, 1, "the header has no column " + ", ".join(missing))
        index = [header.index(c) for c in IMU_COLUMNS]
        position = {c: k for k, c in enumerate(IMU_COLUMNS)}
        keep_all = count <= limit
        reducers = {}
        if not keep_all:
            for group, columns in IMU_GROUPS.items():
                reducers[group] = BucketExtremes(span[0], span[1], limit,
                                                 [position[c] for _, c in columns])
        stored, rows = {}, 0   # row number -> values, of the rows kept so far
        for row, values in imu_chunks(path, f, len(header), index, 2):
            end = row + len(values)
            if keep_all:
                stored.update((row + k, values[k]) for k in range(len(values)))
            else:
                numbers = np.arange(row, end)
                for reducer in reducers.values():
                    reducer.add(numbers, values)
                alive = set().union(*(r.kept() for r in reducers.values()))
                alive.add(end - 1)  # the last row so far: the file's last at the end
                # copies: a view would keep its whole chunk alive
                stored = {k: (values[k - row].copy() if k >= row else stored[k]) for k in alive}
            rows = end
    if rows == 0:
        raise Problem(path, None, "has no samples")
    groups = {}
    for group, columns in IMU_GROUPS.items():
        keep = sorted(stored) if keep_all else sorted(reducers[group].kept() | {rows - 1})
        entry = {"t": [float(stored[k][0]) for k in keep]}
        for short, column in columns:
            entry[short] = [float(stored[k][position[column]]) for k in keep]
        groups[group] = entry
    return {"rows": rows, "groups": groups}


def imu_json(name, imu, points):
    """An IMU's entry of the page at `points` samples per group."""
    out = {"name": name, "file": f"sensors/{name}_imu.csv", "samples": imu["rows"],
           "problem": None}
    for group, columns in IMU_GROUPS.items():
        g = imu["groups"][group]
        keep = extrema_indices(g["t"], [g[short] for short, _ in columns], points)
        digits = BIAS_DIGITS if group == "bias" else READING_DIGITS
        entry = {"t": rounded(pick(g["t"], keep), S)}
        for short, _ in columns:
            entry[short] = significant(pick(g[short], keep), digits)
        out[group] = entry
    return out


# ------------------------------------------------------------------------------- the scanners

def read_scanner(scans_path, truth_path, max_ranges):
    """<laser>_scans.csv with <laser>_scans_truth.csv: the scanner's fixed fields and every k-th
    sweep (and the last) with k the smallest stride that keeps at most `max_ranges` measured
    ranges. Each row of both files is checked to have the same stamp; the kept rows are parsed
    whole (the others only to their stamp)."""
    if not os.path.exists(truth_path):
        raise Problem(truth_path, None, "is missing (the scanner's true poses are in it)")
    sweeps = data_rows(scans_path)
    if sweeps > MAX_SWEEPS:
        raise Problem(scans_path, None, f"{sweeps} sweeps, more than the {MAX_SWEEPS} the page "
                      "reads")
    with open(scans_path, encoding="utf-8") as scans, open(truth_path, encoding="utf-8") as truth:
        header = header_of(scans, scans_path, SCAN_FIXED)
        beams = len(header) - len(SCAN_FIXED)
        if not 1 <= beams <= MAX_BEAMS:
            raise Problem(scans_path, 1, f"{beams} beams (1 to {MAX_BEAMS})")
        truth_header = header_of(truth, truth_path, TRUTH_FIXED)
        if len(truth_header) != len(TRUTH_FIXED) + beams:
            raise Problem(truth_path, 1, f"{len(truth_header) - len(TRUTH_FIXED)} beams, the "
                          f"scans {beams}")
        stride = max(1, math.ceil(sweeps * beams / max(max_ranges, 1)))
        out = {"beams": beams, "sweeps": 0, "stride": stride, "fixed": None, "t": [],
               "first": [], "last": [], "ranges": [], "exact": []}
        number = 1
        for row, (line, true_line) in enumerate(itertools.zip_longest(scans, truth)):
            number += 1
            if line is None or true_line is None:
                raise Problem(truth_path if true_line is None else scans_path, number,
                              "the scans and their truth have different numbers of sweeps")
            stamp, true_stamp = line.split(",", 1)[0].strip(), true_line.split(",", 1)[0].strip()
            if stamp != true_stamp:
                raise Problem(truth_path, number, f"t {true_stamp}, the scan's {stamp}")
            out["sweeps"] = row + 1
            if row % stride and row != sweeps - 1:
                continue
            values = parse_line(scans_path, number, line, len(header))
            exact = parse_line(truth_path, number, true_line, len(truth_header))
            fixed = values[1:len(SCAN_FIXED)]
            if not all(math.isfinite(v) for v in values[:len(SCAN_FIXED)] + exact[:15]):
                raise Problem(scans_path, number, "a stamp, a fixed field or a pose is not "
                              "finite")
            if out["fixed"] is None:
                out["fixed"] = fixed
            elif any(abs(a - b) > 1e-12 * max(1.0, abs(b)) for a, b in zip(fixed, out["fixed"])):
                raise Problem(scans_path, number, "the sweep's angles, times or range limits "
                              "differ from the first sweep's")
            if out["t"] and values[0] <= out["t"][-1]:
                raise Problem(scans_path, number, "t is not after the previous sweep's")
            out["t"].append(values[0])
            out["first"].append(exact[1:8])
            out["last"].append(exact[8:15])
            out["ranges"].append(values[len(SCAN_FIXED):])
            out["exact"].append(exact[15:])
    if not out["t"]:
        raise Problem(scans_path, None, "has no sweeps")
    return out


def scanner_json(name, scanner, points):
    """A scanner's entry of the page at `points`: its kept sweeps thinned to every m-th so that at
    most points * RANGES_PER_POINT measured ranges remain (the last one kept)."""
    n, beams = len(scanner["t"]), scanner["beams"]
    m = max(1, math.ceil(n * beams / (points * RANGES_PER_POINT)))
    keep = list(range(0, n, m))
    if keep[-1] != n - 1:
        keep.append(n - 1)
    fixed = scanner["fixed"]
    return {"name": name, "file": f"sensors/{name}_scans.csv", "problem": None,
            "sweeps": scanner["sweeps"], "stride": scanner["stride"] * m, "beams": beams,
            "angle_min": fixed[0], "angle_increment": fixed[1], "time_increment": fixed[2],
            "range_min": fixed[4], "range_max": fixed[5],
            "t": rounded(pick(scanner["t"], keep), S),
            "first": [rounded(p[:3], M) + rounded(p[3:], QUATERNION)
                      for p in pick(scanner["first"], keep)],
            "last": [rounded(p[:3], M) + rounded(p[3:], QUATERNION)
                     for p in pick(scanner["last"], keep)],
            "ranges": [rounded(r, M) for r in pick(scanner["ranges"], keep)],
            "exact": [rounded(r, M) for r in pick(scanner["exact"], keep)]}


# ------------------------------------------------------------------------------ the folder

def sensor_names(folder, suffix):
    """The names of the files `<name><suffix>` in sensors/ (sorted, at most MAX_SENSORS)."""
    names = sorted(f[:-len(suffix)] for f in os.listdir(folder)
                   if f.endswith(suffix) and NAME.fullmatch(f[:-len(suffix)]))
    return names[:MAX_SENSORS]


def read_sensors(run_dir, span, limit):
    """{"imus": [(name, data | Problem text)], "lasers": [...]} of RUN_DIR/sensors/, read once
    with at most about `limit` samples per IMU group and limit * RANGES_PER_POINT ranges per
    scanner; None without a sensors/ folder holding IMU or scanner files."""
    folder = os.path.join(run_dir, "sensors")
    if not os.path.isdir(folder):
        return None
    out = {"imus": [], "lasers": []}
    for name in sensor_names(folder, "_imu.csv"):
        try:
            out["imus"].append((name, read_imu(os.path.join(folder, f"{name}_imu.csv"), span,
                                               limit)))
        except (Problem, OSError, UnicodeDecodeError, ValueError) as e:
            out["imus"].append((name, problem_text(e, folder, f"{name}_imu.csv")))
    for name in sensor_names(folder, "_scans.csv"):
        try:
            out["lasers"].append((name, read_scanner(
                os.path.join(folder, f"{name}_scans.csv"),
                os.path.join(folder, f"{name}_scans_truth.csv"), limit * RANGES_PER_POINT)))
        except (Problem, OSError, UnicodeDecodeError, ValueError) as e:
            out["lasers"].append((name, problem_text(e, folder, f"{name}_scans.csv")))
    return out if out["imus"] or out["lasers"] else None


def problem_text(error, folder, name):
    """The page's line for a sensor's file that could not be read: paths relative to the run."""
    text = str(error) if isinstance(error, Problem) else f"{os.path.join(folder, name)}: {error}"
    return text.replace(os.path.dirname(folder) + os.sep, "")[:300]


def sensors_json(sensors, points):
    """The page's "sensors" section at `points` samples per series."""
    imus = [imu_json(name, d, points) if isinstance(d, dict) else
            {"name": name, "file": f"sensors/{name}_imu.csv", "problem": d}
            for name, d in sensors["imus"]]
    lasers = [scanner_json(name, d, points) if isinstance(d, dict) else
              {"name": name, "file": f"sensors/{name}_scans.csv", "problem": d}
              for name, d in sensors["lasers"]]
    return {"imus": imus, "lasers": lasers}
