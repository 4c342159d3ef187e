#!/usr/bin/python3
"""scenarios/stereo.yaml's stereo pair through `run --export`, checked as a stereo user would
(docs/sensors.md, "Stereo"): the calibration read from the two exported EuRoC sensor.yaml files
(intrinsics, distortion, T_BS) rectifies a frame pair with OpenCV's cv2.stereoRectify
(Bouguet's method), cv2.StereoSGBM (Hirschmuller 2008) matches it, and depth = f B / d must agree
with the left camera's exact depth (its noise off: the exported depth/ is then the rendered
z-buffer's depth, quantised to 1/5000 m), remapped with the same rectification, on the textured
pixels. The same frames through a calibration with a wrong baseline, a swapped pair or a right
camera's T_BS turned by half a degree must miss the bound. Also: the pair shares every stamp,
cameras.yaml names the cameras, and each frame's true camera pose is the truth's robot pose times
its T_BS.

usage: cli_stereo_test.py CORRIDORSIM SOURCE_DIR WORK_DIR   (python3 with python3-opencv, yaml)
"""

import json
import math
import os
import sys

import cv2
import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_test_support import NO_EXTRAS, fail, fresh_folder, run  # noqa: E402

# The bound: the median relative depth error and the share of textured pixels within 2 %.
MAX_MEDIAN = 0.015
MIN_WITHIN_2PCT = 0.7
FRAMES = ("0", "500000000", "1000000000")  # stamps (ns) of the frames matched


def calibration(mav, cam):
    with open(os.path.join(mav, cam, "sensor.yaml")) as f:
        s = yaml.safe_load(f)
    fu, fv, cu, cv_ = s["intrinsics"]
    if s["distortion_model"] != "radial-tangential" or s["camera_model"] != "pinhole":
        fail("%s/sensor.yaml: not a pinhole radial-tangential camera: %s" % (cam, s))
    k = np.array([[fu, 0, cu], [0, fv, cv_], [0, 0, 1.0]])
    d = np.array(s["distortion_coefficients"], dtype=float)
    t_bs = np.array(s["T_BS"]["data"], dtype=float).reshape(4, 4)
    return {"K": k, "D": d, "T_BS": t_bs, "size": tuple(s["resolution"])}


def yawed(t_bs, degrees):
    """T_BS with the camera turned about the body's z axis by `degrees`."""
    a = math.radians(degrees)
    r = np.eye(4)
    r[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
    out = t_bs.copy()
    out[:3, :3] = r[:3, :3] @ t_bs[:3, :3]
    return out


def score(left, right, images, depths):
    """Median relative error of f B / d against the left camera's exact depth, the share within
    2 % and the pixels compared, over the frames."""
    right_from_left = np.linalg.inv(right["T_BS"]) @ left["T_BS"]
    size = left["size"]
    r1, r2, p1, p2, _q, _roi1, _roi2 = cv2.stereoRectify(
        left["K"], left["D"], right["K"], right["D"], size, right_from_left[:3, :3],
        right_from_left[:3, 3], flags=cv2.CALIB_ZERO_DISPARITY, alpha=0)
    f = p1[0, 0]
    baseline = -p2[0, 3] / p2[0, 0]
    m1 = cv2.initUndistortRectifyMap(left["K"], left["D"], r1, p1, size, cv2.CV_32FC1)
    m2 = cv2.initUndistortRectifyMap(right["K"], right["D"], r2, p2, size, cv2.CV_32FC1)
    # The rectified left pixel's source pixel as a ray of the original left camera: its exact
    # depth z there gives the point X = z (x_n, y_n, 1), and (R1 X)_z is its rectified depth.
    sources = np.stack([m1[0].ravel(), m1[1].ravel()], axis=1).reshape(-1, 1, 2).astype(np.float64)
    rays = cv2.undistortPoints(sources, left["K"], left["D"]).reshape(-1, 2)
    rays = np.concatenate([rays, np.ones((rays.shape[0], 1))], axis=1)
    sgbm = cv2.StereoSGBM_create(minDisparity=0, numDisparities=176, blockSize=7, P1=8 * 49,
                                 P2=32 * 49, uniquenessRatio=10, speckleWindowSize=100,
                                 speckleRange=2, mode=cv2.STEREO_SGBM_MODE_HH)
    errors = []
    for (left_image, right_image), depth in zip(images, depths):
        lr = cv2.remap(left_image, m1[0], m1[1], cv2.INTER_LINEAR)
        rr = cv2.remap(right_image, m2[0], m2[1], cv2.INTER_LINEAR)
        disparity = sgbm.compute(lr, rr).astype(np.float64) / 16.0
        z = cv2.remap(depth, m1[0], m1[1], cv2.INTER_NEAREST).astype(np.float64)
        z_rect = ((rays * z.reshape(-1, 1)) @ r1.T)[:, 2].reshape(z.shape)
        # Textured: a horizontal gradient over 7x7 (what block matching needs).
        gradient = cv2.boxFilter(np.abs(cv2.Sobel(lr, cv2.CV_64F, 1, 0, ksize=3)), -1, (7, 7))
        valid = (disparity > 0.5) & (z_rect > 0) & (gradient > 20)
        errors.append(np.abs(f * baseline / disparity[valid] - z_rect[valid]) / z_rect[valid])
    e = np.concatenate(errors) if errors else np.array([])
    if e.size == 0:
        return math.inf, 0.0, 0
    return float(np.median(e)), float(np.mean(e < 0.02)), int(e.size)


def passes(result):
    median, within, n = result
    return n >= 20000 and median <= MAX_MEDIAN and within >= MIN_WITHIN_2PCT


def pose_matrix(pose):
    """The 4x4 matrix of a JSON pose {t, q = [qx, qy, qz, qw]} (docs/frames.md)."""
    x, y, z, w = pose["q"]
    m = np.eye(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = pose["t"]
    return m


def check_truth_poses(export, left, right, stamps):
    """Each exported frame's world_from_camera (labels/<camera>/<t>.json) is the robot's true pose
    at the stamp times the camera's exported T_BS: the pair's calibration is the rig's."""
    worst = 0.0
    for camera, calib in (("stereo_left", left), ("stereo_right", right)):
        for t in stamps:
            with open(os.path.join(export, "labels", camera, t + ".json")) as f:
                truth = json.load(f)
            expected = pose_matrix(truth["world_from_robot"]) @ calib["T_BS"]
            error = np.abs(pose_matrix(truth["world_from_camera"]) - expected).max()
            worst = max(worst, float(error))
    if worst > 1e-5:  # the JSON rounds t to 1e-6 m and q to 1e-9
        fail("a frame's world_from_camera differs from world_from_robot * T_BS by %.2e" % worst)
    print("ok: every frame's true camera pose is the robot's times its exported T_BS (%.1e)"
          % worst)


def main():
    # Absolute: the runs start in WORK_DIR.
    binary, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    work = fresh_folder(os.path.abspath(sys.argv[3]))
    export = os.path.join(work, "export")
    command = ["run", os.path.join(source, "scenarios", "stereo.yaml"), "--out",
               os.path.join(work, "run"), "--export", export, "--set", "duration_s=1",
               "--set", "sensors.front.enabled=false", "--set", "sensors.lateral.enabled=false",
               "--set", "sensors.stereo_left.noise.enabled=false"] + NO_EXTRAS
    run(binary, command, 0, work)
    print("ran: corridorsim " + " ".join(command))
    mav = os.path.join(export, "euroc", "mav0")
    with open(os.path.join(mav, "cameras.yaml")) as f:
        cameras = yaml.safe_load(f)
    if cameras != {"cam2": "stereo_left", "cam3": "stereo_right"}:
        fail("euroc/mav0/cameras.yaml: %s" % cameras)

    def stamps(cam, index):
        with open(os.path.join(mav, cam, index)) as f:
            return [line.split(",")[0] for line in f.read().splitlines()[1:]]
    left_stamps = stamps("cam2", "data.csv")
    if left_stamps != stamps("cam3", "data.csv") or left_stamps != stamps("cam2", "depth.csv") \
            or len(left_stamps) != 11:
        fail("the pair's stamps differ or are not the 11 of 1 s at 10 Hz: %s / %s"
             % (left_stamps, stamps("cam3", "data.csv")))
    print("ok: cam2 (stereo_left, with depth/) and cam3 (stereo_right) share all 11 stamps")

    left, right = calibration(mav, "cam2"), calibration(mav, "cam3")
    check_truth_poses(export, left, right, left_stamps)
    images, depths = [], []
    for t in FRAMES:
        pair = [cv2.imread(os.path.join(mav, cam, "data", t + ".png"), cv2.IMREAD_GRAYSCALE)
                for cam in ("cam2", "cam3")]
        depth = cv2.imread(os.path.join(mav, "cam2", "depth", t + ".png"), cv2.IMREAD_UNCHANGED)
        if any(p is None for p in pair) or depth is None or depth.dtype != np.uint16:
            fail("frame %s: the pair's images or the 16-bit depth did not read" % t)
        images.append(pair)
        depths.append((depth.astype(np.float64) / 5000.0).astype(np.float32))
    result = score(left, right, images, depths)
    baseline = np.linalg.norm((np.linalg.inv(right["T_BS"]) @ left["T_BS"])[:3, 3])
    print("stereo: baseline %.4f m; %d textured pixels of %d frames: median relative depth error "
          "%.4f, %.1f %% within 2 %%" % (baseline, result[2], len(FRAMES), result[0],
                                         100 * result[1]))
    if not passes(result):
        fail("stereo depth misses the bound (median <= %.3f, >= %.0f %% within 2 %%, >= 20000 px)"
             % (MAX_MEDIAN, 100 * MIN_WITHIN_2PCT))
    # What a wrong calibration gives on the same frames: each must miss the bound.
    half_baseline = dict(right, T_BS=right["T_BS"].copy())
    half_baseline["T_BS"][1, 3] = (right["T_BS"][1, 3] + left["T_BS"][1, 3]) / 2
    turned = dict(right, T_BS=yawed(right["T_BS"], 0.5))
    wrong = {
        "a baseline of half the length": (left, half_baseline, images),
        "the pair swapped": (right, left, [(b, a) for a, b in images]),
        "the right camera's T_BS turned 0.5 deg": (left, turned, images),
    }
    for name, (l, r, pairs) in wrong.items():
        bad = score(l, r, pairs, depths)
        print("  with %s: median %.4f, %.1f %% within 2 %%, %d pixels"
              % (name, bad[0], 100 * bad[1], bad[2]))
        if passes(bad):
            fail("the bound does not tell %s from the true calibration" % name)
    print("ok: depth from the exported calibration agrees with the truth; a wrong one does not")


if __name__ == "__main__":
    main()
