#!/usr/bin/env python3
"""scripts/p3_study.py's split of the position error along and across the robot's true heading,
on constructed files: a robot heading along +y (yaw 90 deg) with an error in x has it all across
its track; one heading along +x has an error in x all along it; samples without a true pose are
left out of the split (but not out of the largest error).

Usage: p3_study_test.py SOURCE_DIR WORK_DIR (standard library only)."""
import math
import os
import shutil
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def close(a, b):
    return a is not None and abs(a - b) < 1e-9


def main():
    source, work = sys.argv[1], sys.argv[2]
    sys.path.insert(0, os.path.join(source, "scripts"))
    import p3_study  # noqa: E402 (the script's own folder holds study_common)

    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    truth = os.path.join(work, "ground_truth.tum")
    with open(truth, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        # yaw 90 deg at t = 0.02, 0 at t = 0.04; no pose at t = 0.06.
        q = math.sin(math.pi / 4), math.cos(math.pi / 4)
        f.write("0.020000000 0 0 0 0 0 %.12f %.12f\n" % q)
        f.write("0.040000000 1 0 0 0 0 0 1\n")
    errors = os.path.join(work, "p_errors.csv")
    with open(errors, "w") as f:
        f.write("t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n")
        f.write("0.020000000,0.3,0.0,0,0.1,0.1,0.01,1.5\n")   # heading +y: 0.3 m across
        f.write("0.040000000,0.0,0.4,0,0.1,0.1,0.01,\n")      # heading +x: 0.4 m across
        f.write("0.060000000,2.0,0.0,0,0.1,0.1,0.01,2.5\n")   # no true pose: out of the split
    yaw = p3_study.read_truth_yaw(truth)
    if sorted(yaw) != ["0.020000000", "0.040000000"] or not close(yaw["0.020000000"], math.pi / 2):
        fail("read_truth_yaw: %r" % yaw)
    nees, e = p3_study.read_errors(errors, yaw)
    if not close(e["cross_track_rmse_m"], math.sqrt((0.3 ** 2 + 0.4 ** 2) / 2)):
        fail("cross-track RMSE %r" % e["cross_track_rmse_m"])
    if not close(e["along_track_rmse_m"], 0.0):
        fail("along-track RMSE %r" % e["along_track_rmse_m"])
    if not close(e["max_position_error_m"], 2.0) or e["error_samples"] != 3:
        fail("largest error %r over %r samples" % (e["max_position_error_m"], e["error_samples"]))
    if nees[0] != 1.5 or not math.isnan(nees[1]) or nees[2] != 2.5:
        fail("NEES series %r" % nees)
    # Along the track: heading +x, error in x.
    with open(errors, "w") as f:
        f.write("t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n")
        f.write("0.040000000,-0.25,0.0,0,0.1,0.1,0.01,1\n")
    _, e = p3_study.read_errors(errors, yaw)
    if not close(e["along_track_rmse_m"], 0.25) or not close(e["cross_track_rmse_m"], 0.0):
        fail("along %r, across %r" % (e["along_track_rmse_m"], e["cross_track_rmse_m"]))
    # No true pose at all: the split is unknown (None), not zero.
    _, e = p3_study.read_errors(errors, {})
    if e["along_track_rmse_m"] is not None or e["cross_track_rmse_m"] is not None:
        fail("without truth: %r" % e)
    print("PASS")


if __name__ == "__main__":
    main()
