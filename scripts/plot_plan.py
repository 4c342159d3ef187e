"""plot_run.py's plan: the world drawn top-down (walls, doors, lamps, plates) in the colours of
worlds/map_plot.cpp's map.png, the plan's extent and its panels when a corridor is long, the
figure that holds them and the legend's world entries; and saving a figure without metadata. The
run plots (plot_run.py, plot_map.py, plot_detections.py) use it; plot_run.py chooses the
matplotlib backend before any of them is imported."""

import math
import os

import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Rectangle

# Plan colours, the same as worlds/map_plot.cpp draws map.png.
DOOR_COLORS = {"closed": "#d72828", "open": "#1ea03c", "empty": "#285adc"}
WALL_COLOR = "#37373c"
LAMP_ON_FACE, LAMP_ON_EDGE = "#ffd700", "#aa8200"
LAMP_OFF_EDGE = "#646464"
PLATE_COLOR = "#6a3d9a"

PANEL_MAX_ASPECT = 8.0  # a trajectories panel is at most 8 times longer than it is wide
PANEL_MAX_COUNT = 8
PANEL_OVERLAP_M = 0.5   # neighbouring panels share this much, so nothing hides at a cut
PLAN_MARGIN_M = 0.3
ESTIMATE_SLACK_M = 1.5  # how far beyond the world and the truth the plan grows for estimates
DPI = 100


def save(fig, plots_dir, name, written):
    """Writes the figure atomically (temporary file, then rename) and without metadata."""
    path = os.path.join(plots_dir, name)
    tmp = path + ".tmp"
    fig.savefig(tmp, format="png", dpi=DPI, metadata={"Software": None})
    os.replace(tmp, path)
    written.append(path)
    plt.close(fig)


def plain(text):
    """Text drawn as it is: matplotlib reads '$...$' as mathtext, which a label may contain."""
    return str(text).replace("$", r"\$")


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
