#!/usr/bin/python3
"""A synthetic run folder and study folder for the viewer's browser test (no corridorsim build
needed): what scripts/make_viewer.py and scripts/make_report.py would give, made up.

    tests/viewer/make_fixture.py OUT_DIR [--no-frames]

Writes OUT_DIR/run/ (ground_truth.tum, <pipeline>.tum, <pipeline>_cov.txt, viewer.html) and
OUT_DIR/study/ (report.html, runs/<point>/seed_<n>/viewer.html). The page data follows
docs/viewer.md; its numbers are rounded as there (1e-4 m and s, 1e-5 rad, 4 significant digits
for covariances, NEES, NIS and ms), the files keep full precision, so the test sees the same
rounding gap it sees on a real run. Odd data on purpose: a pipeline that failed part way, NaN gaps
in its errors, no nis / frame_ms / landmarks for it, camera stamps at 1/15 s.
"""

import argparse
import base64
import html
import io
import json
import math
import os
import random
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
VIEWER = os.path.normpath(os.path.join(HERE, "..", "..", "viewer"))
UPLOT = os.path.join(VIEWER, "node_modules", "uplot", "dist")


def sig(v, n=4):
    """v to n significant digits; None for NaN / inf (JSON has no NaN)."""
    if v is None or not math.isfinite(v):
        return None
    return float(f"{v:.{n - 1}e}")


def rnd(v, d):
    return None if v is None or not math.isfinite(v) else round(v, d)


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def fill(template, parts, data, title):
    """The template with its placeholder lines replaced, as scripts/make_viewer.py does."""
    with open(template, encoding="utf-8") as f:
        lines = f.read().split("\n")
    out = []
    for line in lines:
        key = line.strip()
        if key in parts:
            with open(parts[key], encoding="utf-8") as f:
                out.append(f.read())
        else:
            out.append(line)
    text = "\n".join(out)
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    text = text.replace("CORRIDORSIM_DATA_JSON", payload, 1)
    return text.replace("CORRIDORSIM_TITLE", html.escape(title), 1)


def centre_line(s):
    """A point at arc length s on a 30 x 10 m rectangular loop with rounded corners (r = 1 m)."""
    r, L1, L2 = 1.0, 28.0, 8.0
    arc = math.pi / 2 * r
    segs = [("line", (1, 0), (1, 0), L1), ("arc", (29, 1), -math.pi / 2, arc), ("line", (30, 1), (0, 1), L2),
            ("arc", (29, 9), 0, arc), ("line", (29, 10), (-1, 0), L1), ("arc", (1, 9), math.pi / 2, arc),
            ("line", (0, 9), (0, -1), L2), ("arc", (1, 1), math.pi, arc)]
    total = sum(q[3] for q in segs)
    s %= total
    for kind, a, b, length in segs:
        if s <= length:
            if kind == "line":
                return a[0] + b[0] * s, a[1] + b[1] * s, math.atan2(b[1], b[0])
            ang = b + s / r
            return a[0] + r * math.cos(ang), a[1] + r * math.sin(ang), ang + math.pi / 2
        s -= length
    return 1.0, 0.0, 0.0


def make_run(out, frames, rng):
    os.makedirs(out, exist_ok=True)
    duration, v = 90.0, 0.6
    truth = [(i * 0.01,) + centre_line(1.0 + v * i * 0.01) for i in range(int(duration / 0.01) + 1)]

    def truth_at(t):
        return truth[min(int(round(t / 0.01)), len(truth) - 1)][1:]

    def write_tum(name, rows):
        with open(os.path.join(out, name), "w") as f:
            f.write("# t tx ty tz qx qy qz qw\n")
            for t, x, y, yaw in rows:
                f.write(f"{t:.9f} {x:.9f} {y:.9f} 0.000000000 0 0 {math.sin(yaw / 2):.9f} {math.cos(yaw / 2):.9f}\n")

    write_tum("ground_truth.tum", [(t, x, y, yaw) for t, x, y, yaw in truth])

    pipelines = []
    specs = [("odometry", 0.02, None, 0.0), ("p1_demo", 1 / 15, None, 0.0), ("p2_broken", 0.1, 40.0, 0.0)]
    for name, dt, fail_at, _ in specs:
        n = int(((fail_at or duration) - 1e-9) / dt) + 1
        rows, cov = [], []
        ex = ey = eyaw = 0.0
        for k in range(n):
            t = k * dt
            tx, ty, tyaw = truth_at(t)
            if name == "odometry":
                eyaw += rng.gauss(0, 0.0004)
                ex += rng.gauss(0, 0.002) + 0.0008 * math.sin(eyaw * 30)
                ey += rng.gauss(0, 0.002)
                sx, sy, sxy, syaw = 0.02 + 0.004 * t, 0.02 + 0.003 * t, 0.3, 0.01 + 0.0006 * t
            else:
                ex = 0.97 * ex + rng.gauss(0, 0.01)
                ey = 0.97 * ey + rng.gauss(0, 0.008)
                eyaw = 0.97 * eyaw + rng.gauss(0, 0.002)
                sx, sy, sxy, syaw = 0.06 + 0.02 * math.sin(t / 7) ** 2, 0.04, -0.4, 0.012
                if name == "p2_broken" and t > 30:
                    ex += 0.01 * (t - 30)
            cxx, cyy, cxy = sx * sx, sy * sy, sxy * sx * sy
            rows.append((t, tx + ex, ty + ey, wrap(tyaw + eyaw)))
            cov.append((cxx, cxy, cyy, syaw * syaw))
        write_tum(f"{name}.tum", rows)
        with open(os.path.join(out, f"{name}_cov.txt"), "w") as f:
            f.write("# timestamp(s) tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33\n")
            for (t, x, y, yaw), (cxx, cxy, cyy, cyaw) in zip(rows, cov):
                f.write(f"{t:.9f} {x:.9f} {y:.9f} 0.0 0 0 {math.sin(yaw / 2):.9f} {math.cos(yaw / 2):.9f} "
                        f"1e-6 0 0 1e-6 0 {cyaw:.9e} {cxx:.9e} {cxy:.9e} 0 {cyy:.9e} 0 1e-6\n")
        pipelines.append((name, rows, cov, fail_at))

    # ---- the page data
    page = {
        "schema": 1, "title": "fixture_loop seed 7", "scenario": "fixture_loop", "seed": 7, "duration_s": duration,
        "world": {
            "bounds": [-2.5, -2.5, 32.5, 12.5],
            "walls": [[-1.2, -1.2, 31.2, -1.2], [31.2, -1.2, 31.2, 11.2], [31.2, 11.2, -1.2, 11.2], [-1.2, 11.2, -1.2, -1.2],
                      [1.2, 1.2, 12, 1.2], [13, 1.2, 28.8, 1.2], [28.8, 1.2, 28.8, 8.8], [28.8, 8.8, 1.2, 8.8], [1.2, 8.8, 1.2, 1.2]],
            "doors": [{"a": [12, 1.2], "b": [13, 1.2], "state": "open", "room": "104"},
                      {"a": [5, -1.2], "b": [6, -1.2], "state": "closed", "room": "101"},
                      {"a": [20, 11.2], "b": [21, 11.2], "state": "ajar", "room": None}],
            "plates": [{"center": [4.4, -1.2], "normal": [0, 1], "room": "101"},
                       {"center": [11.5, 1.2], "normal": [0, -1], "room": "104"},
                       {"center": [25, 11.2], "normal": None, "room": None}],
            "lamps": [{"center": [x, 0.0], "shape": "circular", "extent": 0.3, "on": x != 15} for x in (5, 10, 15, 20, 25)] +
                     [{"center": [30, 5], "shape": "panel", "extent": [0.6, 1.2], "on": True},
                      {"center": [15, 10], "shape": "panel", "extent": [1.2, 0.6], "on": False}],
            "distractors": [{"center": [8, 0.9], "class": "bin"}, {"center": [30.8, 7], "class": "fire_extinguisher"}],
        },
        "truth": {"t": [rnd(t, 4) for t, *_ in truth], "x": [rnd(x, 4) for _, x, _, _ in truth],
                  "y": [rnd(y, 4) for _, _, y, _ in truth], "yaw": [rnd(a, 5) for *_, a in truth]},
        "pipelines": [],
        "events": [{"t": 12.3, "type": "collision", "text": "bumped into bin (distractor 0)"},
                   {"t": 33.71, "type": "slip", "text": "left wheel slipped 0.04 m"},
                   {"t": 35.02, "type": "slip", "text": "right wheel slipped 0.02 m"},
                   {"t": 55.5, "type": "frame_dropped", "text": "front frame dropped"},
                   {"t": 40.0, "type": "pipeline_failed", "text": "p2_broken: NEES above 1e6 </script> <b>not bold</b>"}],
        "expectations": [{"text": "p1_demo.ate_rmse_m < 0.15", "measured": 0.0412, "passed": True},
                         {"text": "odometry.ate_rmse_m < 0.5", "measured": 0.81, "passed": False},
                         {"text": "p2_broken.failed == false", "measured": None, "passed": False}],
        "frames": {},
    }
    for name, rows, cov, fail_at in pipelines:
        t = [r[0] for r in rows]
        tt = [truth_at(x) for x in t]
        errs = {"t": [], "ex": [], "ey": [], "eyaw": [], "sx": [], "sy": [], "syaw": [], "nees": []}
        sq = []
        for (ti, x, y, yaw), (cxx, cxy, cyy, cyaw), (tx, ty, tyaw) in zip(rows, cov, tt):
            ex_, ey_, ea = x - tx, y - ty, wrap(yaw - tyaw)
            det = cxx * cyy - cxy * cxy
            nees = (cyy * ex_ * ex_ - 2 * cxy * ex_ * ey_ + cxx * ey_ * ey_) / det + ea * ea / cyaw
            gap = name == "p2_broken" and 20 <= ti <= 22
            errs["t"].append(rnd(ti, 4))
            for k, val in (("ex", ex_), ("ey", ey_), ("eyaw", ea), ("sx", math.sqrt(cxx)), ("sy", math.sqrt(cyy)),
                           ("syaw", math.sqrt(cyaw)), ("nees", nees)):
                val = float("nan") if gap else val
                errs[k].append(sig(val) if k == "nees" else rnd(val, 5 if k in ("eyaw", "syaw") else 4))
            sq.append(ex_ * ex_ + ey_ * ey_)
        ate = math.sqrt(sum(sq) / len(sq))
        p = {
            "name": name, "failed": "diverged: NEES above 1e6 at t = 40 s" if fail_at else None,
            "path": {"t": [rnd(x, 4) for x in t], "x": [rnd(r[1], 4) for r in rows], "y": [rnd(r[2], 4) for r in rows],
                     "yaw": [rnd(r[3], 5) for r in rows],
                     "cxx": [sig(c[0]) for c in cov], "cxy": [sig(c[1]) for c in cov], "cyy": [sig(c[2]) for c in cov]},
            "truth_at": {"x": [rnd(a[0], 4) for a in tt], "y": [rnd(a[1], 4) for a in tt], "yaw": [rnd(a[2], 5) for a in tt]},
            "errors": errs, "nees_band": [0.2158, 9.348],
            "metrics": {"ate_rmse_m": round(ate, 6), "ate_aligned_rmse_m": round(ate * 0.7, 6),
                        "rpe_1m_trans_rmse_m": round(ate * 0.2, 6), "final_position_error_m": round(math.sqrt(sq[-1]), 6),
                        "nees_mean": 3.1, "nees_in_band_fraction": 0.91, "samples": len(rows),
                        "alignment": {"x_m": 0.01, "y_m": -0.02, "yaw_rad": 0.001}, "health": {"rejected_updates": 3}},
        }
        if name == "p1_demo":
            nt, nv, na = [], [], []
            for k in range(0, len(t), 3):
                for _ in range(2):
                    nt.append(rnd(t[k], 4)); nv.append(sig(rng.chisquare(2) if hasattr(rng, "chisquare") else rng.expovariate(0.5)))
                    na.append(1 if nv[-1] < 12 else 0)
            p["nis"] = {"corner": {"dof": 2, "band": [0.0506, 7.378], "t": nt, "nis": nv, "accepted": na},
                        "plate": {"dof": 2, "band": [0.0506, 7.378], "t": nt[::4], "nis": [sig(v * 1.5) for v in nv[::4]],
                                  "accepted": na[::4]}}
            p["frame_ms"] = {"t": [rnd(x, 4) for x in t], "ms": [sig(4 + 3 * rng.random() + 0.05 * k ** 0.5) for k in range(len(t))],
                             "landmarks": [min(40, k // 20) for k in range(len(t))]}
            p["landmarks"] = [
                {"id": 1, "type": "plate", "status": "converged", "label": "101", "x": 4.45, "y": -1.15, "cxx": 0.004, "cxy": 0.001,
                 "cyy": 0.002, "first_seen": 4.0, "truth": [4.4, -1.2], "wrong": False},
                {"id": 2, "type": "corner", "status": "initializing", "label": "c2", "x": 12.1, "y": 1.3, "cxx": 0.02, "cxy": 0.0,
                 "cyy": 0.05, "first_seen": 15.0, "truth": [12.0, 1.2], "wrong": False},
                {"id": 3, "type": "plate", "status": "converged", "label": "107", "x": 11.6, "y": 1.1, "cxx": 0.003, "cxy": -0.001,
                 "cyy": 0.003, "first_seen": 17.5, "truth": [11.5, 1.2], "wrong": True},
                {"id": 4, "type": "lamp", "status": "converged", "label": "", "x": 10.05, "y": 0.02, "cxx": 0.001, "cxy": 0.0,
                 "cyy": 0.001, "first_seen": None, "truth": None, "wrong": False},
            ]
            p["detections"] = []
        else:
            p["frame_ms"] = None
        page["pipelines"].append(p)

    if frames:
        from PIL import Image, ImageDraw
        scale = 0.25
        ft, jp = [], []
        for k in range(0, int(duration / 0.4)):
            tf = round(6 * k / 15, 9)  # a p1_demo stamp
            img = Image.new("RGB", (160, 120), (40, 42, 48))
            d = ImageDraw.Draw(img)
            d.polygon([(0, 120), (60, 60), (100, 60), (160, 120)], fill=(90, 90, 95))
            d.rectangle([60, 30, 100, 60], outline=(200, 200, 200))
            d.text((4, 4), f"t={tf:.2f}", fill=(255, 255, 0))
            buf = io.BytesIO()
            img.save(buf, "JPEG", quality=70)
            ft.append(rnd(tf, 4))
            jp.append(base64.b64encode(buf.getvalue()).decode("ascii"))
            dets = page["pipelines"][1]["detections"]
            dets.append({"t": rnd(tf, 4), "camera": "front", "type": "plate", "u": 320.0, "v": 180.0,
                         "box": [280.0 + k % 20, 150.0, 360.0 + k % 20, 200.0], "label": "101", "landmark": 1})
            dets.append({"t": rnd(tf, 4), "camera": "front", "type": "corner", "u": 240.0 + 3 * (k % 30), "v": 240.0,
                         "box": None, "label": "", "landmark": -1})
        page["frames"] = {"front": {"width": 160, "height": 120, "scale": scale, "t": ft, "jpeg": jp}}

    parts = {"/*CORRIDORSIM_UPLOT_CSS*/": os.path.join(UPLOT, "uPlot.min.css"),
             "/*CORRIDORSIM_VIEWER_CSS*/": os.path.join(VIEWER, "viewer.css"),
             "/*CORRIDORSIM_UPLOT_JS*/": os.path.join(UPLOT, "uPlot.iife.min.js"),
             "/*CORRIDORSIM_VIEWER_JS*/": os.path.join(VIEWER, "viewer.js")}
    with open(os.path.join(out, "viewer.html"), "w", encoding="utf-8") as f:
        f.write(fill(os.path.join(VIEWER, "viewer.html"), parts, page, page["title"]))
    return page


def make_study(out, run_page, rng):
    os.makedirs(out, exist_ok=True)
    pipelines = ["p1_demo", "odometry"]
    metrics = [{"name": "ate_rmse_m", "unit": "m"}, {"name": "rpe_1m_trans_rmse_m", "unit": "m"},
               {"name": "nees_mean", "unit": ""}]
    lamp = [0.25, 0.5, 1.0]
    points = [{"id": f"p{i:03d}", "label": f"lamps.on_fraction={v}", "values": {"lamps.on_fraction": v}} for i, v in enumerate(lamp)]
    runs, summary, paired, series = [], [], [], {}
    for pt, v in zip(points, lamp):
        per = {p: {m["name"]: [] for m in metrics} for p in pipelines}
        for seed in range(1, 7):
            status, reason = "finished", None
            if pt["id"] == "p001" and seed == 3:
                status, reason = "diverged", "p1_demo NEES above 1e6 at t = 61.2 s"
            if pt["id"] == "p002" and seed == 5:
                status, reason = "timeout", "wall clock above 600 s"
            rel = f"runs/{pt['id']}/seed_{seed}/viewer.html"
            mets = {}
            if status != "timeout":
                for p in pipelines:
                    base = 0.05 + 0.1 / v if p == "p1_demo" else 0.6
                    mets[p] = {"ate_rmse_m": round(base * (1 + 0.3 * rng.random()), 4),
                               "rpe_1m_trans_rmse_m": round(base * 0.2 * (1 + rng.random()), 4),
                               "nees_mean": round(2 + 3 * rng.random(), 3) if status == "finished" else None}
                    for m in metrics:
                        if mets[p][m["name"]] is not None:
                            per[p][m["name"]].append(mets[p][m["name"]])
            runs.append({"point": pt["id"], "seed": seed, "status": status, "reason": reason,
                         "viewer": None if status == "timeout" else rel, "metrics": mets})
            if status != "timeout":
                d = os.path.join(out, os.path.dirname(rel))
                os.makedirs(d, exist_ok=True)
                with open(os.path.join(out, rel), "w") as f:
                    f.write("<!DOCTYPE html><title>run</title><p>a run's viewer</p>\n")
        for p in pipelines:
            for m in metrics:
                xs = sorted(per[p][m["name"]])
                if not xs:
                    continue
                mean = sum(xs) / len(xs)
                std = math.sqrt(sum((x - mean) ** 2 for x in xs) / max(len(xs) - 1, 1))
                summary.append({"point": pt["id"], "pipeline": p, "metric": m["name"], "n": len(xs), "mean": mean, "std": std,
                                "median": xs[len(xs) // 2], "p95": xs[-1], "min": xs[0], "max": xs[-1],
                                "ci_low": mean - 1.96 * std / math.sqrt(len(xs)), "ci_high": mean + 1.96 * std / math.sqrt(len(xs))})
        for m in metrics[:2]:
            a, b = per["p1_demo"][m["name"]], per["odometry"][m["name"]]
            n = min(len(a), len(b))
            diffs = [x - y for x, y in zip(a, b)][:n]
            md = sum(diffs) / n
            sd = math.sqrt(sum((x - md) ** 2 for x in diffs) / max(n - 1, 1))
            paired.append({"point": pt["id"], "a": "p1_demo", "b": "odometry", "metric": m["name"], "n": n, "diff": md,
                           "diff_ci_low": md - 2.57 * sd / math.sqrt(n), "diff_ci_high": md + 2.57 * sd / math.sqrt(n),
                           "ratio": sum(a) / sum(b), "p_sign": 0.031, "p_wilcoxon": 0.028})
        series[pt["id"]] = {}
        for p in pipelines:
            ts = [i * 0.5 for i in range(181)]
            grow = 0.004 if p == "odometry" else 0.0
            series[pt["id"]][p] = {"t": ts, "error_mean": [0.05 / v * (1 + 0.2 * math.sin(t / 5)) + grow * t for t in ts],
                                   "error_2sigma": [0.1 / v + 2 * grow * t for t in ts],
                                   "nees_mean": [2.5 + math.sin(t / 9) + (3 if p == "odometry" and t > 60 else 0) for t in ts],
                                   "nees_band": [2.6, 3.4]}
    data = {"schema": 1, "title": "lamps study (fixture)", "study": "lamps_fixture",
            "command": "corridorsim study scenarios/lamps.yaml --seeds 1..6 --out out/lamps",
            "pipelines": pipelines, "metrics": metrics, "points": points, "runs": runs, "summary": summary, "paired": paired,
            "series": series, "sweep": {"keys": ["lamps.on_fraction"], "values": {p["id"]: p["values"] for p in points}},
            "expectations": [{"text": "p1_demo beats odometry on ate_rmse_m at every point", "measured": 3, "passed": True},
                             {"text": "no run diverges", "measured": 1, "passed": False}]}
    parts = {"/*CORRIDORSIM_UPLOT_CSS*/": os.path.join(UPLOT, "uPlot.min.css"),
             "/*CORRIDORSIM_VIEWER_CSS*/": os.path.join(VIEWER, "viewer.css"),
             "/*CORRIDORSIM_UPLOT_JS*/": os.path.join(UPLOT, "uPlot.iife.min.js"),
             "/*CORRIDORSIM_REPORT_JS*/": os.path.join(VIEWER, "report.js")}
    with open(os.path.join(out, "report.html"), "w", encoding="utf-8") as f:
        f.write(fill(os.path.join(VIEWER, "report.html"), parts, data, data["title"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--no-frames", action="store_true")
    a = ap.parse_args()
    rng = random.Random(7)
    shutil.rmtree(a.out, ignore_errors=True)
    page = make_run(os.path.join(a.out, "run"), not a.no_frames, rng)
    if os.path.exists(os.path.join(VIEWER, "report.html")):
        make_study(os.path.join(a.out, "study"), page, rng)
    print(a.out)


if __name__ == "__main__":
    sys.exit(main())
