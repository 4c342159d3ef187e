"""plot_run.py's plots of a pipeline's map over the plan (plot_plan.py): landmarks_<pipeline>.png
(each landmark with its 2-sigma ellipse, coloured by type, plates with their room number,
vanishing points in the legend), doors_<pipeline>.png (the door particle clouds at registration,
P3 Fig. 9) and areas_<pipeline>.png (the map divided at the doors, P2 Fig. 12)."""

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Ellipse, Polygon, Rectangle

from corridorsim.files import LANDMARK_TYPES
from plot_plan import draw_world, plain, plan_extent, plan_figure, save, world_handles

# The colours of the landmark and detection types; the true plates keep PLATE_COLOR.
TYPE_COLORS = {"door_plate": "#e6550d", "door": "#8c564b", "lamp": "#e91e63", "corner": "#17a2b8",
               "vanishing_point": "#7f7f7f"}
CHI2_2DOF_95 = 5.991  # 95 % quantile of chi-square with 2 dof: the ellipse is sqrt(5.991) sigma
MAX_LISTED_VPS = 6         # vanishing points listed in the legend of landmarks_<pipeline>.png


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
