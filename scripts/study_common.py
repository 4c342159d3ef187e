"""What the seed studies (p1_study.py, p3_study.py) share: their command line and the --seeds
syntax, running
`corridorsim run SCENARIO --seed N` for each seed, the NEES cells of the runs' errors.csv, and the
NEES averaged over seeds against its chi-square band. Standard library only."""
import argparse
import concurrent.futures
import math
import os
import subprocess
import sys


def parse_seeds(text):
    """'1-10', '3', '1,4,7-9': sorted distinct seeds, 1 to 1000 of them; ValueError otherwise."""
    seeds = []
    for part in text.split(","):
        if "-" in part:
            a, b = part.split("-", 1)
            if not (a.isdigit() and b.isdigit()) or int(a) > int(b):
                raise ValueError(f"--seeds: bad range '{part}'")
            seeds.extend(range(int(a), int(b) + 1))
        elif part.isdigit():
            seeds.append(int(part))
        else:
            raise ValueError(f"--seeds: bad seed '{part}'")
    if not seeds or len(seeds) > 1000:
        raise ValueError("--seeds: between 1 and 1000 seeds")
    return sorted(set(seeds))


def study_arguments(argv, description, tool, scenario, out):
    """The seed studies' command line (--scenario, default `scenario`; --seeds; --out, default
    `out`; --corridorsim; --jobs; --resume): (args, seeds), with seeds None after the error
    `<tool>: error: ...` is printed (exit 2)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--scenario", default=scenario)
    parser.add_argument("--seeds", default="1-10")
    parser.add_argument("--out", default=out)
    parser.add_argument("--corridorsim", default="build/bin/corridorsim")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--resume", action="store_true",
                        help="keep the seeds whose run folder is already complete")
    args = parser.parse_args(argv)
    try:
        seeds = parse_seeds(args.seeds)
    except ValueError as e:
        sys.stderr.write(f"{tool}: error: {e}\n")
        return args, None
    if not (1 <= args.jobs <= 64):
        sys.stderr.write(f"{tool}: error: --jobs: between 1 and 64\n")
        return args, None
    return args, seeds


def chi2_quantile(p, dof):
    """Wilson-Hilferty: accurate to a fraction of a percent for dof >= 3."""
    # Standard normal quantile (Acklam's rational approximation is overkill: bisection on erf).
    lo, hi = -10.0, 10.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if 0.5 * (1.0 + math.erf(mid / math.sqrt(2.0))) < p:
            lo = mid
        else:
            hi = mid
    z = 0.5 * (lo + hi)
    h = 2.0 / (9.0 * dof)
    return dof * (1.0 - h + z * math.sqrt(h)) ** 3


def run_one(args, seed, tool, allow_extra_failure=False):
    """The run folder of `seed` (args.out/seed_N), run unless --resume finds it complete.
    RuntimeError when corridorsim fails; exit 3 (an expectation failed) is a result. With
    `allow_extra_failure`, exit 4 (the results are written, an extra such as maps/ failed) is too,
    with a warning."""
    out = os.path.join(args.out, f"seed_{seed}")
    if args.resume and os.path.isfile(os.path.join(out, "metrics.json")):
        return out  # a finished run of an earlier, interrupted study (run folders are atomic)
    cmd = [args.corridorsim, "run", args.scenario, "--seed", str(seed), "--out", out, "--force",
           "--no-plots"]
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode == 4 and allow_extra_failure:
        sys.stderr.write(f"{tool}: warning: seed {seed}: an extra of the run failed (exit 4); "
                         f"its results are used\n")
    elif done.returncode not in (0, 3):
        sys.stderr.write(done.stdout[-4000:])
        raise RuntimeError(f"seed {seed}: corridorsim exited {done.returncode}")
    return out


def run_all(args, seeds, tool, allow_extra_failure=False):
    """{seed: run folder} for every seed, args.jobs at a time; RuntimeError when one fails."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        return dict(zip(seeds, pool.map(
            lambda s: run_one(args, s, tool, allow_extra_failure), seeds)))


def nees_cell(cells, column):
    """The NEES of a row of <pipeline>_errors.csv (its cells, the nees column's index): nan where
    the row has none (the cell empty or nan while the covariance is singular, at the start)."""
    if len(cells) > column and cells[column] not in ("", "nan"):
        return float(cells[column])
    return float("nan")


def average_nees(series, dof=3):
    """The NEES averaged over seeds at each sample (`series`: one NEES list per seed, nan where
    missing; samples where a seed has none are left out), its mean over time, the 95 % band of
    the mean of N chi-square(dof) values [chi2(dof N, 0.025) / N, chi2(dof N, 0.975) / N], and the
    fraction of samples inside it."""
    n = len(series)
    length = min(len(s) for s in series)
    anees = []
    for i in range(length):
        column = [s[i] for s in series]
        if all(math.isfinite(v) for v in column):
            anees.append(sum(column) / n)
    low, high = chi2_quantile(0.025, dof * n) / n, chi2_quantile(0.975, dof * n) / n
    return {
        "nees_average": sum(anees) / len(anees) if anees else float("nan"),
        "nees_band": [low, high],
        "anees_in_band_fraction": (sum(1 for a in anees if low <= a <= high) / len(anees)
                                   if anees else None),
    }
