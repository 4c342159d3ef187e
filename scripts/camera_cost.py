#!/usr/bin/python3
"""Measures what each extra camera costs a run (issue 53, "Truth and cost"; docs/sensors.md).

Drives the default corridor for a few simulated seconds with `corridorsim drive --save-frames`
(every enabled camera rendered and its frames written, as a dataset recording does), first with
the default rig (front RGB-D, lateral, upward), then with 1, 2, ... extra pinhole cameras (the
new-camera defaults: 640x480, 58 deg, 10 Hz, no depth) mounted around the robot, and the same
without the three default cameras. Each configuration runs `--repeats` times; the table gives the
fastest wall time of each and the marginal cost of one more camera per simulated second and per
frame. Wall clock: run it on an idle machine and compare figures of one invocation only.

Usage:
  /usr/bin/python3 scripts/camera_cost.py [--bin build/bin/corridorsim] [--seconds 10]
      [--extra 0,1,2,4] [--repeats 2] [--out out/camera_cost]

Writes <out>/camera_cost.json and prints a markdown table. Exit 0, or 2 on bad arguments.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import time

# Extra cameras' mounts: around the robot, each looking outwards (none near a wall at 0.5 m).
MOUNTS = [
    "{x_m: 0.15, y_m: 0.06, z_m: 0.5}",
    "{x_m: 0.15, y_m: -0.06, z_m: 0.5}",
    "{x_m: -0.15, z_m: 0.5, yaw_deg: 180}",
    "{x_m: 0.0, y_m: 0.1, z_m: 0.5, yaw_deg: 45}",
    "{x_m: 0.0, y_m: -0.1, z_m: 0.5, yaw_deg: -45}",
    "{x_m: 0.1, z_m: 0.55, pitch_deg: 20}",
]


def counts(text):
    try:
        values = [int(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("expected comma-separated counts, got '%s'" % text)
    if not values or any(v < 0 or v > len(MOUNTS) for v in values):
        raise argparse.ArgumentTypeError("each count must lie in [0, %d]" % len(MOUNTS))
    return values


def scenario_text(source, seconds, extra, defaults):
    lines = ["include: %s\n" % os.path.join(source, "scenarios", "default.yaml"),
             "duration_s: %g\n" % seconds, "sensors:\n"]
    if not defaults:
        lines += ["  %s: {enabled: false}\n" % c for c in ("front", "lateral", "upward")]
    for k in range(extra):
        lines.append("  extra%d: {type: camera, rate_hz: 10, mount: %s}\n" % (k, MOUNTS[k]))
    return "".join(lines)


def timed_drive(binary, scenario, out):
    shutil.rmtree(out, ignore_errors=True)
    start = time.monotonic()
    p = subprocess.run([binary, "drive", scenario, "--save-frames", "--out", out],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - start
    if p.returncode != 0:
        sys.exit("camera_cost: %s failed (exit %d):\n%s" % (scenario, p.returncode, p.stderr[-2000:]))
    frames = sum(len(files) for _, _, files in os.walk(os.path.join(out, "frames")))
    return wall, frames


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default=os.path.join(here, "build", "bin", "corridorsim"))
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--extra", type=counts, default=[0, 1, 2, 4])
    parser.add_argument("--repeats", type=int, default=2, choices=range(1, 11))
    parser.add_argument("--out", default=os.path.join("out", "camera_cost"))
    args = parser.parse_args()
    if not 1.0 <= args.seconds <= 600.0:
        parser.error("--seconds must lie in [1, 600]")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for defaults in (True, False):
        for extra in args.extra:
            if not defaults and extra == 0:
                continue
            name = "%s_%d" % ("rig" if defaults else "bare", extra)
            scenario = os.path.join(args.out, name + ".yaml")
            with open(scenario, "w") as f:
                f.write(scenario_text(here, args.seconds, extra, defaults))
            runs = [timed_drive(args.bin, scenario, os.path.join(args.out, name))
                    for _ in range(args.repeats)]
            wall = min(r[0] for r in runs)
            rows.append({"default_cameras": defaults, "extra_cameras": extra, "wall_s": wall,
                         "frame_files": runs[0][1]})
            print("%s: %.2f s wall, %d frame files" % (name, wall, runs[0][1]), flush=True)
    base = next((r for r in rows if r["default_cameras"] and r["extra_cameras"] == 0), None)
    print("\n| cameras | wall (s) | per simulated s | added per extra camera per simulated s |")
    print("|---|---|---|---|")
    for r in rows:
        cams = ("front, lateral, upward" if r["default_cameras"] else "none") + \
            " + %d extra" % r["extra_cameras"]
        added = ""
        if r["default_cameras"] and base and r["extra_cameras"] > 0:
            added = "%.3f s" % ((r["wall_s"] - base["wall_s"]) / r["extra_cameras"] / args.seconds)
            r["added_per_camera_per_simulated_s"] = float(added[:-2])
        print("| %s | %.2f | %.3f | %s |" % (cams, r["wall_s"], r["wall_s"] / args.seconds, added))
    with open(os.path.join(args.out, "camera_cost.json"), "w") as f:
        json.dump({"simulated_s": args.seconds, "repeats": args.repeats, "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
