#!/usr/bin/python3
"""Plots of a finished `corridorsim study`: writes STUDY_DIR/plots/*.png.

    scripts/plot_study.py STUDY_DIR

Reads STUDY_DIR/summary.json (harness/study/study_summary.cpp, schema_version 1): `vary` (the swept
keys), `pipelines`, and `points`, each with its `id`, its `vary` values (YAML text) and per
pipeline the `values` per seed (`seed`, `ate_rmse_m`, ...; null where a run has none),
`metrics.ate_rmse_m` (mean and 95 % bootstrap CI over the seeds), `runs.diverged_seeds`, `nees`
(average, in_band_fraction) and `series` (the runs' statistics on a time grid: t in s, RMS
position error and sigma in m, mean x / y error in m, the average NEES with its band). Every key
but `points` and each point's `id` and `pipelines` may be absent: what it would draw is left out
(a panel says "no data"); nulls are skipped.

Writes (each printed on its own line; the names are fixed, report.md links them):
  ate_box.png          ATE RMSE over the seeds: one panel per sweep point, a box per pipeline
                       (quartiles, median, whiskers to 1.5 IQR), every seed as a dot (spread
                       sideways by a fixed sequence, no randomness; diverged runs in red) and the
                       mean with its 95 % bootstrap CI beside the box.
  error_over_time.png  the RMS over the runs of the planar position error against time, the mean
                       x and y errors, and the +-2 sigma band of the filter's RMS position sigma
                       (P3 Fig. 18 over seeds): a row per pipeline, a column per sweep point; x
                       shared, y shared within a row (a pipeline across the points).
  error_axes.png       P3 Fig. 18's layout over seeds: a row per axis (x, y, yaw), a column per
                       pipeline, the RMS error over the runs with +-2 times the RMS of the
                       filter's sigma on that axis; the first sweep point only (x shared).
  nis_over_time.png    only when a pipeline has landmark updates: per pipeline (first sweep
                       point) the mean NIS of each landmark type over time, the runs'
                       innovations pooled per time bin, with the 95 % band of that mean.
  nees.png             the average NEES over the runs against time with the 95 % band of the mean
                       of N chi-square(3) values, laid out as error_over_time.png; a log y axis
                       when a row's values span more than two decades.
  sweep.png            only with a sweep (`vary` not empty): a panel per swept key, the mean ATE
                       RMSE with its CI against the key's value, one line per pipeline (and per
                       combination of the other keys' values). Numeric values (Python float())
                       make a numeric axis, logarithmic when all are positive and span more than
                       a decade; other values are placed in sweep order as categories. Lines are
                       offset slightly in x so that their error bars stay apart.
  frame_times.png      only when the study has frame_times.csv (pipelines that record their cost
                       per frame: P1's): the median and 95th percentile time per camera frame
                       against the landmarks in the state, per pipeline (P1 Fig. 16 over seeds).
With many sweep points, ate_box.png shows at most 24 (in at most 6 rows, fewer columns when many
pipelines widen the panels) and the time plots at most 6, evenly spaced in sweep order (the
figure's title says so; summary.csv has every point). Pipelines are those of the top-level
`pipelines`, then any other a point names; one absent at a point leaves its place empty. Values
beyond 1e100 in magnitude (a diverged filter's) are skipped like nulls.

Exit status: 0 when the plots were written; 2 when STUDY_DIR or its summary.json is missing or
malformed (one line: `plot_study.py: <file>: <what>`, naming the key) or on a bad command line;
1 when matplotlib is missing or a plot cannot be written. summary.json is read and checked before
anything is drawn, so a bad input leaves no partial plots. The PNGs carry no software or date
metadata, so the same summary.json and matplotlib version give the same bytes.
"""

import argparse
import math
import os
import sys
import textwrap
import warnings

# matplotlib and numpy: Debian's, under /usr/bin/python3 when the python3 that started this lacks
# them (system_python.py, beside this script).
sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import system_python  # noqa: E402

PROG = "plot_study.py"
try:
    import matplotlib
    import numpy as np
except ImportError as missing:
    system_python.rerun_or_exit(__file__, missing, PROG)
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the backend)
import matplotlib.ticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

# summary.json and frame_times.csv read and checked (study_summary.py, beside this script).
from study_summary import (AXES, NEES_DOF, InputError, finite, read_frame_times,  # noqa: E402
                           read_summary)

# How much one figure shows.
MAX_BOX_POINTS = 24     # panels of ate_box.png
MAX_BOX_ROWS = 6
MAX_FIGURE_WIDTH = 28.0  # inches: ate_box.png takes fewer columns of wider panels
MAX_SERIES_POINTS = 6   # columns of error_over_time.png and nees.png
BOX_COLUMNS = 4
MAX_LEGEND_LINES = 30   # entries in a sweep panel's legend
LOG_DECADES = 2.0       # a y axis turns logarithmic when its values span more than this
DPI = 100
GRID = {"lw": 0.3, "color": "0.85"}


# ------------------------------------------------------------------------------------------------
# Drawing

def plain(text):
    """Text drawn as it is: matplotlib reads '$...$' as mathtext, which a name may contain."""
    return str(text).replace("$", r"\$")


def save(fig, plots_dir, name, written):
    """Writes the figure atomically (temporary file, then rename) and without metadata."""
    path = os.path.join(plots_dir, name)
    tmp = path + ".tmp"
    try:
        fig.savefig(tmp, format="png", dpi=DPI, metadata={"Software": None})
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.remove(tmp)
    written.append(path)


def pipeline_color(index, count):
    if count <= 10:
        return f"C{index}"
    return plt.get_cmap("tab20")(index % 20)


def point_label(point, width=None):
    """'p001: key = value, ...', wrapped to `width` characters."""
    text = point["id"]
    if point["vary"]:
        text += ": " + ", ".join(f"{k} = {v}" for k, v in point["vary"].items())
    text = plain(text)
    return "\n".join(textwrap.wrap(text, width)) if width else text


def shown_points(points, limit):
    """At most `limit` points, evenly spaced in sweep order (first and last included)."""
    if len(points) <= limit:
        return list(points)
    picks = sorted(set(int(round(i)) for i in np.linspace(0, len(points) - 1, limit)))
    return [points[i] for i in picks]


def subset_note(shown, points):
    if len(shown) == len(points):
        return ""
    return (f" ({len(shown)} of {len(points)} sweep points, evenly spaced; summary.csv has "
            "all)")


def wants_log(values):
    """True when the finite positive `values` span more than LOG_DECADES decades."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    return v.size >= 2 and math.log10(v.max()) - math.log10(v.min()) > LOG_DECADES


def y_from_zero(ax, values, headroom, empty):
    """The y axis of `values`: logarithmic when they span more than LOG_DECADES (wants_log), else
    from 0 to `headroom` times their largest; `empty` in the panel when there are none."""
    if wants_log(values):
        ax.set_yscale("log")
    elif values:
        ax.set_ylim(bottom=0.0, top=max(values) * headroom if max(values) > 0 else 1.0)
    else:
        no_data(ax, empty)


def no_data(ax, text="no data"):
    ax.text(0.5, 0.5, text, ha="center", va="center", color="0.4", transform=ax.transAxes)


def fmt(v, spec=".3g"):
    return "–" if v is None else format(v, spec)


def jitter(n, width):
    """n sideways offsets in [-width/2, width/2): the golden-ratio sequence (no randomness)."""
    return ((np.arange(n) * 0.6180339887498949) % 1.0 - 0.5) * width


def finish_layout(fig, title, handles):
    """The title on top, the figure's legend in rows under the panels (as many entries a row as
    the width takes), and the panels laid out between them."""
    height = fig.get_figheight()
    fig.suptitle(title, y=1.0 - 0.12 / height, va="top")
    ncol = max(1, min(len(handles), int(fig.get_figwidth() / 3.3)))
    rows = math.ceil(len(handles) / ncol)
    fig.legend(handles=handles, loc="lower center", ncol=ncol, fontsize=9, frameon=False)
    fig.tight_layout(rect=(0, (0.08 + 0.24 * rows) / height, 1, 1.0 - 0.5 / height))


def plot_ate_box(study, plots_dir, written):
    """ate_box.png: ATE RMSE over the seeds, a panel per sweep point, a box per pipeline."""
    names = study["pipelines"]
    panel_w = max(4.2, 0.95 * len(names) + 1.8)
    ncols = max(1, min(len(study["points"]), BOX_COLUMNS, int(MAX_FIGURE_WIDTH / panel_w)))
    points = shown_points(study["points"], min(MAX_BOX_POINTS, ncols * MAX_BOX_ROWS))
    nrows = math.ceil(len(points) / ncols)
    rotate = max(len(n) for n in names) > 12 if names else False
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel_w * ncols, 3.9 * nrows + 1.3),
                             squeeze=False)
    wrap = max(30, int(panel_w * 11))
    any_diverged = False
    for ax, point in zip(axes.flat, points):
        ticks, all_values = [], []
        for j, name in enumerate(names):
            p = point["pipelines"].get(name)
            if p is None:
                ticks.append(f"{plain(name)}\n(absent)")
                continue
            values, seeds = p["ate"], p["seeds"]
            finite = np.isfinite(values)
            nulls = int((~finite).sum())
            count = int(finite.sum())
            ticks.append(f"{plain(name)}\n{count} seed{'' if count == 1 else 's'}" +
                         (f", {nulls} null" if nulls else ""))
            if not finite.any():
                ax.text(j, 0.5, "no values", ha="center", va="center", color="0.4",
                        rotation=90, transform=ax.get_xaxis_transform())
                continue
            v = values[finite]
            all_values.extend(v.tolist())
            color = pipeline_color(j, len(names))
            ax.boxplot([v], positions=[j], widths=0.5, showfliers=False, manage_ticks=False,
                       patch_artist=True, zorder=2,
                       boxprops={"facecolor": "none", "edgecolor": "0.25"},
                       medianprops={"color": "0.1", "lw": 1.5},
                       whiskerprops={"color": "0.25"}, capprops={"color": "0.25"})
            diverged = np.array([s in p["diverged"] for s in seeds[finite]], dtype=bool)
            any_diverged |= bool(diverged.any())
            x = j + jitter(v.size, 0.42)
            ax.scatter(x[~diverged], v[~diverged], s=16, color=color, alpha=0.75,
                       edgecolors="none", zorder=3)
            if diverged.any():
                ax.scatter(x[diverged], v[diverged], s=26, facecolors="none",
                           edgecolors="#d72828", linewidths=1.2, zorder=3)
            mean = p["ate_mean"]
            if mean is not None:
                if p["ate_ci"] is not None:
                    lo, hi = p["ate_ci"]
                    yerr = [[max(mean - lo, 0.0)], [max(hi - mean, 0.0)]]
                    all_values.extend([lo, hi])
                else:
                    yerr = None
                ax.errorbar([j + 0.36], [mean], yerr=yerr, fmt="D", ms=5, color="k",
                            mfc="#ffb000", capsize=3, lw=1.0, zorder=4)
                all_values.append(mean)
        ax.set_xticks(range(len(names)), ticks, fontsize=8, rotation=30 if rotate else 0,
                      ha="right" if rotate else "center")
        ax.set_xlim(-0.6, len(names) - 0.4)
        y_from_zero(ax, all_values, 1.08, "no ATE values")
        ax.set_ylabel("ATE RMSE [m]")
        ax.set_title(point_label(point, wrap), fontsize=9)
        ax.grid(True, axis="y", **GRID)
    for ax in axes.flat[len(points):]:
        ax.axis("off")
    handles = [Line2D([], [], ls="", marker="o", color="0.45", ms=5, label="one seed"),
               Line2D([], [], color="0.1", lw=1.5, label="median; box: quartiles; "
                      "whiskers: 1.5 IQR"),
               Line2D([], [], ls="-", marker="D", ms=5, color="k", mfc="#ffb000",
                      label="mean with its 95 % bootstrap CI")]
    if any_diverged:
        handles.insert(1, Line2D([], [], ls="", marker="o", ms=6, mfc="none", mec="#d72828",
                                 label="diverged run"))
    finish_layout(fig, "ATE RMSE over the seeds, per pipeline" +
                  subset_note(points, study["points"]), handles)
    save(fig, plots_dir, "ate_box.png", written)


def series_grid(study, title_of, draw, plots_dir, name, written, suptitle, legend_handles,
                log_of=None):
    """A figure with a row per pipeline and a column per shown sweep point (named above its top
    panel); x shared by all panels, y within a row. title_of(pipeline, p) gives a panel's
    title; draw(ax, p) draws one panel and returns its y values (for log_of(axes, values), which
    sets a row's y axis) or None when it had nothing to draw."""
    names = study["pipelines"]
    points = shown_points(study["points"], MAX_SERIES_POINTS)
    nrows, ncols = len(names), len(points)
    panel_w = 10.0 if ncols == 1 else max(4.8, 16.0 / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel_w * ncols, 2.7 * nrows + 1.4),
                             squeeze=False, sharex=True)
    # y is shared within a row (one pipeline across the sweep points), never between pipelines:
    # dead reckoning's metres would flatten a SLAM pipeline's centimetres.
    row_values = [[] for _ in names]
    for col, point in enumerate(points):
        for row, pipeline in enumerate(names):
            ax = axes[row, col]
            if col > 0:
                ax.sharey(axes[row, 0])
            p = point["pipelines"].get(pipeline)
            values = None
            if p is None:
                no_data(ax, "pipeline absent at this point")
            elif p["series"] is None or p["series"]["t"].size == 0:
                no_data(ax, "no series" if p["finished"] != 0 else "no finished run")
            else:
                values = draw(ax, p)
                if values is None:
                    no_data(ax)
            if values is not None:
                row_values[row].extend(values)
            # The column's sweep point above its top panel; each panel names its pipeline.
            width = max(30, int(panel_w * 11))
            title = "\n".join(textwrap.wrap(title_of(pipeline, p), width))
            if row == 0:
                title = point_label(point, width) + "\n" + title
            ax.set_title(title, fontsize=9)
            ax.grid(True, **GRID)
            ax.tick_params(labelbottom=True)
            if row == nrows - 1:
                ax.set_xlabel("time [s]")
    if log_of is not None:
        for row in range(nrows):
            log_of([axes[row, col] for col in range(ncols)], row_values[row])
    finish_layout(fig, suptitle + subset_note(points, study["points"]), legend_handles)
    save(fig, plots_dir, name, written)


def plot_error_over_time(study, plots_dir, written):
    """error_over_time.png: per pipeline and point, the RMS over the runs of the planar position
    error (m) against time (s), the mean x and y errors, and +-2 sigma of the RMS position sigma."""

    def draw(ax, p):
        s = p["series"]
        t, err, sigma = s["t"], s["position_error_rms_m"], s["position_sigma_rms_m"]
        ex, ey = s["error_x_mean_m"], s["error_y_mean_m"]
        if not (np.isfinite(err).any() or np.isfinite(sigma).any()):
            return None
        ax.axhline(0.0, color="0.6", lw=0.6)
        if np.isfinite(sigma).any():
            ax.fill_between(t, -2.0 * sigma, 2.0 * sigma, color="C3", alpha=0.12, lw=0)
            ax.plot(t, 2.0 * sigma, color="C3", lw=0.9, ls="--")
            ax.plot(t, -2.0 * sigma, color="C3", lw=0.9, ls="--")
        ax.plot(t, ex, color="C1", lw=0.8)
        ax.plot(t, ey, color="C2", lw=0.8)
        ax.plot(t, err, color="C0", lw=1.5)
        ax.set_ylabel("position error [m]")
        return np.concatenate([err, 2.0 * sigma, -2.0 * sigma, ex, ey]).tolist()

    def title(pipeline, p):
        runs = "" if p is None or p["finished"] is None else f" ({p['finished']} runs)"
        return f"{plain(pipeline)}{runs}"

    handles = [Line2D([], [], color="C0", lw=1.5, label="RMS position error over the runs"),
               Line2D([], [], color="C1", lw=0.8, label="mean x error"),
               Line2D([], [], color="C2", lw=0.8, label="mean y error"),
               Patch(facecolor="C3", alpha=0.25, edgecolor="C3", ls="--",
                     label="±2σ, σ = RMS over the runs of √(σx² + σy²)")]
    series_grid(study, title, draw, plots_dir, "error_over_time.png", written,
                "Planar position error over time (estimate − truth, world frame) with the "
                "filter's ±2σ (P3 Fig. 18 over seeds)", handles)


def plot_error_axes(study, plots_dir, written):
    """error_axes.png: P3 Fig. 18's rows (x, y, yaw) per pipeline at the first point: the RMS
    error over the runs and +-2 RMS sigma of that axis."""
    point = study["points"][0]
    names = [n for n in study["pipelines"] if point["pipelines"].get(n) is not None]
    if not names:
        return
    fig, axes = plt.subplots(len(AXES), len(names), figsize=(4.6 * len(names) + 0.6, 7.8),
                             squeeze=False, sharex=True)
    for col, name in enumerate(names):
        p = point["pipelines"][name]
        for row, (axis, label) in enumerate(AXES):
            ax = axes[row, col]  # y not shared: dead reckoning's metres would flatten SLAM's
            s = p["series"]
            err = None if s is None else s[f"error_rms_{axis}"]
            if err is None or not np.isfinite(err).any():
                no_data(ax, "no series")
            else:
                t, sigma = s["t"], s[f"sigma_rms_{axis}"]
                ax.axhline(0.0, color="0.6", lw=0.6)
                ax.fill_between(t, -2.0 * sigma, 2.0 * sigma, color="C3", alpha=0.12, lw=0)
                ax.plot(t, 2.0 * sigma, color="C3", lw=0.9, ls="--")
                ax.plot(t, -2.0 * sigma, color="C3", lw=0.9, ls="--")
                ax.plot(t, err, color="C0", lw=1.3)
            if row == 0:
                runs = "" if p["finished"] is None else f" ({p['finished']} runs)"
                ax.set_title(plain(name) + runs, fontsize=9)
            if col == 0:
                ax.set_ylabel(label)
            if row == len(AXES) - 1:
                ax.set_xlabel("time [s]")
            ax.grid(True, **GRID)
    handles = [Line2D([], [], color="C0", lw=1.3, label="RMS error over the runs"),
               Patch(facecolor="C3", alpha=0.25, edgecolor="C3", ls="--",
                     label="±2σ, σ = RMS over the runs of the filter's σ on the axis")]
    finish_layout(fig, "Pose error per axis over time (P3 Fig. 18 over seeds)"
                  + ("" if len(study["points"]) == 1 else ", " + point_label(point, 60)), handles)
    save(fig, plots_dir, "error_axes.png", written)


def plot_nis(study, plots_dir, written):
    """nis_over_time.png, only when a pipeline has landmark updates: per pipeline at the first
    point, the mean NIS of each landmark type over time (innovations of all runs pooled per time
    bin) with the 95 % band of that mean."""
    point = study["points"][0]
    names = [n for n in study["pipelines"]
             if point["pipelines"].get(n) is not None and point["pipelines"][n]["nis"]]
    if not names:
        return
    fig, axes = plt.subplots(len(names), 1, figsize=(11, 2.8 * len(names) + 1.2), squeeze=False,
                             sharex=True)
    for row, name in enumerate(names):
        ax = axes[row, 0]
        for k, (kind, ns) in enumerate(sorted(point["pipelines"][name]["nis"].items())):
            colour = f"C{k % 10}"
            if ns["band_low"] is not None and ns["band_high"] is not None:
                ax.fill_between(ns["t"], ns["band_low"], ns["band_high"], color=colour,
                                alpha=0.12, lw=0, step="post")
            if ns["anis"] is not None:
                ax.step(ns["t"], ns["anis"], where="post", color=colour, lw=1.0,
                        label=f"{plain(kind)}: mean NIS, its 95 % band shaded")
        ax.set_title(plain(name), fontsize=9)
        ax.set_ylabel("mean NIS")
        ax.grid(True, **GRID)
        ax.legend(fontsize=8, loc="upper right")
        if row == len(names) - 1:
            ax.set_xlabel("time [s]")
    finish_layout(fig, "NIS per landmark type over time, the runs' innovations pooled per time "
                  "bin" + ("" if len(study["points"]) == 1 else ", " + point_label(point, 60)),
                  [])
    save(fig, plots_dir, "nis_over_time.png", written)


def plot_nees(study, plots_dir, written):
    """nees.png: per pipeline and point, the NEES averaged over the runs against time (s) with
    the 95 % band of the mean of N chi-square(dof) values."""
    dofs = sorted({p["nees_dof"] for point in study["points"]
                   for p in point["pipelines"].values()}) or [NEES_DOF]

    def draw(ax, p):
        s = p["series"]
        t, anees, lo, hi = s["t"], s["anees"], s["band_low"], s["band_high"]
        if not np.isfinite(anees).any():
            return None
        ax.fill_between(t, lo, hi, color="C2", alpha=0.18, lw=0)
        ax.plot(t, lo, color="C2", lw=0.7, ls="--")
        ax.plot(t, hi, color="C2", lw=0.7, ls="--")
        ax.axhline(p["nees_dof"], color="0.4", lw=0.7, ls=":")
        ax.plot(t, anees, color="C0", lw=1.3)
        ax.set_ylabel(f"average NEES ({p['nees_dof']} dof)")
        return np.concatenate([anees, lo, hi, [p["nees_dof"]]]).tolist()

    def title(pipeline, p):
        text = plain(pipeline)
        if p is not None:
            inside = None if p["nees_in_band"] is None else 100.0 * p["nees_in_band"]
            text += (f": average {fmt(p['nees_average'])}, {fmt(inside, '.0f')} % of the "
                     "times in the band")
        return text

    def log_of(axes, values):
        if wants_log(values):
            v = np.asarray(values, dtype=float)
            v = v[np.isfinite(v) & (v > 0)]
            for ax in axes:
                ax.set_yscale("log")
            axes[0].set_ylim(v.min() / 1.5, v.max() * 1.5)
        elif values:
            v = np.asarray(values, dtype=float)
            v = v[np.isfinite(v)]
            if v.size:
                axes[0].set_ylim(min(0.0, v.min()), v.max() * 1.08 if v.max() > 0 else 1.0)

    dof_text = "/".join(str(d) for d in dofs)
    handles = [Line2D([], [], color="C0", lw=1.3, label="NEES averaged over the runs"),
               Patch(facecolor="C2", alpha=0.3, edgecolor="C2", ls="--",
                     label=f"95 % band of the mean of N χ²({dof_text}) values"),
               Line2D([], [], color="0.4", lw=0.7, ls=":", label=f"expected value ({dof_text})")]
    series_grid(study, title, draw, plots_dir, "nees.png", written,
                "Average NEES of the pose (x, y, yaw) over time against its 95 % band", handles,
                log_of)


def as_number(text):
    """float(text) when it is a number within MAX_ABS_VALUE, else None."""
    try:
        return finite(float(text))
    except (TypeError, ValueError, OverflowError):
        return None


def plot_sweep(study, plots_dir, written):
    """sweep.png: a panel per swept key: the mean ATE RMSE (m) with its CI against the key's
    value, one line per pipeline and combination of the other keys' values."""
    keys, names, points = study["vary"], study["pipelines"], study["points"]
    fig, axes = plt.subplots(len(keys), 1, figsize=(12, 4.6 * len(keys)), squeeze=False)
    markers = "osD^vP*Xh<>p"
    styles = ["-", "--", "-.", ":"]
    for ax, key in zip(axes[:, 0], keys):
        others = [k for k in keys if k != key]
        texts = list(dict.fromkeys(pt["vary"][key] for pt in points))
        numbers = [as_number(v) for v in texts]
        numeric = all(v is not None for v in numbers)
        log_x = numeric and min(numbers) > 0 and max(numbers) / min(numbers) > 10.0
        x_of = dict(zip(texts, numbers)) if numeric else {v: i for i, v in enumerate(texts)}
        combos = list(dict.fromkeys(tuple(pt["vary"][k] for k in others) for pt in points))
        lines = [(j, name, combo) for j, name in enumerate(names) for combo in combos]
        # Sideways offsets so that the lines' error bars stay apart: together at most 20 % of
        # the smallest gap between two values (in decades on a log axis).
        positions = sorted(set(math.log10(v) if log_x else v for v in x_of.values()))
        gaps = np.diff(positions)
        unit = float(gaps.min()) if gaps.size else (1.0 if log_x or not numeric else
                                                    max(abs(positions[0]), 1.0))
        spread = min(0.03 * (len(lines) - 1), 0.2) * unit
        all_y = []
        for k, (j, name, combo) in enumerate(lines):
            shift = (k / (len(lines) - 1) - 0.5) * spread if len(lines) > 1 else 0.0
            xs, ys, lo, hi = [], [], [], []
            for pt in points:
                if tuple(pt["vary"][o] for o in others) != combo:
                    continue
                p = pt["pipelines"].get(name)
                if p is None or p["ate_mean"] is None:
                    continue
                x = x_of[pt["vary"][key]]
                x = x * 10.0 ** shift if log_x else x + shift
                mean = p["ate_mean"]
                ci = p["ate_ci"] if p["ate_ci"] is not None else (mean, mean)
                xs.append(x)
                ys.append(mean)
                lo.append(max(mean - ci[0], 0.0))
                hi.append(max(ci[1] - mean, 0.0))
                all_y.extend([mean, ci[0], ci[1]])
            if not xs:
                continue
            order = np.argsort(xs, kind="stable")
            xs, ys = np.array(xs)[order], np.array(ys)[order]
            yerr = np.array([lo, hi])[:, order]
            if len(names) > 1:
                color = pipeline_color(j, len(names))
                c = combos.index(combo)
                marker, style = markers[c % len(markers)], styles[(c // len(markers)) % 4]
            else:
                c = combos.index(combo)
                color, marker, style = pipeline_color(c, len(combos)), "o", "-"
            parts = [plain(name)] if len(names) > 1 or not others else []
            parts += [plain(f"{o} = {v}") for o, v in zip(others, combo)]
            label = ", ".join(parts) if k < MAX_LEGEND_LINES else None
            ax.errorbar(xs, ys, yerr=yerr, color=color, marker=marker, ls=style, ms=5, lw=1.2,
                        capsize=3, elinewidth=0.9, label=label)
        if log_x:
            ax.set_xscale("log")
        if not numeric:
            ax.set_xticks(range(len(texts)), [plain(v) for v in texts],
                          rotation=30 if len(texts) > 6 else 0,
                          ha="right" if len(texts) > 6 else "center")
            ax.set_xlim(-0.5, len(texts) - 0.5)
        elif len(texts) <= 12:  # each value its own labelled tick, as the sweep wrote it
            ax.set_xticks(numbers, [plain(v) for v in texts])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            if len(texts) == 1:
                v = numbers[0]
                ax.set_xlim(*((v / 10.0, v * 10.0) if log_x else (v - 1.0, v + 1.0)))
        y_from_zero(ax, all_y, 1.1, "no ATE means")
        ax.set_xlabel(plain(key) + ("" if numeric else " (sweep order)")
                      + (", log scale" if log_x else ""))
        ax.set_ylabel("ATE RMSE, mean over seeds [m]")
        against = f" for each value of {', '.join(plain(o) for o in others)}" if others else ""
        ax.set_title(f"mean ATE RMSE against {plain(key)}{against} (error bars: 95 % "
                     "bootstrap CI over the seeds)", fontsize=10)
        ax.grid(True, which="major", **GRID)
        if ax.get_legend_handles_labels()[0]:
            extra = len(lines) - MAX_LEGEND_LINES
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8,
                      title=f"{extra} more lines not listed" if extra > 0 else None,
                      title_fontsize=8)
    fig.suptitle("Sweep: mean ATE RMSE per pipeline against the swept values")
    fig.tight_layout()
    save(fig, plots_dir, "sweep.png", written)


def plot_frame_times(rows, plots_dir, written):
    """frame_times.png (P1 Fig. 16 over seeds): per pipeline (and point), the median time per
    camera frame against the landmarks in the state, with the 95th percentile; wall clock."""
    fig, ax = plt.subplots(figsize=(8.0, 4.8))
    series = {}
    for r in rows:
        series.setdefault((r["point"], r["pipeline"]), []).append(r)
    points = sorted({k[0] for k in series})
    for i, ((point, pipeline), rs) in enumerate(sorted(series.items())):
        x = [(r["low"] + r["high"]) / 2.0 for r in rs]
        label = plain(pipeline) + (f" ({point})" if len(points) > 1 else "")
        color = f"C{i % 10}"
        ax.plot(x, [r["median"] for r in rs], color=color, lw=1.5, marker="o", ms=3, label=label)
        ax.plot(x, [r["p95"] for r in rs], color=color, lw=0.8, ls="--")
    ax.plot([], [], color="0.4", lw=0.8, ls="--", label="95th percentile")
    ax.set_xlabel("landmarks in the state")
    ax.set_ylabel("time per camera frame [ms]")
    ax.grid(True, **GRID)
    ax.legend(fontsize=8)
    ax.set_title("Filter time per frame against the landmarks in the state (P1 Fig. 16 over "
                 "seeds; wall clock)", fontsize=10)
    fig.tight_layout()
    save(fig, plots_dir, "frame_times.png", written)


def plot_study(study, plots_dir, frame_times=None):
    """Draws every plot; returns the paths written."""
    os.makedirs(plots_dir, exist_ok=True)
    written = []
    plot_ate_box(study, plots_dir, written)
    plot_error_over_time(study, plots_dir, written)
    plot_error_axes(study, plots_dir, written)
    plot_nis(study, plots_dir, written)
    plot_nees(study, plots_dir, written)
    if study["vary"]:
        plot_sweep(study, plots_dir, written)
    if frame_times:
        plot_frame_times(frame_times, plots_dir, written)
    return written


def main(argv):
    parser = argparse.ArgumentParser(prog=PROG, description="Writes STUDY_DIR/plots/*.png for a "
                                     "finished `corridorsim study`.")
    parser.add_argument("study_dir", metavar="STUDY_DIR")
    args = parser.parse_args(argv)
    try:
        study = read_summary(args.study_dir)
        frame_times = read_frame_times(args.study_dir)
    except InputError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    plots_dir = os.path.join(args.study_dir, "plots")
    # Values near the limits of a double (a diverged filter's) overflow in matplotlib's tick
    # arithmetic: the plot is still drawn, so the warnings are left out.
    warnings.filterwarnings("ignore", category=RuntimeWarning)
    try:
        paths = plot_study(study, plots_dir, frame_times)
    except OSError as e:
        print(f"{PROG}: {e.filename or plots_dir}: cannot write: {e.strerror or e}",
              file=sys.stderr)
        return 1
    for path in paths:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

