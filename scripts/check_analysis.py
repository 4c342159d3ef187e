#!/usr/bin/python3
"""Checks that corridorsim.Run recomputes a run's trajectory metrics exactly: for every pipeline
of RUN_DIR/metrics.json that has ate_rmse_m, Run.ate, Run.rpe over 1, 5 and 10 m (translation
and yaw) and Run.final_error must equal metrics.json's ate_rmse_m, rpe_<d>m_trans_rmse_m,
rpe_<d>m_yaw_rmse_rad and final_position_error_m as floats (no tolerance), and so must every
other trajectory metric Run.trajectory_metrics gives (samples, ate_mean_m, ..., alignment.*).

    scripts/check_analysis.py RUN_DIR [RUN_DIR ...]

Prints each mismatch (`RUN_DIR: pipeline: metric: python X != metrics.json Y`) and exits 1; else
one line per folder (`RUN_DIR: N pipelines, M values equal`) and exits 0. Exit 2 when an input is
unreadable or malformed (the message names the file and line) or on a bad command line.
scripts/check_metrics.sh runs it on the run of every shipped scenario (docs/analysis.md).
"""

import argparse
import math
import os
import sys

# numpy and pandas: Debian's, under /usr/bin/python3 when the python3 that started this lacks them
# (system_python.py, beside this script); corridorsim.analysis: the installed package's, else the
# checkout's.
sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import system_python  # noqa: E402

try:
    import numpy  # noqa: F401
    import pandas  # noqa: F401
except ImportError as missing:
    system_python.rerun_or_exit(__file__, missing, "check_analysis",
                                reexec_env="CORRIDORSIM_CHECK_ANALYSIS_REEXEC",
                                hint="Debian: python3-numpy python3-pandas", status=2)

system_python.use_corridorsim_with("analysis")
from corridorsim.analysis import RPE_DISTANCES_M, Run  # noqa: E402
from corridorsim.files import InputError  # noqa: E402

# The four the brief of docs/analysis.md promises, by their accessor.
PROMISED = [("ate_rmse_m", lambda run, p: run.ate(p))] + [
    (f"rpe_{d}m_{kind}_rmse_{unit}", lambda run, p, d=d, kind=kind: run.rpe(p, d, kind))
    for d in RPE_DISTANCES_M for kind, unit in [("trans", "m"), ("yaw", "rad")]
] + [("final_position_error_m", lambda run, p: run.final_error(p))]


def same(a, b):
    """Equal values of the same kind: floats equal as floats (no tolerance; NaN equals NaN),
    counts as integers, null as null."""
    if a is None or b is None:
        return a is None and b is None
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, int) and isinstance(b, int):
        return a == b
    return (isinstance(a, float) and isinstance(b, float) and
            (a == b or (math.isnan(a) and math.isnan(b))))


def check(run_dir):
    """(mismatch lines, pipelines checked, values compared) of one run folder."""
    run = Run(run_dir)
    mismatches, pipelines, compared = [], 0, 0
    for name in run.pipelines:
        if run.metric(name, "ate_rmse_m") is None:
            continue
        pipelines += 1
        recomputed = run.trajectory_metrics(name)
        checked = set()
        for metric, accessor in PROMISED:
            ours, theirs = accessor(run, name), run.metric(name, metric)
            compared += 1
            checked.add(metric)
            if not same(ours, theirs):
                mismatches.append(f"{run_dir}: {name}: {metric}: python {ours!r} != "
                                  f"metrics.json {theirs!r}")
        for metric, ours in recomputed.items():
            if metric in checked:
                continue
            theirs = run.metric(name, metric)
            compared += 1
            if not same(ours, theirs):
                mismatches.append(f"{run_dir}: {name}: {metric}: python {ours!r} != "
                                  f"metrics.json {theirs!r}")
    return mismatches, pipelines, compared


def main(argv):
    parser = argparse.ArgumentParser(
        description="Checks corridorsim.Run's trajectory metrics against metrics.json, exactly.")
    parser.add_argument("run_dirs", nargs="+", metavar="RUN_DIR")
    args = parser.parse_args(argv)
    failed = False
    for run_dir in args.run_dirs:
        try:
            mismatches, pipelines, compared = check(run_dir)
        except InputError as e:
            print(f"check_analysis: {e}", file=sys.stderr)
            return 2
        for line in mismatches:
            print(line)
        if mismatches:
            failed = True
        else:
            print(f"{run_dir}: {pipelines} pipelines, {compared} values equal")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
