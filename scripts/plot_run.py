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

# matplotlib and numpy: Debian's, under /usr/bin/python3 when the python3 that started this lacks
# them (system_python.py, beside this script).
sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import system_python  # noqa: E402

try:
    import matplotlib
    import numpy as np
except ImportError as missing:
    system_python.rerun_or_exit(__file__, missing, "plot_run")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the backend)
from matplotlib.lines import Line2D  # noqa: E402

# The strict readers of a run folder live in the corridorsim Python package (python/corridorsim/
# files.py); the names are re-exported here for the scripts that import plot_run. When the package
# is not on sys.path (a checkout's script run directly), the checkout's python/ folder is added.
system_python.use_corridorsim_with("files")
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

# The drawing beside this script: the plan (and save), the map plots, the detection plots.
from plot_detections import plot_detections, plot_frame_time  # noqa: E402
from plot_map import (ellipse_2sigma, plot_areas, plot_door_particles,  # noqa: E402,F401
                      plot_landmarks, vanishing_point_text)
from plot_plan import (draw_world, outside, plain, plan_extent, plan_figure,  # noqa: E402,F401
                       save, world_handles)


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


def plot_errors_and_nees(run, band_of, plots_dir, written):
    """errors_<pipeline>.png of every pipeline with error samples, and nees_<pipeline>.png where
    its NEES has a finite value, with the band `band_of(pipeline)` (None: the chi-square band)."""
    for name, p in run["pipelines"].items():
        errors = p["errors"]
        if errors["t"].size == 0:
            continue
        plot_errors(name, errors, plots_dir, written)
        nees = errors.get("nees")
        if nees is not None and np.isfinite(nees).any():
            plot_nees(name, errors, band_of(name), plots_dir, written)


def plot_run(run, plots_dir):
    """Draws every plot whose data is present; returns the paths written."""
    os.makedirs(plots_dir, exist_ok=True)
    written = []
    plot_trajectories(run, plots_dir, written)
    metrics = run["metrics"]
    plot_errors_and_nees(run, lambda name: metrics["pipelines"].get(name, {}).get("nees_band"),
                         plots_dir, written)
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


def write_plots(program, read, plot, plots_dir):
    """The plot commands' end: read() (InputError: `<program>: <file>:<line>: <what>` on stderr,
    exit 1), then plot(what was read, plots_dir), each path written printed; exit 0."""
    try:
        run = read()
    except InputError as e:
        print(f"{program}: {e}", file=sys.stderr)
        return 1
    for path in plot(run, plots_dir):
        print(path)
    return 0


def main(argv):
    parser = argparse.ArgumentParser(description="Writes RUN_DIR/plots/*.png for a finished "
                                     "`corridorsim run`.")
    parser.add_argument("run_dir", metavar="RUN_DIR")
    args = parser.parse_args(argv)
    return write_plots("plot_run", lambda: read_run(args.run_dir), plot_run,
                       os.path.join(args.run_dir, "plots"))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

