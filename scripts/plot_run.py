#!/usr/bin/python3
"""Plots of a finished `corridorsim run`: writes RUN_DIR/plots/*.png.

    scripts/plot_run.py RUN_DIR

Reads from RUN_DIR (metres, seconds, radians, world frame W; docs/frames.md):
  world.json               the world's ground truth as `corridorsim world` writes ground_truth.json
  ground_truth.tum         the true trajectory, TUM lines `t tx ty tz qx qy qz qw`
  metrics.json             {"pipelines": {name: {...}}, "expectations": [{text, measured, passed}]}
  <pipeline>.tum           each pipeline's estimated trajectory
  <pipeline>_errors.csv    t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees
  <pipeline>_landmarks.json   (optional) the final map: [{id, type, status, label,
                           position_in_world, covariance (3x3, m^2), points: [{role,
                           position_in_world, covariance}]}] in id order
  <pipeline>_detections.csv   (optional) every detection: stamp_s,camera,type,u_px,v_px,
                           box_min_x_px,box_min_y_px,box_max_x_px,box_max_y_px,plate_box,radius_px,
                           label,open,score,recognition_score,landmark_id,new_landmark
  maps/<pipeline>_frame_times.csv   (optional) stamp_s,landmarks,frame_ms per camera frame
  maps/<pipeline>_doors.json   (optional) corridorsim.upward_doors: each registered door's
                           landmark_id, columns_m and particles [[x_a, y_a, x_b, y_b, h], ...]
  maps/<pipeline>_areas.json   (optional) corridorsim.upward_areas: areas [{id, kind, door_landmark_id,
                           polygon_m, landmark_ids}] (docs/p3.md "Areas")
The pipelines are the keys of metrics.json's `pipelines`, or, when it has none, the stems of the
other *.tum files. Every metrics key and every file marked optional may be absent: a plot whose
data is absent is skipped.

Writes (each printed on its own line):
  trajectories.png         every trajectory over the world's top-down plan
  errors_<pipeline>.png    x, y and heading error against time with +-2 sigma (P3 Fig. 18)
  nees_<pipeline>.png      NEES against time with the 95 % chi-square band for 3 dof
  landmarks_<pipeline>.png the map over the plan: each landmark with its 2-sigma ellipse (x-y block,
                           chi-square 2 dof 95 %), coloured by type, dashed while initialising,
                           plates with their read room number; vanishing points in the legend
  doors_<pipeline>.png     the door particle clouds at registration (P3 Fig. 9): each sample's two
                           columns, with the door landmark's final columns
  areas_<pipeline>.png     the map divided at the doors (P2 Fig. 12): each room's outline and the
                           landmarks coloured by their area, over the plan with the true rooms
  detections_<pipeline>.png  per detection type: u_px against time, detections per frame, and
                           the score of associated against unassociated detections
  frame_time_<pipeline>.png  frame time against the landmarks in the state and over time (P1
                           Fig. 16)
  detectors.png            precision / recall / accuracy per detector and pipeline
  summary.png              the main metrics per pipeline and the expectations, pass or fail

Exit status: 0 when all plots were written; 1 when an input is missing or malformed (the message
names the file and, where it can, the line); 2 on a bad command line. Every input is read and
checked before anything is drawn, so a bad input leaves no partial plots. The PNGs carry no
software or date metadata, so the same inputs and matplotlib version give the same bytes.
"""

import argparse
import math
import os
import sys
import textwrap

# Debian's python3-matplotlib and python3-numpy live in /usr/bin/python3's site-packages; a pyenv
# or venv `python3` that comes first on PATH may not see them, so the script re-runs itself there.
SYSTEM_PYTHON = "/usr/bin/python3"
REEXEC_ENV = "CORRIDORSIM_PLOT_REEXEC"
try:
    import matplotlib
    import numpy as np
except ImportError as missing:
    if (not os.environ.get(REEXEC_ENV) and os.path.exists(SYSTEM_PYTHON) and
            os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON)):
        os.environ[REEXEC_ENV] = "1"
        os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
    print(f"plot_run: {missing.name} is not installed for {sys.executable} "
          "(scripts/setup.sh installs python3-matplotlib)", file=sys.stderr)
    sys.exit(1)
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the backend)
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Circle, Ellipse, Polygon, Rectangle  # noqa: E402

# The strict readers of a run folder live in the corridorsim Python package (python/corridorsim/
# files.py); the names are re-exported here for the scripts that import plot_run. When the package
# is not on sys.path (a checkout's script run directly), the checkout's python/ folder is added.
try:
    import corridorsim.files  # noqa: F401
except ImportError:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python"))
    for _module in [m for m in sys.modules if m == "corridorsim" or m.startswith("corridorsim.")]:
        del sys.modules[_module]  # an installed package without files.py: take the checkout's
from corridorsim.files import (  # noqa: E402,F401
    BOX_COLUMNS, DETECTION_COLUMNS, DETECTOR_SCORES, DOOR_STATES, ERROR_COLUMNS_OPTIONAL,
    ERROR_COLUMNS_REQUIRED, LANDMARK_STATUSES, LANDMARK_TYPES, MAX_CSV_ROWS, MAX_LANDMARK_POINTS,
    MAX_LANDMARKS, MAX_PARTICLES, MAX_TEXT_CHARS, SUMMARY_METRICS, CsvCells, InputError, JsonArray,
    JsonObject, JsonReader, finite_numbers, is_integer, is_number, load_json, read_areas,
    read_csv_table, read_detections, read_detectors, read_errors, read_format, read_frame_times,
    read_landmarks, read_metrics, read_optional, read_point3, read_run, read_short_text, read_text,
    read_tum, read_upward_doors, read_world)

# Single-sample 95 % bounds of chi-square (2.5 % and 97.5 % quantiles) by degrees of freedom.
CHI2_95_BOUNDS = {1: (0.000982, 5.0239), 2: (0.0506, 7.3778), 3: (0.2158, 9.3484),
                  6: (1.2373, 14.4494)}
NEES_DOF = 3  # x, y, yaw

# SUMMARY_METRICS (the scalars read from metrics.json's pipelines, with their labels in
# summary.png), DETECTOR_SCORES, LANDMARK_TYPES (in drawing order), LANDMARK_STATUSES and the
# MAX_* bounds on the inputs come from corridorsim.files.

# Plan colours, the same as worlds/map_plot.cpp draws map.png.
DOOR_COLORS = {"closed": "#d72828", "open": "#1ea03c", "empty": "#285adc"}
WALL_COLOR = "#37373c"
LAMP_ON_FACE, LAMP_ON_EDGE = "#ffd700", "#aa8200"
LAMP_OFF_EDGE = "#646464"
PLATE_COLOR = "#6a3d9a"

# The colours of the landmark and detection types; the true plates keep PLATE_COLOR.
TYPE_COLORS = {"door_plate": "#e6550d", "door": "#8c564b", "lamp": "#e91e63", "corner": "#17a2b8",
               "vanishing_point": "#7f7f7f"}
SCORE_NAMES = {"door_plate": "SVM margin", "corner": "Harris response",
               "vanishing_point": "line count", "door": "score", "lamp": "score"}
CHI2_2DOF_95 = 5.991  # 95 % quantile of chi-square with 2 dof: the ellipse is sqrt(5.991) sigma

# Bounds on what is drawn.
MAX_PLATE_ANNOTATIONS = 80  # labelled plate tracks in detections_<pipeline>.png
MAX_LISTED_VPS = 6         # vanishing points listed in the legend of landmarks_<pipeline>.png

PANEL_MAX_ASPECT = 8.0  # a trajectories panel is at most 8 times longer than it is wide
PANEL_MAX_COUNT = 8
PANEL_OVERLAP_M = 0.5   # neighbouring panels share this much, so nothing hides at a cut
PLAN_MARGIN_M = 0.3
ESTIMATE_SLACK_M = 1.5  # how far beyond the world and the truth the plan grows for estimates
DPI = 100


# ------------------------------------------------------------------------------------------------
# Drawing

def chi2_95_bounds(dof):
    """2.5 % and 97.5 % quantiles of chi-square with `dof` degrees of freedom: scipy when it is
    installed, else the table, else the Wilson-Hilferty approximation."""
    try:
        from scipy.stats import chi2
        return float(chi2.ppf(0.025, dof)), float(chi2.ppf(0.975, dof))
    except ImportError:
        pass
    if dof in CHI2_95_BOUNDS:
        return CHI2_95_BOUNDS[dof]
    z, h = 1.959964, 2.0 / (9.0 * dof)
    return tuple(dof * (1.0 - h + s * z * math.sqrt(h)) ** 3 for s in (-1.0, 1.0))


def save(fig, plots_dir, name, written):
    """Writes the figure atomically (temporary file, then rename) and without metadata."""
    path = os.path.join(plots_dir, name)
    tmp = path + ".tmp"
    fig.savefig(tmp, format="png", dpi=DPI, metadata={"Software": None})
    os.replace(tmp, path)
    written.append(path)
    plt.close(fig)


def plan_extent(run):
    """(xmin, xmax, ymin, ymax) of the plan: walls, lamps, plates and the true trajectory, with a
    margin, grown by at most ESTIMATE_SLACK_M to take in the estimates. A diverged estimate is
    cut at the border rather than shrinking the corridor to a line."""
    world = run["world"]
    xs, ys = [], []
    for a, b in world["walls"]:
        xs += [a[0], b[0]]
        ys += [a[1], b[1]]
    for p in world["plates"] + world["lamps"]:
        xs.append(p["center"][0])
        ys.append(p["center"][1])
    xs += [run["truth"][:, 1].min(), run["truth"][:, 1].max()]
    ys += [run["truth"][:, 2].min(), run["truth"][:, 2].max()]
    m = PLAN_MARGIN_M
    xmin, xmax, ymin, ymax = min(xs) - m, max(xs) + m, min(ys) - m, max(ys) + m
    for p in run["pipelines"].values():
        tum = p["trajectory"]
        xmin = max(min(xmin, tum[:, 1].min() - m), xmin - ESTIMATE_SLACK_M)
        xmax = min(max(xmax, tum[:, 1].max() + m), xmax + ESTIMATE_SLACK_M)
        ymin = max(min(ymin, tum[:, 2].min() - m), ymin - ESTIMATE_SLACK_M)
        ymax = min(max(ymax, tum[:, 2].max() + m), ymax + ESTIMATE_SLACK_M)
    return xmin, xmax, ymin, ymax


def outside(tum, extent):
    """Whether some pose of the trajectory lies outside the plotted extent."""
    xmin, xmax, ymin, ymax = extent
    x, y = tum[:, 1], tum[:, 2]
    return bool(((x < xmin) | (x > xmax) | (y < ymin) | (y > ymax)).any())


def plan_panels(extent):
    """Splits a long plan along its longer axis into panels of at most PANEL_MAX_ASPECT:1.
    Returns ([(xlim, ylim)], stacked) where stacked means one panel above the other."""
    xmin, xmax, ymin, ymax = extent
    dx, dy = xmax - xmin, ymax - ymin
    stacked = dx >= dy
    long_lo, long_len, short = (xmin, dx, dy) if stacked else (ymin, dy, dx)
    count = max(1, min(PANEL_MAX_COUNT, math.ceil(long_len / (PANEL_MAX_ASPECT * short))))
    step = long_len / count
    overlap = PANEL_OVERLAP_M if count > 1 else 0.0
    panels = []
    for i in range(count):
        lo = long_lo + i * step - (overlap if i > 0 else 0.0)
        hi = long_lo + (i + 1) * step + (overlap if i < count - 1 else 0.0)
        panels.append(((lo, hi), (ymin, ymax)) if stacked else ((xmin, xmax), (lo, hi)))
    return panels, stacked


def draw_world(ax, world):
    """The top-down plan: walls, doors by state, lamps (off ones hollow), plates with numbers."""
    for a, b in world["walls"]:
        ax.plot([a[0], b[0]], [a[1], b[1]], color=WALL_COLOR, lw=2.0, solid_capstyle="butt",
                zorder=3)
    for door in world["doors"]:
        color = DOOR_COLORS.get(door["state"], "0.5")
        ax.plot([door["a"][0], door["b"][0]], [door["a"][1], door["b"][1]], color=color,
                lw=4.0, solid_capstyle="butt", zorder=4)
    for lamp in world["lamps"]:
        (x, y), on = lamp["center"], lamp["on"]
        style = dict(facecolor=LAMP_ON_FACE if on else "none",
                     edgecolor=LAMP_ON_EDGE if on else LAMP_OFF_EDGE, lw=0.8, zorder=1)
        if lamp["shape"] == "circular":
            ax.add_patch(Circle((x, y), lamp["extent"], **style))
        else:
            sx, sy = lamp["extent"]
            ax.add_patch(Rectangle((x - sx / 2, y - sy / 2), sx, sy, **style))
    for plate in world["plates"]:
        (x, y) = plate["center"]
        ax.plot([x], [y], marker="s", ms=5, color=PLATE_COLOR, zorder=5)
        if plate["room"] is not None:
            # The number sits on the corridor side of the plate, along its normal.
            nx, ny = plate["normal"] or (0.0, 0.0)
            ax.text(x + 0.3 * nx, y + 0.3 * ny, plain(plate["room"]), fontsize=7,
                    color=PLATE_COLOR, ha="center", va="center", clip_on=True, zorder=5)


def plan_figure(extent, handles, title, draw):
    """A figure of the plan over `extent` cut into panels (plan_panels) stacked top to bottom (or
    placed left to right), with equal axes in metres, `handles` as a legend on top and `title`;
    draw(ax) fills each panel. Returns the figure."""
    panels, stacked = plan_panels(extent)
    n = len(panels)
    (xlim, ylim) = panels[0]
    pw, ph = xlim[1] - xlim[0], ylim[1] - ylim[0]

    # Figure layout in inches: at most 16 in wide, each panel's axes at most 10 in high, sized
    # by the data's aspect ratio; the legend's rows on top.
    left, right, bottom, max_w, max_h = 0.7, 0.25, 0.55, 16.0, 10.0
    gap = 0.45 if stacked else 0.85  # side by side, the gap holds the tick labels
    if stacked:
        aw = max_w - left - right
        ah = min(aw * ph / pw, max_h)
        aw = ah * pw / ph
    else:
        aw = (max_w - left - right - (n - 1) * gap) / n
        ah = min(aw * ph / pw, max_h)
        aw = ah * pw / ph
    content_w = aw if stacked else n * aw + (n - 1) * gap
    width = max(8.0, left + right + content_w)
    x0 = left + (width - left - right - content_w) / 2  # centres narrow panels
    columns = max(2, min(len(handles), int(width / 2.2)))
    title_lines = title.count("\n") + 1
    top = 0.55 + 0.2 * (title_lines - 1) + 0.25 * math.ceil(len(handles) / columns)
    height = bottom + top + (n * ah + (n - 1) * gap if stacked else ah)
    fig = plt.figure(figsize=(width, height))
    for i, (xlim, ylim) in enumerate(panels):
        if stacked:
            rect = [x0, bottom + (n - 1 - i) * (ah + gap), aw, ah]
        else:
            rect = [x0 + i * (aw + gap), bottom, aw, ah]
        ax = fig.add_axes([rect[0] / width, rect[1] / height, rect[2] / width, rect[3] / height])
        draw(ax)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, lw=0.3, color="0.85")
        if stacked or i == 0:
            ax.set_ylabel("y [m]")
        if not stacked or i == n - 1:
            ax.set_xlabel("x [m]")

    fig.legend(handles=handles, loc="upper center", ncol=columns, frameon=False, fontsize=9,
               bbox_to_anchor=(0.5, 1.0 - (0.35 + 0.2 * (title_lines - 1)) / height))
    fig.suptitle(title, y=1.0 - 0.08 / height, va="top", fontsize=11)
    return fig


def world_handles(plate_label="door plate (room)"):
    """Legend entries of draw_world's plan."""
    handles = [Line2D([], [], color=WALL_COLOR, lw=2.0, label="wall")]
    for state, color in DOOR_COLORS.items():
        handles.append(Line2D([], [], color=color, lw=4.0, label=f"door {state}"))
    handles.append(Line2D([], [], ls="", marker="s", ms=5, color=PLATE_COLOR,
                          label=plate_label))
    handles.append(Circle((0, 0), 1, facecolor=LAMP_ON_FACE, edgecolor=LAMP_ON_EDGE,
                          label="lamp on"))
    handles.append(Circle((0, 0), 1, facecolor="none", edgecolor=LAMP_OFF_EDGE, label="lamp off"))
    return handles


def plot_trajectories(run, plots_dir, written):
    """trajectories.png: the true and estimated x-y paths (m) over the plan, equal axes; a long
    corridor is cut into panels stacked top to bottom (or placed left to right)."""
    extent = plan_extent(run)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]

    handles = [Line2D([], [], color="k", lw=1.6, marker="o", ms=5, label="ground truth (o start)")]
    for j, (name, p) in enumerate(run["pipelines"].items()):
        note = ", leaves the plot" if outside(p["trajectory"], extent) else ""
        handles.append(Line2D([], [], color=colors[j % len(colors)], lw=1.1, marker="x", ms=7,
                              label=f"{name} (x end{note})"))
    handles += world_handles()

    def draw(ax):
        draw_world(ax, run["world"])
        truth = run["truth"]
        ax.plot(truth[:, 1], truth[:, 2], color="k", lw=1.6, zorder=6)
        ax.plot(truth[:1, 1], truth[:1, 2], "o", color="k", ms=5, zorder=7)
        for j, p in enumerate(run["pipelines"].values()):
            tum = p["trajectory"]
            ax.plot(tum[:, 1], tum[:, 2], color=colors[j % len(colors)], lw=1.1, zorder=6)
            ax.plot(tum[-1:, 1], tum[-1:, 2], "x", color=colors[j % len(colors)], ms=7, mew=1.5,
                    zorder=7)

    fig = plan_figure(extent, handles, "Trajectories over the world plan (frame W, metres)", draw)
    save(fig, plots_dir, "trajectories.png", written)


def wrap_angle(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def plot_errors(name, errors, plots_dir, written):
    """errors_<name>.png: x, y (m) and heading (deg) error of the estimate minus the truth in
    the world frame against time (s), with the filter's +-2 sigma bounds, drawn as P3 Fig. 18."""
    t = errors["t"]
    rows = [("ex_m", "sigma_x_m", "x error [m]", 1.0),
            ("ey_m", "sigma_y_m", "y error [m]", 1.0),
            ("eyaw_rad", "sigma_yaw_rad", "heading error [deg]", 180.0 / math.pi)]
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    for ax, (column, sigma_column, label, scale) in zip(axes, rows):
        e = errors[column]
        if column == "eyaw_rad":
            e = wrap_angle(e)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.plot(t, e * scale, color="C0", lw=1.0, label="error")
        sigma = errors.get(sigma_column)
        if sigma is not None and np.isfinite(sigma).any():
            ax.plot(t, 2.0 * sigma * scale, color="C3", lw=0.9, ls="--", label="±2σ")
            ax.plot(t, -2.0 * sigma * scale, color="C3", lw=0.9, ls="--")
        ax.set_ylabel(label)
        ax.grid(True, lw=0.3, color="0.85")
    axes[0].legend(loc="upper left", fontsize=9)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{name}: pose error (estimate − truth, world frame) with ±2σ bounds")
    fig.tight_layout()
    save(fig, plots_dir, f"errors_{name}.png", written)


def plot_nees(name, errors, band, plots_dir, written):
    """nees_<name>.png: the pose NEES (3 dof, dimensionless) against time (s), the single-sample
    95 % chi-square band and the mean over the run. A log axis when NEES runs far above the band."""
    t, nees = errors["t"], errors["nees"]
    lo, hi = band if band is not None else chi2_95_bounds(NEES_DOF)
    finite = nees[np.isfinite(nees)]
    mean = float(finite.mean())
    inside = float(((finite >= lo) & (finite <= hi)).mean())
    fig, ax = plt.subplots(figsize=(10, 4.5))
    ax.axhspan(lo, hi, color="C2", alpha=0.15, lw=0)
    ax.axhline(lo, color="C2", lw=0.8, ls="--", label=f"95 % band [{lo:.4g}, {hi:.4g}]")
    ax.axhline(hi, color="C2", lw=0.8, ls="--")
    ax.plot(t, nees, color="C0", lw=0.9, label="NEES")
    ax.axhline(mean, color="C1", lw=1.2, label=f"mean {mean:.3g}")
    ax.axhline(NEES_DOF, color="0.4", lw=0.6, ls=":", label=f"expected {NEES_DOF}")
    if finite.max() > 3.0 * hi:
        ax.set_yscale("log")
        ax.set_ylim(bottom=max(min(finite[finite > 0].min(initial=lo), lo) * 0.5, 1e-6))
    else:
        ax.set_ylim(bottom=0.0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"NEES ({NEES_DOF} dof)")
    ax.grid(True, lw=0.3, color="0.85")
    ax.legend(loc="upper left", fontsize=9)
    ax.set_title(f"{name}: NEES, {100 * inside:.0f} % of {finite.size} samples inside the 95 % band")
    fig.tight_layout()
    save(fig, plots_dir, f"nees_{name}.png", written)


def plot_detectors(with_detectors, plots_dir, written):
    """detectors.png: precision, recall and accuracy (0-1) of each detector, one panel per
    pipeline."""
    n = len(with_detectors)
    widest = max(len(d) for _, d in with_detectors)
    fig, axes = plt.subplots(n, 1, figsize=(max(8.0, 1.6 * widest + 2.0), 3.2 * n + 0.6),
                             squeeze=False)
    bar = 0.8 / len(DETECTOR_SCORES)
    for ax, (name, detectors) in zip(axes[:, 0], with_detectors):
        x = np.arange(len(detectors))
        for k, score in enumerate(DETECTOR_SCORES):
            values = [d[score] for _, d in detectors]
            heights = [v if v is not None else 0.0 for v in values]
            bars = ax.bar(x + (k - 1) * bar, heights, bar, label=score, color=f"C{k}")
            ax.bar_label(bars, labels=["–" if v is None else f"{v:.2f}" for v in values],
                         fontsize=7, padding=1)
        ax.set_xticks(x, [d for d, _ in detectors])
        ax.set_ylim(0.0, 1.25)
        ax.set_ylabel("score")
        ax.set_title(name)
        ax.grid(True, axis="y", lw=0.3, color="0.85")
    axes[0, 0].legend(loc="upper right", fontsize=8, ncol=len(DETECTOR_SCORES))
    fig.tight_layout()
    save(fig, plots_dir, "detectors.png", written)


def plain(text):
    """Text drawn as it is: matplotlib reads '$...$' as mathtext, which a label may contain."""
    return str(text).replace("$", r"\$")


def ellipse_2sigma(covariance):
    """(width, height, angle_deg) in m of the 95 % ellipse (chi-square 2 dof) of the x-y block of a
    3x3 covariance (m^2), or None when that block has a null entry or is not positive
    semi-definite. Closed form for a symmetric 2x2 (the block symmetrised)."""
    a, b1, b2, d = covariance[0][0], covariance[0][1], covariance[1][0], covariance[1][1]
    if any(v is None for v in (a, b1, b2, d)):
        return None
    b = 0.5 * (b1 + b2)
    mean, half = 0.5 * (a + d), math.hypot(0.5 * (a - d), b)
    major, minor = mean + half, mean - half
    if minor < -1e-9 * max(abs(major), 1e-300):
        return None
    minor = max(minor, 0.0)
    angle = 0.5 * math.degrees(math.atan2(2.0 * b, a - d))
    scale = 2.0 * math.sqrt(CHI2_2DOF_95)
    return scale * math.sqrt(major), scale * math.sqrt(minor), angle


def in_extent(xy, extent):
    xmin, xmax, ymin, ymax = extent
    return xmin <= xy[0] <= xmax and ymin <= xy[1] <= ymax


def vanishing_point_text(landmark):
    """A legend line for a vanishing point: its bearing seen from the W origin (deg) with the
    2-sigma of that bearing (first order from the x-y covariance)."""
    x, y = landmark["position"][:2]
    bearing = math.atan2(y, x)
    c = landmark["covariance"]
    spread = ""
    if all(c[i][j] is not None for i in (0, 1) for j in (0, 1)) and x * x + y * y > 0:
        r2 = x * x + y * y
        jx, jy = -y / r2, x / r2  # d bearing / d (x, y)
        var = jx * jx * c[0][0] + jx * jy * (c[0][1] + c[1][0]) + jy * jy * c[1][1]
        if var >= 0:
            spread = f" ± {math.degrees(2.0 * math.sqrt(var)):.2f}° (2σ)"
    return (f"vanishing point #{landmark['id']} ({landmark['status']}): bearing "
            f"{math.degrees(bearing):.2f}°{spread} from the W origin")


def plot_landmarks(name, run, landmarks, plots_dir, written):
    """landmarks_<name>.png: the pipeline's final map over the plan (as trajectories.png): each
    landmark at its x-y estimate (m) with the 2-sigma ellipse of the x-y block of its covariance
    (chi-square 2 dof, 95 %), coloured by type, dashed while initialising; plates labelled with
    the room number read; a door's column points joined. Vanishing points lie ~1000 m away, so
    the legend lists them instead."""
    extent = plan_extent(run)
    trajectory = run["pipelines"][name]["trajectory"]
    on_plan = [lm for lm in landmarks if lm["type"] != "vanishing_point"]
    vps = [lm for lm in landmarks if lm["type"] == "vanishing_point"]
    many = len(on_plan) > 100
    no_ellipse = sum(1 for lm in on_plan for c in [lm["covariance"]] +
                     [p["covariance"] for p in lm["points"]] if ellipse_2sigma(c) is None)
    off_plan = sum(1 for lm in on_plan if not in_extent(lm["position"], extent))

    def marker_size(kind):
        return 2.0 if kind == "corner" else (4.0 if many else 5.0)

    handles = [Line2D([], [], color="0.55", lw=1.0, label="ground truth"),
               Line2D([], [], color="C0", lw=1.1, marker="x", ms=7, label=f"{name} (x end)")]
    for kind in LANDMARK_TYPES[:-1]:
        count = sum(1 for lm in on_plan if lm["type"] == kind)
        if count:
            handles.append(Line2D([], [], color=TYPE_COLORS[kind], lw=0.9, marker="o",
                                  ms=marker_size(kind) + 1, label=f"{kind} ({count})"))
    statuses = {lm["status"] for lm in landmarks}
    if "converged" in statuses:
        handles.append(Line2D([], [], color="0.3", lw=0.9, label="converged (solid)"))
    if "initializing" in statuses:
        handles.append(Line2D([], [], color="0.3", lw=0.9, ls="--",
                              label="initialising (dashed, hollow)"))
    for lm in vps[:MAX_LISTED_VPS]:
        handles.append(Line2D([], [], ls="", marker="*", ms=8, color=TYPE_COLORS[lm["type"]],
                              label=vanishing_point_text(lm)))
    if len(vps) > MAX_LISTED_VPS:
        handles.append(Line2D([], [], ls="", label=f"... and {len(vps) - MAX_LISTED_VPS} more "
                              "vanishing points"))
    handles += world_handles("true door plate (room)")

    def draw_point(ax, kind, status, xy, covariance, ms, lw):
        color = TYPE_COLORS[kind]
        dashed = status == "initializing"
        ax.plot([xy[0]], [xy[1]], ls="", marker="o", ms=ms, mew=0.8, color=color,
                markerfacecolor="none" if dashed else color, zorder=8)
        shape = ellipse_2sigma(covariance)
        if shape is not None:
            ax.add_patch(Ellipse(xy[:2], shape[0], shape[1], angle=shape[2], fill=False,
                                 edgecolor=color, lw=lw, ls="--" if dashed else "-", zorder=7))

    def draw(ax):
        draw_world(ax, run["world"])
        truth = run["truth"]
        ax.plot(truth[:, 1], truth[:, 2], color="0.55", lw=1.0, zorder=6)
        ax.plot(trajectory[:, 1], trajectory[:, 2], color="C0", lw=1.1, zorder=6)
        ax.plot(trajectory[-1:, 1], trajectory[-1:, 2], "x", color="C0", ms=7, mew=1.5, zorder=7)
        for lm in on_plan:
            kind, status = lm["type"], lm["status"]
            ms, lw = marker_size(kind), 0.4 if kind == "corner" else 0.9
            draw_point(ax, kind, status, lm["position"], lm["covariance"], ms, lw)
            if lm["points"]:
                xs = [p["position"][0] for p in lm["points"]]
                ys = [p["position"][1] for p in lm["points"]]
                ax.plot(xs, ys, color=TYPE_COLORS[kind], lw=0.8, zorder=7,
                        ls="--" if status == "initializing" else "-")
                for p in lm["points"]:
                    draw_point(ax, kind, status, p["position"], p["covariance"], 0.6 * ms, 0.6)
            if kind == "door_plate":
                ax.annotate(plain(lm["label"] or "?"), lm["position"][:2], xytext=(3, 3),
                            textcoords="offset points", fontsize=7, color=TYPE_COLORS[kind],
                            weight="bold", zorder=9)

    converged = sum(1 for lm in landmarks if lm["status"] == "converged")
    notes = [f"{len(landmarks)} landmarks ({converged} converged)"]
    if no_ellipse:
        notes.append(f"{no_ellipse} without an ellipse (covariance not positive semi-definite "
                     "or not finite)")
    if off_plan:
        notes.append(f"{off_plan} beyond the plan")
    title = (f"{name}: landmarks with 2σ ellipses (x-y covariance, χ² 2 dof 95 %: "
             f"√{CHI2_2DOF_95} σ), frame W, metres\n" + "; ".join(notes))
    fig = plan_figure(extent, handles, title, draw)
    save(fig, plots_dir, f"landmarks_{name}.png", written)


def plot_door_particles(name, run, doors, plots_dir, written):
    """doors_<name>.png: each registered door's particle cloud at registration (P3 Fig. 9), the
    two columns of every sample (x-y, m), and the door landmark's final columns joined, over the
    plan with the true doorways by state."""
    extent = plan_extent(run)
    truth = run["truth"]
    samples = sum(len(d["particles"]) for d in doors)
    handles = [Line2D([], [], color="0.55", lw=1.0, label="ground truth"),
               Line2D([], [], ls="", marker=".", ms=4, color="C1",
                      label="column a of a sample"),
               Line2D([], [], ls="", marker=".", ms=4, color="C4",
                      label="column b of a sample"),
               Line2D([], [], color=TYPE_COLORS["door"], lw=1.5, marker="o", ms=5,
                      label=f"door landmark, final columns ({len(doors)})")]
    handles += world_handles("true door plate (room)")

    def draw(ax):
        draw_world(ax, run["world"])
        ax.plot(truth[:, 1], truth[:, 2], color="0.55", lw=1.0, zorder=6)
        for door in doors:
            if door["particles"]:
                p = np.array(door["particles"])
                ax.plot(p[:, 0], p[:, 1], ls="", marker=".", ms=1.5, color="C1", alpha=0.5,
                        zorder=7)
                ax.plot(p[:, 2], p[:, 3], ls="", marker=".", ms=1.5, color="C4", alpha=0.5,
                        zorder=7)
            (xa, ya), (xb, yb) = door["columns"]
            ax.plot([xa, xb], [ya, yb], color=TYPE_COLORS["door"], lw=1.5, marker="o", ms=4,
                    zorder=8)
            ax.annotate(str(door["id"]), ((xa + xb) / 2, (ya + yb) / 2), xytext=(3, 3),
                        textcoords="offset points", fontsize=7, color=TYPE_COLORS["door"],
                        zorder=9)

    title = (f"{name}: door particle clouds at registration (P3 Fig. 9; {samples} samples of "
             f"{len(doors)} doors) and the doors' final columns, frame W, metres")
    save(plan_figure(extent, handles, title, draw), plots_dir, f"doors_{name}.png", written)


def plot_areas(name, run, areas, landmarks, plots_dir, written):
    """areas_<name>.png: the map divided at the doors (P2 Fig. 12): each room area's outline
    filled in its own colour, the point landmarks coloured by their area (the corridor grey),
    over the plan with the true rooms dotted."""
    extent = plan_extent(run)
    truth = run["truth"]
    position = {lm["id"]: lm["position"] for lm in landmarks}
    rooms = [a for a in areas if a["kind"] == "room"]
    corridor = sum(len(a["landmarks"]) for a in areas if a["kind"] == "corridor")
    colors = plt.get_cmap("tab10")

    def color_of(area):
        return "0.45" if area["kind"] == "corridor" else colors((area["id"] - 1) % 10)

    handles = [Line2D([], [], color="0.55", lw=1.0, label="ground truth"),
               Line2D([], [], ls="", marker="o", ms=4, color="0.45",
                      label=f"corridor landmark ({corridor})"),
               Line2D([], [], color="0.3", lw=0.8, ls=":", label="true room"),
               Rectangle((0, 0), 1, 1, facecolor=colors(0), alpha=0.25,
                         label=f"room area ({len(rooms)}) and its landmarks")]
    handles += world_handles("true door plate (room)")

    def draw(ax):
        draw_world(ax, run["world"])
        for door in run["world"]["doors"]:
            if door["footprint"] is not None:
                (x0, y0), (x1, y1) = door["footprint"]
                ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor="0.3",
                                       lw=0.8, ls=":", zorder=2))
        ax.plot(truth[:, 1], truth[:, 2], color="0.55", lw=1.0, zorder=6)
        for area in areas:
            c = color_of(area)
            if area["polygon"]:
                ax.add_patch(Polygon(area["polygon"], closed=True, facecolor=c, alpha=0.2,
                                     edgecolor=c, lw=1.0, zorder=2))
                x, y = area["polygon"][0]
                ax.annotate(f"room {area['id']}", (x, y), fontsize=7, color=c, zorder=9)
            xy = np.array([position[i][:2] for i in sorted(area["landmarks"]) if i in position])
            if len(xy):
                ax.plot(xy[:, 0], xy[:, 1], ls="", marker="o",
                        ms=2.0 if area["kind"] == "corridor" else 4.0, color=c, zorder=8)

    title = (f"{name}: the map divided at the doors (P2 Fig. 12): {len(rooms)} rooms, "
             "landmarks coloured by area, frame W, metres")
    save(plan_figure(extent, handles, title, draw), plots_dir, f"areas_{name}.png", written)


def score_bins(values):
    """Histogram bins for the scores: 30 over their range, log-spaced when they are positive and
    span more than three decades (Harris responses); (bins, log)."""
    lo, hi = float(values.min()), float(values.max())
    if lo > 0 and hi / lo > 1e3:
        return np.geomspace(lo, hi, 31), True
    if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1.0):
        return np.linspace(lo - 0.5, hi + 0.5, 31), False
    return np.linspace(lo, hi, 31), False


def plot_detections(name, detections, plots_dir, written):
    """detections_<name>.png: one row per detection type: u_px against time (s) coloured by the
    association (plates labelled with the room number read, hollow when none was read), the
    detections per frame over time, and the score of associated against unassociated detections
    where scores exist (a first precision-recall view)."""
    stamp = np.array(detections["stamp_s"])
    u = np.array(detections["u_px"])
    score = np.array(detections["score"])
    landmark_id = np.array(detections["landmark_id"])
    new = np.array(detections["new_landmark"], dtype=bool)
    kinds = np.array(detections["type"])
    cameras = np.array(detections["camera"])
    labels = detections["label"]
    present = [k for k in LANDMARK_TYPES if (kinds == k).any()]
    fig, axes = plt.subplots(len(present), 3, figsize=(16, 3.0 * len(present) + 0.8),
                             squeeze=False, gridspec_kw={"width_ratios": [3.0, 2.0, 1.6]})
    groups = [("associated", "C0", (landmark_id >= 0) & ~new),
              ("new landmark", "C2", new),
              ("not associated", "C3", landmark_id < 0)]
    for row, kind in zip(axes, present):
        raster, per_frame, scores = row
        of_kind = kinds == kind
        dense = of_kind.sum() > 2000
        names = sorted(set(cameras[of_kind]))
        markers = dict(zip(names, "os^Dv<>p"))  # beyond 8 cameras, all take the last marker
        for label, color, chosen in groups:
            for camera in names:
                sel = of_kind & chosen & (cameras == camera)
                if not sel.any():
                    continue
                read = np.array([bool(labels[i]) for i in np.flatnonzero(sel)])
                face = color if kind != "door_plate" else np.where(read, color, "none")
                raster.scatter(stamp[sel], u[sel], s=3 if dense else 12, marker=markers.get(
                    camera, "p"), facecolors=face, edgecolors=color, linewidths=0.6, label=(
                    f"{label} ({camera})" if len(names) > 1 else label), zorder=3)
        if kind == "door_plate":
            # The room number read for each plate track (label, landmark), at its first
            # detection; unread plates are the hollow markers.
            seen = set()
            for i in np.flatnonzero(of_kind):
                key = (labels[i], int(landmark_id[i]))
                if not labels[i] or key in seen or len(seen) == MAX_PLATE_ANNOTATIONS:
                    continue
                seen.add(key)
                color = "C3" if landmark_id[i] < 0 else "C0"
                raster.annotate(plain(labels[i]), (stamp[i], u[i]), xytext=(0, 5),
                                textcoords="offset points", fontsize=6, color=color,
                                rotation=90, ha="center", va="bottom")
        raster.set_ylabel(f"{kind}\nu [px] ({', '.join(plain(c) for c in names)})")
        raster.grid(True, lw=0.3, color="0.85")
        raster.legend(loc="upper right", fontsize=7, ncol=3)

        # Detections per frame (camera, stamp) with at least one detection of the type.
        frames = {}
        for i in np.flatnonzero(of_kind):
            total, associated = frames.get((stamp[i], cameras[i]), (0, 0))
            frames[(stamp[i], cameras[i])] = (total + 1, associated + (landmark_id[i] >= 0))
        keys = sorted(frames)
        t = np.array([k[0] for k in keys])
        per_frame.plot(t, [frames[k][0] for k in keys], ".", ms=3, color="0.35", label="all")
        per_frame.plot(t, [frames[k][1] for k in keys], ".", ms=3, color="C0",
                       label="associated")
        per_frame.set_ylabel("per frame")
        per_frame.set_ylim(bottom=0)
        per_frame.grid(True, lw=0.3, color="0.85")
        per_frame.legend(loc="upper right", fontsize=7)
        per_frame.set_title(f"{of_kind.sum()} in {len(keys)} frames (frames with one or more)",
                            fontsize=8)

        finite = of_kind & np.isfinite(score)
        if finite.any():
            bins, log = score_bins(score[finite])
            for label, color, chosen in [("associated", "C0", landmark_id >= 0),
                                         ("not associated", "C3", landmark_id < 0)]:
                values = score[finite & chosen]
                if values.size:
                    scores.hist(values, bins=bins, histtype="step", lw=1.2, color=color,
                                label=f"{label} ({values.size})")
            if log:
                scores.set_xscale("log")
            scores.set_xlabel(SCORE_NAMES[kind], fontsize=8)
            scores.set_ylabel("detections")
            scores.legend(loc="upper right", fontsize=7)
            scores.grid(True, lw=0.3, color="0.85")
        else:
            scores.axis("off")
            scores.text(0.5, 0.5, "no scores", ha="center", va="center", color="0.4",
                        transform=scores.transAxes)
    axes[-1, 0].set_xlabel("time [s]")
    axes[-1, 1].set_xlabel("time [s]")
    axes[0, 2].set_title("score: associated against not\n(a first precision-recall view)",
                         fontsize=8)
    fig.suptitle(f"{name}: detections by type ({len(stamp)} in all)")
    fig.tight_layout()
    save(fig, plots_dir, f"detections_{name}.png", written)


def plot_frame_time(name, frame_times, plots_dir, written):
    """frame_time_<name>.png (P1 Fig. 16): the cost of each front frame (ms) against the landmarks
    in the state, with the median per landmark count and the frame interval (the real-time
    budget), and both over time (s)."""
    t, n, ms = frame_times["stamp_s"], frame_times["landmarks"], frame_times["frame_ms"]
    fig, (by_count, by_time) = plt.subplots(1, 2, figsize=(14, 5))
    by_count.plot(n, ms, ".", ms=3, color="C0", alpha=0.6, label="frame")
    counts = np.unique(n)
    medians = [float(np.median(ms[n == c])) for c in counts]
    by_count.plot(counts, medians, color="C1", lw=1.3, label="median per landmark count")
    budget = float(np.median(np.diff(t))) * 1e3 if t.size > 1 else None
    if budget is not None:
        for ax in (by_count, by_time):
            ax.axhline(budget, color="C3", lw=0.9, ls="--",
                       label=f"frame interval {budget:.0f} ms (real time)")
    by_count.set_xlabel("landmarks in the state")
    by_count.set_ylabel("frame time [ms]")
    by_count.set_ylim(bottom=0)
    by_count.grid(True, lw=0.3, color="0.85")
    by_count.legend(loc="upper left", fontsize=8)
    by_time.plot(t, ms, color="C0", lw=0.8, label="frame time")
    by_time.set_xlabel("time [s]")
    by_time.set_ylabel("frame time [ms]")
    by_time.set_ylim(bottom=0)
    by_time.grid(True, lw=0.3, color="0.85")
    state = by_time.twinx()
    state.plot(t, n, color="C2", lw=1.2, label="landmarks in the state")
    state.set_ylabel("landmarks")
    state.set_ylim(bottom=0)
    lines = by_time.get_legend_handles_labels()
    extra = state.get_legend_handles_labels()
    by_time.legend(lines[0] + extra[0], lines[1] + extra[1], loc="upper left", fontsize=8)
    slow = int((ms > budget).sum()) if budget is not None else 0
    fig.suptitle(f"{name}: computation time per frame (P1 Fig. 16): {t.size} frames, mean "
                 f"{ms.mean():.1f} ms, max {ms.max():.1f} ms, {slow} over the frame interval, "
                 f"{int(n.max())} landmarks at most")
    fig.tight_layout()
    save(fig, plots_dir, f"frame_time_{name}.png", written)


def format_value(v):
    if v is None:
        return "–"
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, (int, float)):
        return f"{v:.4g}"
    return str(v)


def plot_summary(metrics, plots_dir, written):
    """summary.png: the main metrics per pipeline as a table, then each expectation with its
    measured value and PASS / FAIL."""
    names = list(metrics["pipelines"])
    rows = [(label, [metrics["pipelines"][p][key] for p in names]) for key, label in
            SUMMARY_METRICS if any(metrics["pipelines"][p][key] is not None for p in names)]
    expectations = metrics["expectations"]
    wrapped = [textwrap.wrap(e["text"], 95) or [""] for e in expectations]
    table_h = 0.3 * (len(rows) + 1) if rows else 0.0
    list_h = 0.22 * sum(len(w) for w in wrapped) + 0.12 * len(wrapped)
    height = 0.8 + table_h + (0.6 + list_h if expectations else 0.0)
    fig = plt.figure(figsize=(12, height))
    y = 1.0 - 0.25 / height  # running top edge, in figure fractions
    fig.text(0.02, y, "Run summary", fontsize=12, weight="bold", va="top")
    y -= 0.45 / height
    if rows:
        # Metric names in the first column (matplotlib's row labels get no width of their own).
        table_w = min(0.96, 0.25 + 0.14 * len(names))
        ax = fig.add_axes([0.02, y - table_h / height, table_w, table_h / height])
        ax.axis("off")
        label_w = 0.25 / table_w
        value_w = (1.0 - label_w) / len(names)
        table = ax.table(cellText=[[label] + [format_value(v) for v in values]
                                   for label, values in rows],
                         colLabels=["metric"] + names, colWidths=[label_w] + [value_w] * len(names),
                         cellLoc="center", bbox=[0.0, 0.0, 1.0, 1.0])
        table.auto_set_font_size(False)
        table.set_fontsize(9)
        for r in range(len(rows) + 1):
            table[r, 0].set_text_props(ha="left")
        y -= table_h / height + 0.3 / height
    if expectations:
        fig.text(0.02, y, "Expectations", fontsize=11, weight="bold", va="top")
        y -= 0.3 / height
        for e, lines in zip(expectations, wrapped):
            verdict = {True: ("PASS", "#1ea03c"), False: ("FAIL", "#d72828")}.get(
                e["passed"], ("?", "0.4"))
            fig.text(0.02, y, verdict[0], color=verdict[1], weight="bold", fontsize=9, va="top",
                     family="monospace")
            measured = "" if e["measured"] is None else f"   (measured {format_value(e['measured'])})"
            lines = list(lines)
            lines[-1] += measured
            for line in lines:
                fig.text(0.08, y, line, fontsize=9, va="top")
                y -= 0.22 / height
            y -= 0.12 / height
    save(fig, plots_dir, "summary.png", written)


def plot_run(run, plots_dir):
    """Draws every plot whose data is present; returns the paths written."""
    os.makedirs(plots_dir, exist_ok=True)
    written = []
    plot_trajectories(run, plots_dir, written)
    metrics = run["metrics"]
    for name, p in run["pipelines"].items():
        errors = p["errors"]
        if errors["t"].size == 0:
            continue
        plot_errors(name, errors, plots_dir, written)
        nees = errors.get("nees")
        if nees is not None and np.isfinite(nees).any():
            band = metrics["pipelines"].get(name, {}).get("nees_band")
            plot_nees(name, errors, band, plots_dir, written)
    for name, p in run["pipelines"].items():
        if p["landmarks"]:
            plot_landmarks(name, run, p["landmarks"], plots_dir, written)
        if p["doors"]:
            plot_door_particles(name, run, p["doors"], plots_dir, written)
        if p["areas"] and p["landmarks"] is not None:
            plot_areas(name, run, p["areas"], p["landmarks"], plots_dir, written)
        if p["detections"] is not None and p["detections"]["stamp_s"]:
            plot_detections(name, p["detections"], plots_dir, written)
        if p["frame_times"] is not None:
            plot_frame_time(name, p["frame_times"], plots_dir, written)
    with_detectors = [(name, m["detectors"]) for name, m in metrics["pipelines"].items()
                      if m["detectors"]]
    if with_detectors:
        plot_detectors(with_detectors, plots_dir, written)
    has_scalars = any(m[key] is not None for m in metrics["pipelines"].values()
                      for key, _ in SUMMARY_METRICS)
    if has_scalars or metrics["expectations"]:
        plot_summary(metrics, plots_dir, written)
    return written


def main(argv):
    parser = argparse.ArgumentParser(description="Writes RUN_DIR/plots/*.png for a finished "
                                     "`corridorsim run`.")
    parser.add_argument("run_dir", metavar="RUN_DIR")
    args = parser.parse_args(argv)
    try:
        run = read_run(args.run_dir)
    except InputError as e:
        print(f"plot_run: {e}", file=sys.stderr)
        return 1
    for path in plot_run(run, os.path.join(args.run_dir, "plots")):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
