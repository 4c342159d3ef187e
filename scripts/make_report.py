#!/usr/bin/python3
"""Writes STUDY_DIR/report.html: the study's figures interactive, the table of runs sortable, the
failed and diverged runs with their reasons, each run linked to its viewer.html by a relative
link (docs/viewer.md).

    make_report.py STUDY_DIR [--out FILE]

Reads summary.json, paired.csv's numbers (through summary.json), status/ and each run's
metrics.json. Exit 0: written; 2: a malformed input file (path:line: message); 1: the page could
not be written. corridorsim study calls it after plots/ (exit 4 there when it fails).
"""

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import system_python  # noqa: E402

system_python.use_corridorsim_with("files")
from corridorsim import files  # noqa: E402
from pages import fill_page, keep_path_bytes, make_page, page_json  # noqa: E402

SCHEMA = 1
MAX_TEXT = 300
MAX_RUNS = 100000
# The metrics of a run the table shows besides the study's own (summary.json "metrics").
TABLE_METRICS = ["ate_rmse_m", "ate_aligned_rmse_m", "rpe_1m_trans_rmse_m",
                 "final_position_error_m", "nees_mean", "nees_in_band_fraction"]


def number(value):
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value) else None


def text(value):
    return str(value)[:MAX_TEXT] if value is not None else None


def point_label(point):
    vary = point.get("vary") or {}
    return ", ".join(f"{k}={v}" for k, v in vary.items()) if vary else point.get("id", "")


def read_status(study_dir, point, seed):
    path = os.path.join(study_dir, "status", point, f"seed_{seed}.json")
    if not os.path.exists(path):
        return None
    status = files.load_json(path)
    return status if isinstance(status, dict) else None


def run_rows(study_dir, summary, pipelines, metric_names):
    """One row per planned run of every point: its outcome, the reason when it is not a result,
    its pipelines' metrics and the relative link to its viewer."""
    rows = []
    for point in summary.get("points", []):
        pid = point.get("id", "")
        runs = point.get("runs", {})
        seeds = set()
        for p in pipelines:
            seeds.update(point.get("pipelines", {}).get(p, {}).get("values", {}).get("seed", []))
        failed = {s: "failed" for s in runs.get("failed_seeds", [])}
        failed.update({s: "timeout" for s in runs.get("timed_out_seeds", [])})
        diverged = {}
        for p in pipelines:
            pr = point.get("pipelines", {}).get(p, {}).get("runs", {})
            for seed, why in zip(pr.get("diverged_seeds", []), pr.get("diverged_why", [])):
                diverged.setdefault(seed, []).append(f"{p}: {why}")
        for seed in sorted(seeds | set(failed) | set(diverged)):
            if len(rows) >= MAX_RUNS:
                return rows
            folder = os.path.join("runs", pid, f"seed_{seed}")
            viewer = os.path.join(folder, "viewer.html")
            row = {"point": pid, "seed": seed, "status": "finished", "reason": None,
                   "viewer": viewer if os.path.isfile(os.path.join(study_dir, viewer)) else None,
                   "metrics": {}}
            if seed in failed:
                status = read_status(study_dir, pid, seed) or {}
                row["status"] = failed[seed]
                row["reason"] = text(status.get("detail") or failed[seed])
            elif seed in diverged:
                row["status"] = "diverged"
                row["reason"] = text("; ".join(diverged[seed]))
            metrics_path = os.path.join(study_dir, folder, "metrics.json")
            if row["status"] in ("finished", "diverged") and os.path.isfile(metrics_path):
                metrics = files.load_json(metrics_path)
                for p in pipelines:
                    section = metrics.get("pipelines", {}).get(p)
                    if isinstance(section, dict):
                        row["metrics"][p] = {m: number(section.get(m)) for m in metric_names}
            rows.append(row)
    return rows


def summary_rows(summary, pipelines, metric_names):
    rows = []
    for point in summary.get("points", []):
        for p in pipelines:
            metrics = point.get("pipelines", {}).get(p, {}).get("metrics", {})
            for m in metric_names:
                d = metrics.get(m)
                if not isinstance(d, dict):
                    continue
                row = {"point": point.get("id"), "pipeline": p, "metric": m}
                for k in ("n", "mean", "std", "median", "p95", "min", "max", "ci_low", "ci_high"):
                    row[k] = number(d.get(k))
                rows.append(row)
    return rows


def paired_rows(summary):
    rows = []
    for point in summary.get("points", []):
        for pair in point.get("paired", []):
            for metric, m in (pair.get("metrics") or {}).items():
                if not isinstance(m, dict):
                    continue
                row = {"point": point.get("id"), "a": pair.get("a"), "b": pair.get("b"),
                       "metric": metric}
                for k in ("n", "diff", "diff_ci_low", "diff_ci_high", "ratio", "ratio_ci_low",
                          "ratio_ci_high", "p_sign", "p_wilcoxon"):
                    row[k] = number(m.get(k))
                rows.append(row)
    return rows


def series_of(summary, pipelines):
    out = {}
    for point in summary.get("points", []):
        per = {}
        for p in pipelines:
            s = point.get("pipelines", {}).get(p, {}).get("series")
            if not isinstance(s, dict) or not s.get("t"):
                continue
            err = s.get("position_error_rms_m", [])
            sigma = s.get("position_sigma_rms_m", [])
            low, high = s.get("band_low", []), s.get("band_high", [])
            finite_low = [v for v in low if number(v) is not None]
            finite_high = [v for v in high if number(v) is not None]
            per[p] = {"t": [number(v) for v in s["t"]],
                      "error_rms": [number(v) for v in err],
                      "error_2sigma": [2.0 * v if number(v) is not None else None for v in sigma],
                      "nees_mean": [number(v) for v in s.get("anees", [])],
                      "nees_low": [number(v) for v in low],
                      "nees_high": [number(v) for v in high],
                      "nees_band": [min(finite_low) if finite_low else None,
                                    max(finite_high) if finite_high else None]}
        out[point.get("id")] = per
    return out


def build_data(study_dir):
    summary_path = os.path.join(study_dir, "summary.json")
    summary = files.load_json(summary_path)
    if not isinstance(summary, dict) or not isinstance(summary.get("points"), list):
        raise files.InputError(summary_path, None, "expected an object with a 'points' array")
    pipelines = [p for p in summary.get("pipelines", []) if isinstance(p, str)]
    study_metrics = [m for m in summary.get("metrics", []) if isinstance(m, str)]
    metric_names = list(dict.fromkeys(TABLE_METRICS + study_metrics))
    points = [{"id": p.get("id"), "label": point_label(p), "values": p.get("vary") or {}}
              for p in summary["points"]]
    vary = summary.get("vary") or []
    expectations = []
    for p in summary["points"]:
        for e in p.get("expectations", []):
            expectations.append({"text": text(f"{p.get('id')}: {e.get('expectation', '')}"),
                                 "measured": number(e.get("measured")),
                                 "passed": bool(e.get("passed"))})
    command = None
    report_md = os.path.join(study_dir, "report.md")
    if os.path.exists(report_md):
        with open(report_md, encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("corridorsim study"):
                    command = text(line.strip())
                    break
    name = os.path.basename(os.path.abspath(study_dir))
    return {
        "schema": SCHEMA, "title": f"study {name}", "study": name, "command": command,
        "pipelines": pipelines,
        "metrics": [{"name": m, "unit": "m" if m.endswith("_m") else
                     "rad" if m.endswith("_rad") else ""} for m in metric_names],
        "points": points,
        "runs": run_rows(study_dir, summary, pipelines, metric_names),
        "summary": summary_rows(summary, pipelines, metric_names),
        "paired": paired_rows(summary),
        "series": series_of(summary, pipelines),
        "sweep": {"keys": vary} if vary else None,
        "expectations": expectations,
    }


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study_dir")
    parser.add_argument("--out", help="the page (default STUDY_DIR/report.html)")
    args = parser.parse_args(argv)
    keep_path_bytes(sys.stdout)
    out = args.out or os.path.join(args.study_dir, "report.html")
    made = {}

    def build():
        if not os.path.isdir(args.study_dir):
            raise files.InputError(args.study_dir, None, "is not a directory")
        data = build_data(args.study_dir)
        made["runs"] = len(data["runs"])
        made["page"] = fill_page("report.html", "report.js", page_json(data), data["title"])
        return made["page"]

    code = make_page("make_report.py", args.study_dir, out, build,
                     (OSError, RuntimeError, ValueError, KeyError, TypeError, AttributeError))
    if code == 0:
        print(f"wrote {out} ({len(made['page'].encode('utf-8')) / 1e6:.2f} MB, "
              f"{made['runs']} runs)")
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
