#!/usr/bin/env python3
"""P3's comparison (Fig. 18) over many seeds: runs `corridorsim run SCENARIO --seed N` for each
seed (upward-camera SLAM) and checks the targets of P3's issue against the runs' own files.

    scripts/p3_study.py [--scenario scenarios/p3_lamps.yaml] [--seeds 1-10] [--out out/p3_study]
                        [--corridorsim build/bin/corridorsim] [--jobs 1] [--resume]

Writes OUT/seed_<N>/ (one run folder each, without plots) and OUT/study.json, and prints a table.
Per pipeline and seed it reads metrics.json (ATE RMSE and max, final position error, NEES; for
p3_upward also detection.lamp and data_association.<type>) and <pipeline>_errors.csv (the planar
position error hypot(ex_m, ey_m) and the NEES over time). The SLAM pipelines under test are the
runs' pipelines whose name starts with p2_ or p3_ (p3_upward, p3_corners, p2_upward when enabled).
Targets (exit 3 when one is missed, 2 on bad input, 1 when a run fails):
  - p3_upward's planar position error within 0.1 m over the whole run (its max over time) in at
    least 90 % of the seeds (at least ceil(0.9 N) of N seeds: 9 of 10);
  - p3_upward's ATE RMSE at most half of p3_corners' (mean over seeds);
  - p3_corners' ATE RMSE below odometry's (mean over seeds);
  - where the runs have doors: p3_upward's open-door precision >= 95 % and recall >= 80 % in
    every seed (map.door.open_precision, open_recall), no closed door and nothing but a door
    registered (closed_registered, non_door_registered 0 over every seed);
  - p3_upward's association precision >= 99 % for lamps and doors, where it made some;
  - for every SLAM pipeline, its average NEES (the mean over time of the NEES averaged over seeds)
    inside the 95 % chi-square band of N seeds' mean: [chi2(3N, 0.025) / N, chi2(3N, 0.975) / N].
Also reported (not targets): per pipeline the mean and max over seeds of ATE RMSE and final
position error, and the mean over seeds of the position error's RMSE along and across the robot's
true heading (from ground_truth.tum: in a corridor, the error along the track, which for an
upward camera only the wheels' distance sets, and the lateral error); for p3_upward the lamp
detector's recall, precision and centre error and the data association precision per landmark
type, each over the counts summed over every seed.
Standard library only.
"""
import json
import math
import os
import sys

from study_common import average_nees, nees_cell, run_all, study_arguments

PIPELINE = "p3_upward"
CORNERS = "p3_corners"
ODOMETRY = "odometry"
MAX_ERROR_M = 0.1  # p3_upward's position error bound over the whole run
SEED_FRACTION = (9, 10)  # ... in at least this fraction of the seeds (integer maths: no 0.9 * N)


def is_slam(name):
    return name.startswith("p2_") or name.startswith("p3_")


def read_truth_yaw(path):
    """ground_truth.tum (TUM: timestamp tx ty tz qx qy qz qw, planar): {timestamp text: yaw}."""
    yaw = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            cells = line.split()
            if not cells or cells[0].startswith("#") or len(cells) != 8:
                continue
            qz, qw = float(cells[6]), float(cells[7])
            yaw[cells[0]] = 2.0 * math.atan2(qz, qw)
    return yaw


def read_errors(path, truth_yaw):
    """<pipeline>_errors.csv: t, ex_m, ey_m, eyaw_rad, sigma_*, nees (empty while the covariance is
    singular, at the start). Returns the NEES series (nan where missing), the planar position
    error's max over time with its time, and the RMSE of its components along and across the
    robot's true heading (`truth_yaw`, read_truth_yaw; samples without a true pose are left out of
    those two): in a corridor, the error along the track and the lateral error."""
    nees = []
    max_error, max_t, samples = float("nan"), None, 0
    along2, across2, track_samples = 0.0, 0.0, 0
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        ct, cx, cy, cn = (header.index(k) for k in ("t", "ex_m", "ey_m", "nees"))
        for line in f:
            cells = line.strip().split(",")
            nees.append(nees_cell(cells, cn))
            if len(cells) > cy and cells[cx] not in ("", "nan") and cells[cy] not in ("", "nan"):
                ex, ey = float(cells[cx]), float(cells[cy])
                e = math.hypot(ex, ey)
                samples += 1
                if not e <= max_error:  # also takes the first sample (max_error nan)
                    max_error, max_t = e, float(cells[ct])
                yaw = truth_yaw.get(cells[ct])
                if yaw is not None:
                    along2 += (ex * math.cos(yaw) + ey * math.sin(yaw)) ** 2
                    across2 += (-ex * math.sin(yaw) + ey * math.cos(yaw)) ** 2
                    track_samples += 1
    return nees, {"max_position_error_m": max_error if samples else None,
                  "max_position_error_t_s": max_t, "error_samples": samples,
                  "along_track_rmse_m": (math.sqrt(along2 / track_samples) if track_samples
                                         else None),
                  "cross_track_rmse_m": (math.sqrt(across2 / track_samples) if track_samples
                                         else None)}


def finite_or_none(x):
    """JSON has no NaN: write null instead."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: finite_or_none(v) for k, v in x.items()}
    if isinstance(x, list):
        return [finite_or_none(v) for v in x]
    return x


def num(x, spec):
    return format(x, spec) if x is not None and math.isfinite(x) else "-"


def ratio(a, b):
    return a / b if b else None


def main(argv):
    args, seeds = study_arguments(argv, __doc__.split("\n")[0], "p3_study",
                                  "scenarios/p3_lamps.yaml", "out/p3_study")
    if seeds is None:
        return 2
    if not os.path.isfile(args.scenario):
        sys.stderr.write(f"p3_study: error: --scenario: no file '{args.scenario}'\n")
        return 2
    if not (os.path.isfile(args.corridorsim) and os.access(args.corridorsim, os.X_OK)):
        sys.stderr.write(f"p3_study: error: --corridorsim: no executable '{args.corridorsim}'\n")
        return 2
    os.makedirs(args.out, exist_ok=True)
    try:
        dirs = run_all(args, seeds, "p3_study", allow_extra_failure=True)
    except RuntimeError as e:
        sys.stderr.write(f"p3_study: error: {e}\n")
        return 1

    per_seed = {}
    nees_series = {}
    pipelines = None  # those of every seed, in the first seed's order
    for seed, d in dirs.items():
        with open(os.path.join(d, "metrics.json"), encoding="utf-8") as f:
            metrics = json.load(f)["pipelines"]
        row = {}
        truth_yaw = read_truth_yaw(os.path.join(d, "ground_truth.tum"))
        for name, m in metrics.items():
            row[name] = {k: m.get(k) for k in ("ate_rmse_m", "ate_max_m", "final_position_error_m",
                                               "nees_mean")}
            nees, errors = read_errors(os.path.join(d, f"{name}_errors.csv"), truth_yaw)
            row[name].update(errors)
            nees_series.setdefault(name, []).append(nees)
            if name == PIPELINE:
                if "detection" in m and "lamp" in m["detection"]:
                    row[name]["detection_lamp"] = m["detection"]["lamp"]
                if "data_association" in m:
                    row[name]["data_association"] = m["data_association"]
                if "map" in m and "door" in m["map"]:
                    row[name]["map_door"] = m["map"]["door"]
        per_seed[seed] = row
        names = list(metrics)
        pipelines = names if pipelines is None else [p for p in pipelines if p in names]
    for name in sorted(set(nees_series) - set(pipelines)):
        sys.stderr.write(f"p3_study: warning: {name} is not in every seed's run: left out\n")

    n = len(seeds)
    summary = {}
    for name in pipelines:
        def over_seeds(key):
            values = [per_seed[s][name][key] for s in seeds]
            if any(v is None for v in values):
                return None, None
            return sum(values) / n, max(values)
        ate_mean, ate_max = over_seeds("ate_rmse_m")
        final_mean, final_max = over_seeds("final_position_error_m")
        summary[name] = {
            "slam": is_slam(name),
            "ate_rmse_m": ate_mean,
            "ate_rmse_max_m": ate_max,
            "final_position_error_m": final_mean,
            "final_position_error_max_m": final_max,
            "max_position_error_m": over_seeds("max_position_error_m")[1],
            "along_track_rmse_m": over_seeds("along_track_rmse_m")[0],
            "cross_track_rmse_m": over_seeds("cross_track_rmse_m")[0],
            **average_nees(nees_series[name]),
        }

    if PIPELINE in summary:
        # Reported: the lamp detector and the data association over the counts of every seed.
        rows = [per_seed[s][PIPELINE] for s in seeds]
        lamps = [r["detection_lamp"] for r in rows if "detection_lamp" in r]
        if lamps:
            total = {k: sum(l.get(k) or 0 for l in lamps)
                     for k in ("detections", "true_positives", "false_positives", "false_negatives",
                               "ignored", "without_truth")}
            tp = total["true_positives"]
            # The centre error is over the true positives: weight each seed's by its count.
            weighted = [(l["true_positives"], l["mean_center_error_px"], l["rmse_center_error_px"])
                        for l in lamps if l.get("true_positives") and
                        l.get("mean_center_error_px") is not None]
            w = sum(c for c, _, _ in weighted)
            total.update({
                "seeds": len(lamps),
                "precision": ratio(tp, tp + total["false_positives"]),
                "recall": ratio(tp, tp + total["false_negatives"]),
                "mean_center_error_px": ratio(sum(c * m for c, m, _ in weighted), w),
                "rmse_center_error_px": (math.sqrt(sum(c * r * r for c, _, r in weighted) / w)
                                         if w else None),
            })
            summary[PIPELINE]["detection_lamp"] = total
        association = {}
        for r in rows:
            for kind, a in r.get("data_association", {}).items():
                t = association.setdefault(kind, {"seeds": 0, "associations": 0, "correct": 0,
                                                  "possible": 0, "unverifiable": 0})
                t["seeds"] += 1
                for k in ("associations", "correct", "possible", "unverifiable"):
                    # null in any seed (possible: for depth-verified corners) stays null
                    t[k] = t[k] + a[k] if t[k] is not None and a.get(k) is not None else None
        for kind, t in association.items():
            t["precision"] = (ratio(t["correct"], t["associations"])
                              if None not in (t["correct"], t["associations"]) else None)
            t["recall"] = (ratio(t["correct"], t["possible"])
                           if None not in (t["correct"], t["possible"]) else None)
        if association:
            summary[PIPELINE]["data_association"] = association
        doors = [r["map_door"] for r in rows if "map_door" in r]
        if doors:
            summary[PIPELINE]["map_door"] = {
                k: sum(d.get(k) or 0 for d in doors)
                for k in ("estimated", "open_registered", "closed_registered",
                          "non_door_registered", "duplicates", "open_seen", "open_found")}
            summary[PIPELINE]["map_door"]["seeds"] = len(doors)

    # Targets: each {passed, measured, required}; a pipeline the runs lack misses its targets.
    targets = {}

    def target(key, passed, measured, required):
        targets[key] = {"passed": bool(passed), "measured": measured, "required": required}

    need = -(-SEED_FRACTION[0] * n // SEED_FRACTION[1])  # ceil(0.9 n) without rounding errors
    if PIPELINE in summary:
        within = [s for s in seeds
                  if per_seed[s][PIPELINE]["max_position_error_m"] is not None
                  and per_seed[s][PIPELINE]["max_position_error_m"] <= MAX_ERROR_M]
        target("p3_upward_within_0_1_m_in_90_percent_of_seeds", len(within) >= need,
               f"{len(within)}/{n} seeds (worst {summary[PIPELINE]['max_position_error_m']:.3f} m)",
               f">= {need}/{n} seeds with max position error <= {MAX_ERROR_M} m")
    else:
        target("p3_upward_within_0_1_m_in_90_percent_of_seeds", False, f"no {PIPELINE} in the runs",
               f">= {need}/{n} seeds with max position error <= {MAX_ERROR_M} m")

    def ate(name):
        return summary[name]["ate_rmse_m"] if name in summary else None

    a, b = ate(PIPELINE), ate(CORNERS)
    target("p3_upward_ate_at_most_half_of_p3_corners",
           a is not None and b is not None and a <= 0.5 * b,
           f"{a:.4f} m vs {b:.4f} m (ratio {a / b:.3f})" if a is not None and b else
           f"missing: {PIPELINE} {a}, {CORNERS} {b}", "ratio <= 0.5")
    a, b = ate(CORNERS), ate(ODOMETRY)
    target("p3_corners_ate_below_odometry",
           a is not None and b is not None and a < b,
           f"{a:.4f} m vs {b:.4f} m" if a is not None and b is not None else
           f"missing: {CORNERS} {a}, {ODOMETRY} {b}", "below")
    # Doors and association (where the runs have them): open-door precision >= 95 % and recall
    # >= 80 % in every run (a run is one traversal), closed doors and furniture never registered,
    # association precision >= 99 % for lamps and doors.
    if PIPELINE in summary and "map_door" in summary[PIPELINE]:
        doors = {s: per_seed[s][PIPELINE].get("map_door") for s in seeds}
        bad = [s for s, d in doors.items() if d is None or d.get("open_precision") is None
               or d["open_precision"] < 0.95]
        target("p3_upward_open_door_precision_95_percent_per_run", not bad,
               f"worst {min((d or {}).get('open_precision') or 0 for d in doors.values()):.3f}"
               f" (seeds below: {bad})", ">= 0.95 in every seed")
        bad = [s for s, d in doors.items() if d is None or d.get("open_recall") is None
               or d["open_recall"] < 0.8]
        target("p3_upward_open_door_recall_80_percent_per_run", not bad,
               f"worst {min((d or {}).get('open_recall') or 0 for d in doors.values()):.3f}"
               f" (seeds below: {bad})", ">= 0.8 in every seed")
        t = summary[PIPELINE]["map_door"]
        target("p3_upward_no_closed_door_or_furniture_registered",
               t["closed_registered"] == 0 and t["non_door_registered"] == 0,
               f"closed {t['closed_registered']}, not a door {t['non_door_registered']}", "0 and 0")
    if PIPELINE in summary:
        for kind in ("lamp", "door"):
            a = summary[PIPELINE].get("data_association", {}).get(kind)
            if a and a["associations"]:
                target(f"p3_upward_{kind}_association_precision_99_percent",
                       a["precision"] is not None and a["precision"] >= 0.99,
                       f"{num(a['precision'], '.4f')} ({a['correct']}/{a['associations']})",
                       ">= 0.99")
    slam = [name for name in summary if summary[name]["slam"]]
    for name in [PIPELINE, CORNERS] + [p for p in slam if p not in (PIPELINE, CORNERS)]:
        key = f"{name}_average_nees_in_band"
        if name not in summary:
            target(key, False, f"no {name} in the runs", "inside the 95 % band")
            continue
        s = summary[name]
        low, high = s["nees_band"]
        target(key, low <= s["nees_average"] <= high, f"{s['nees_average']:.3f}",
               f"[{low:.3f}, {high:.3f}]")

    study = {"scenario": args.scenario, "seeds": seeds, "summary": summary, "targets": targets,
             "per_seed": {str(s): per_seed[s] for s in seeds}}
    with open(os.path.join(args.out, "study.json"), "w", encoding="utf-8") as f:
        json.dump(finite_or_none(study), f, indent=2)
        f.write("\n")

    print(f"{n} seed(s): {args.seeds}")
    print(f"{'pipeline':<12} {'ATE mean m':>10} {'ATE max m':>9} {'final mean':>10} "
          f"{'final max':>9} {'max err m':>9} {'avg NEES':>9} {'band':>15}")
    for name, s in summary.items():
        band = f"[{s['nees_band'][0]:.2f}, {s['nees_band'][1]:.2f}]"
        print(f"{name:<12} {num(s['ate_rmse_m'], '10.4f')} {num(s['ate_rmse_max_m'], '9.4f')} "
              f"{num(s['final_position_error_m'], '10.4f')} "
              f"{num(s['final_position_error_max_m'], '9.4f')} "
              f"{num(s['max_position_error_m'], '9.4f')} {num(s['nees_average'], '9.2f')} "
              f"{band if s['slam'] else '':>15}")
    print("error along / across the true track, RMSE (mean over seeds): " + ", ".join(
        f"{name} {num(s['along_track_rmse_m'], '.4f')} / {num(s['cross_track_rmse_m'], '.4f')} m"
        for name, s in summary.items()))
    if PIPELINE in summary and CORNERS in summary:
        a, b = summary[PIPELINE]["along_track_rmse_m"], summary[CORNERS]["ate_rmse_m"]
        if a is not None and b:
            print(f"{PIPELINE}'s error along the track alone is {a / b:.3f} of {CORNERS}' ATE RMSE "
                  f"(the ATE ratio's floor while that part stays)")
    if PIPELINE in summary:
        for s in seeds:
            r = per_seed[s][PIPELINE]
            print(f"seed {s}: {PIPELINE} ATE {num(r['ate_rmse_m'], '.4f')} m, max error "
                  f"{num(r['max_position_error_m'], '.4f')} m at t = "
                  f"{num(r['max_position_error_t_s'], '.2f')} s, final "
                  f"{num(r['final_position_error_m'], '.4f')} m, NEES {num(r['nees_mean'], '.2f')}")
        p3 = summary[PIPELINE]
        if "detection_lamp" in p3:
            l = p3["detection_lamp"]
            print(f"{PIPELINE} lamp detection ({l['seeds']} seed(s)): recall "
                  f"{num(l['recall'], '.4f')} ({l['true_positives']}/"
                  f"{l['true_positives'] + l['false_negatives']}), precision "
                  f"{num(l['precision'], '.4f')} ({l['true_positives']}/"
                  f"{l['true_positives'] + l['false_positives']}), centre error mean "
                  f"{num(l['mean_center_error_px'], '.3f')} px, rmse "
                  f"{num(l['rmse_center_error_px'], '.3f')} px")
        if "map_door" in p3:
            d = p3["map_door"]
            print(f"{PIPELINE} doors ({d['seeds']} seed(s)): {d['estimated']} registered, "
                  f"{d['open_registered']} open, {d['closed_registered']} closed, "
                  f"{d['non_door_registered']} not a door, {d['duplicates']} duplicates; open "
                  f"doors seen {d['open_seen']}, registered {d['open_found']}")
        for kind, t in p3.get("data_association", {}).items():
            print(f"{PIPELINE} data association {kind}: precision {num(t['precision'], '.4f')} "
                  f"({t['correct']}/{t['associations']} correct), recall "
                  f"{num(t['recall'], '.4f')}, unverifiable {t['unverifiable']}")
    for k, t in targets.items():
        print(f"target {k}: {'PASS' if t['passed'] else 'FAIL'}: {t['measured']} "
              f"(required {t['required']})")
    print(f"study: {os.path.join(args.out, 'study.json')}")
    return 0 if all(t["passed"] for t in targets.values()) else 3


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
