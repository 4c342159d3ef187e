#!/usr/bin/python3
"""Plots of `corridorsim evaluate`: writes OUT_DIR/plots/*.png.

    scripts/plot_evaluation.py OUT_DIR RUN_DIR

Reads (metres, seconds, radians, world frame W; docs/evaluation.md):
  OUT_DIR/evaluation.json        {"estimates": {name: {"format", "samples", ...}}}
  OUT_DIR/<name>_aligned.tum     each estimate after the alignment, `t tx ty tz qx qy qz qw`
  OUT_DIR/<name>_errors.csv      t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees
  RUN_DIR/world.json             the world's plan (walls, doors, plates, lamps)
  RUN_DIR/ground_truth.tum       the true trajectory

Writes (each printed on its own line), drawn as scripts/plot_run.py draws a run's:
  trajectories.png       the truth and every aligned estimate over the world's plan
  errors_<name>.png      x, y and heading error against time, with +-2 sigma where the estimate
                         had covariances (ov_eval)
  nees_<name>.png        NEES against time with its 95 % band (ov_eval estimates only)
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_run  # noqa: E402
from plot_run import InputError  # noqa: E402


def read_evaluation(out_dir, run_dir):
    """The run-like record plot_run's drawing functions take; raises InputError."""
    for folder in (out_dir, run_dir):
        if not os.path.isdir(folder):
            raise InputError(folder, None, "is not a directory")
    path = os.path.join(out_dir, "evaluation.json")
    root = plot_run.load_json(path)
    estimates = root.get("estimates")
    if not isinstance(estimates, dict):
        raise InputError(path, None, "has no object 'estimates'")
    run = {
        "world": plot_run.read_world(os.path.join(run_dir, "world.json")),
        "truth": plot_run.read_tum(os.path.join(run_dir, "ground_truth.tum")),
        "pipelines": {},
    }
    for name, entry in estimates.items():
        if not isinstance(entry, dict) or "format" not in entry:
            continue  # a landmark map without a trajectory
        run["pipelines"][name] = {
            "trajectory": plot_run.read_tum(os.path.join(out_dir, f"{name}_aligned.tum")),
            "errors": plot_run.read_errors(os.path.join(out_dir, f"{name}_errors.csv")),
        }
    return run


def plot_evaluation(run, plots_dir):
    os.makedirs(plots_dir, exist_ok=True)
    written = []
    plot_run.plot_trajectories(run, plots_dir, written)
    plot_run.plot_errors_and_nees(run, lambda name: None, plots_dir, written)
    return written


def main(argv):
    parser = argparse.ArgumentParser(description="Writes OUT_DIR/plots/*.png for a finished "
                                     "`corridorsim evaluate`.")
    parser.add_argument("out_dir", metavar="OUT_DIR")
    parser.add_argument("run_dir", metavar="RUN_DIR")
    args = parser.parse_args(argv)
    return plot_run.write_plots("plot_evaluation",
                                lambda: read_evaluation(args.out_dir, args.run_dir),
                                plot_evaluation, os.path.join(args.out_dir, "plots"))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
