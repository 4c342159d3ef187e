#!/usr/bin/env python3
"""P1's comparison (Figs. 15-16) over many seeds: runs `corridorsim run SCENARIO --seed N` for
each seed and checks the targets of P1's issue against the runs' own files.

    scripts/p1_study.py [--scenario scenarios/default.yaml] [--seeds 1-10] [--out out/p1_study]
                        [--corridorsim build/bin/corridorsim] [--jobs 1] [--resume]

Writes OUT/seed_<N>/ (one run folder each, without plots) and OUT/study.json, and prints a table.
Per pipeline and seed it reads metrics.json (ATE RMSE, final position error, NEES) and
<pipeline>_errors.csv (NEES over time); for p1_vp_doorplate also <pipeline>_landmarks.json against
world.json's plates. Targets (exit 3 when one is missed, 2 on bad input, 1 when a run fails):
  - p1_vp_doorplate's ATE RMSE at most half of odometry's and below p1_harris's (mean over seeds);
  - its mean final position error at most 0.15 m;
  - its average NEES (the mean over time of the NEES averaged over seeds) inside the 95 %
    chi-square band of N seeds' mean: [chi2(3N, 0.025) / N, chi2(3N, 0.975) / N];
  - every plate of the world in its semantic map with the right number, within 0.2 m, in every
    seed; no landmark with a number the world does not have (a false plate).
Also reported (not a target): the plates' own NEES over their x-y covariance, averaged over every
plate of every seed, against the 95 % band of the mean of that many chi-square(2) values.
Standard library only.
"""
import json
import math
import os
import sys

from study_common import average_nees, chi2_quantile, nees_cell, run_all, study_arguments

PIPELINE = "p1_vp_doorplate"


def read_nees(path):
    values = []
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        column = header.index("nees")
        for line in f:
            values.append(nees_cell(line.strip().split(","), column))
    return values


def plate_check(run_dir):
    with open(os.path.join(run_dir, "world.json"), encoding="utf-8") as f:
        world = json.load(f)
    truth = {p["room_number"]: p["center"] for p in world["door_plates"]}
    path = os.path.join(run_dir, f"{PIPELINE}_landmarks.json")
    landmarks = []
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            landmarks = json.load(f)
    plates = [l for l in landmarks if l["type"] == "door_plate"]
    errors = {}
    nees = []
    false_plates = []
    for l in plates:
        if l["label"] not in truth:
            false_plates.append(l["label"])
            continue
        t = truth[l["label"]]
        p = l["position_in_world"]
        ex, ey = p[0] - t[0], p[1] - t[1]
        errors[l["label"]] = math.hypot(ex, ey)
        # The plate's NEES over its planar position: e^T P^-1 e with P its x-y covariance.
        (a, b, _), (_, c, _) = l["covariance"][0], l["covariance"][1]
        det = a * c - b * b
        if det > 0:
            nees.append((c * ex * ex - 2 * b * ex * ey + a * ey * ey) / det)
    return {
        "plate_nees": nees,
        "plates_in_world": len(truth),
        "plates_mapped": len(errors),
        "plates_within_0_2_m": sum(1 for e in errors.values() if e <= 0.2),
        "max_plate_error_m": max(errors.values()) if errors else None,
        "false_plates": false_plates,
        "missing_plates": sorted(set(truth) - set(errors)),
    }


def main(argv):
    args, seeds = study_arguments(argv, __doc__.split("\n")[0], "p1_study",
                                  "scenarios/default.yaml", "out/p1_study")
    if seeds is None:
        return 2
    os.makedirs(args.out, exist_ok=True)
    try:
        dirs = run_all(args, seeds, "p1_study")
    except RuntimeError as e:
        sys.stderr.write(f"p1_study: error: {e}\n")
        return 1

    per_seed = {}
    nees_series = {}
    for seed, d in dirs.items():
        with open(os.path.join(d, "metrics.json"), encoding="utf-8") as f:
            metrics = json.load(f)["pipelines"]
        row = {}
        for name, m in metrics.items():
            row[name] = {k: m.get(k) for k in ("ate_rmse_m", "ate_aligned_rmse_m",
                                               "final_position_error_m", "nees_mean",
                                               "nees_in_band_fraction")}
            nees_series.setdefault(name, []).append(read_nees(os.path.join(d, f"{name}_errors.csv")))
        if PIPELINE in metrics:
            row[PIPELINE]["plates"] = plate_check(d)
        per_seed[seed] = row

    n = len(seeds)
    summary = {}
    for name in per_seed[seeds[0]]:
        mean = lambda key: sum(per_seed[s][name][key] for s in seeds) / n
        summary[name] = {
            "ate_rmse_m": mean("ate_rmse_m"),
            "final_position_error_m": mean("final_position_error_m"),
            **average_nees(nees_series[name]),
        }

    targets = {}
    if PIPELINE in summary and "odometry" in summary and "p1_harris" in summary:
        p1 = summary[PIPELINE]
        targets["ate_at_most_half_of_odometry"] = p1["ate_rmse_m"] <= 0.5 * summary["odometry"]["ate_rmse_m"]
        targets["ate_below_p1_harris"] = p1["ate_rmse_m"] < summary["p1_harris"]["ate_rmse_m"]
        targets["mean_final_error_at_most_0_15_m"] = p1["final_position_error_m"] <= 0.15
        low, high = p1["nees_band"]
        targets["average_nees_in_band"] = low <= p1["nees_average"] <= high
        plates = [per_seed[s][PIPELINE]["plates"] for s in seeds]
        targets["all_plates_within_0_2_m"] = all(
            p["plates_within_0_2_m"] == p["plates_in_world"] for p in plates)
        targets["no_false_plate"] = all(not p["false_plates"] for p in plates)

    if PIPELINE in summary:
        # The plates' own consistency (reported, not a target): their mean NEES over every plate of
        # every seed against the 95 % band of the mean of M chi-square(2) values. The plates of one
        # seed share the robot's errors, so they are not independent draws.
        plate_nees = [v for s in seeds for v in per_seed[s][PIPELINE]["plates"]["plate_nees"]]
        if plate_nees:
            m = len(plate_nees)
            summary[PIPELINE]["plate_nees_mean"] = sum(plate_nees) / m
            summary[PIPELINE]["plate_nees_band"] = [chi2_quantile(0.025, 2 * m) / m,
                                                    chi2_quantile(0.975, 2 * m) / m]
            summary[PIPELINE]["plate_nees_above_95_fraction"] = (
                sum(1 for v in plate_nees if v > 5.991) / m)

    study = {"scenario": args.scenario, "seeds": seeds, "summary": summary, "targets": targets,
             "per_seed": {str(s): per_seed[s] for s in seeds}}
    with open(os.path.join(args.out, "study.json"), "w", encoding="utf-8") as f:
        json.dump(study, f, indent=2)
        f.write("\n")

    print(f"{'pipeline':<18} {'ATE rmse m':>10} {'final m':>9} {'avg NEES':>9} {'band':>15}")
    for name, s in summary.items():
        band = f"[{s['nees_band'][0]:.2f}, {s['nees_band'][1]:.2f}]"
        print(f"{name:<18} {s['ate_rmse_m']:>10.3f} {s['final_position_error_m']:>9.3f} "
              f"{s['nees_average']:>9.2f} {band:>15}")
    if PIPELINE in summary:
        for s in seeds:
            p = per_seed[s][PIPELINE]["plates"]
            print(f"seed {s}: plates {p['plates_within_0_2_m']}/{p['plates_in_world']} within 0.2 m,"
                  f" max error {p['max_plate_error_m']}, false {p['false_plates']},"
                  f" missing {p['missing_plates']}")
        p1 = summary[PIPELINE]
        if "plate_nees_mean" in p1:
            low, high = p1["plate_nees_band"]
            print(f"plates' NEES (2 dof): mean {p1['plate_nees_mean']:.2f}, band [{low:.2f}, "
                  f"{high:.2f}], above the 95 % quantile {100 * p1['plate_nees_above_95_fraction']:.1f} %")
    for k, v in targets.items():
        print(f"target {k}: {'met' if v else 'MISSED'}")
    print(f"study: {os.path.join(args.out, 'study.json')}")
    return 0 if all(targets.values()) else 3


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
