"""plot_run.py's plots of a pipeline's detections and frame times: detections_<pipeline>.png
(per detection type: u_px against time, detections per frame, the score of associated against
unassociated detections) and frame_time_<pipeline>.png (frame time against the landmarks in the
state and over time, P1 Fig. 16)."""

import matplotlib.pyplot as plt
import numpy as np

from corridorsim.files import LANDMARK_TYPES
from plot_plan import plain, save

SCORE_NAMES = {"door_plate": "SVM margin", "corner": "Harris response",
               "vanishing_point": "line count", "door": "score", "lamp": "score"}
MAX_PLATE_ANNOTATIONS = 80  # labelled plate tracks in detections_<pipeline>.png


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
