#!/usr/bin/python3
"""Ceiling lamps from the upward camera, in Python: an EKF-SLAM over wheel odometry whose
landmarks are the circular lamps of the ceiling (P3's idea, simplified), written against
corridorsim's protocol (docs/protocol.md) with numpy and Debian's OpenCV only.

- Prediction: the differential-drive model of P1 eqs. 13-17.
- Detection: the lamps are the brightest blobs of the image: threshold, contours, kept when
  round (area over the enclosing circle's) and solid (area over the convex hull's).
- Measurement: a lamp centre's bearing (OpenCV's camera models undo the lens) meets the ceiling
  plane, whose height is an option, at one point: the lamp in the robot frame,
  z = R(yaw)^T (l - t) (the range-bearing model of P1 eq. 18 in Cartesian form), its covariance
  from the pixel noise through the numerical Jacobian of pixel -> point.
- Association: the nearest lamp by NIS, gated (chi2 2 dof 99 %); a detection far from every lamp
  (NIS above new_lamp_chi2) starts a new one (P1 eqs. 26-27).
"""

import math
import sys

import cv2
import numpy as np

import corridorsim


class CameraGeometry:
    """Pixel -> unit bearing in the camera frame, through OpenCV's own model of the lens."""

    def __init__(self, camera):
        m = camera.model
        self.k = np.array([[m["fx"], 0, m["cx"]], [0, m["fy"], m["cy"]], [0, 0, 1]], dtype=float)
        self.d = np.array(m["distortion"], dtype=float)
        self.fisheye = m["model"] == "kannala_brandt"
        self.rotation = np.array(camera.rotation, dtype=float)  # robot_R_camera
        self.translation = np.array(camera.translation, dtype=float)

    def bearing(self, pixel):
        p = np.array([[pixel]], dtype=float)
        if self.fisheye:
            # cv::fisheye::undistortPoints gives x = tan(theta) (X/Z, Y/Z): fine below 90 deg.
            n = cv2.fisheye.undistortPoints(p, self.k, self.d.reshape(4, 1))[0, 0]
        else:
            n = cv2.undistortPoints(p, self.k, self.d)[0, 0]
        v = np.array([n[0], n[1], 1.0])
        return v / np.linalg.norm(v)


class Lamps(corridorsim.Pipeline):
    def on_start(self, calibration, start):
        o = start.options
        self.k_m = float(o.get("k_m", 0.0001))
        self.ceiling_m = float(o.get("ceiling_height_m", 2.7))
        self.pixel_sigma = float(o.get("pixel_sigma_px", 3.0))
        self.gate = float(o.get("gate_chi2", 9.21))
        self.new_lamp = float(o.get("new_lamp_chi2", 40.0))
        self.threshold = int(o.get("threshold", 245))
        self.min_area = float(o.get("min_area_px", 40))
        self.min_elevation = math.radians(float(o.get("min_elevation_deg", 20)))
        self.min_roundness = float(o.get("min_roundness", 0.4))
        self.min_solidity = float(o.get("min_solidity", 0.8))
        self.max_lamps = int(o.get("max_lamps", 200))
        self.camera_id = start.cameras[0]
        self.camera = CameraGeometry(calibration.cameras[self.camera_id])
        self.wheelbase = calibration.wheelbase_m
        self.x = np.array(start.pose, dtype=float)  # robot (x, y, yaw), then lamps (x, y) ...
        self.p = np.zeros((3, 3))
        self.stamp_ns = start.stamp_ns
        self.pending_detections, self.pending_innovations = [], []

    # ---- prediction (P1 eqs. 13-17) ----
    def on_odometry(self, o):
        left, right = o.left_m, o.right_m
        travel, turn = 0.5 * (left + right), (right - left) / self.wheelbase
        heading = self.x[2] + 0.5 * turn
        c, s = math.cos(heading), math.sin(heading)
        n = len(self.x)
        f = np.eye(n)
        f[0, 2], f[1, 2] = -travel * s, travel * c
        lever = travel / (2 * self.wheelbase)
        g = np.zeros((n, 2))
        g[:3] = [[0.5 * c + lever * s, 0.5 * c - lever * s],
                 [0.5 * s - lever * c, 0.5 * s + lever * c],
                 [-1 / self.wheelbase, 1 / self.wheelbase]]
        q = np.diag([self.k_m * abs(left), self.k_m * abs(right)])
        self.x[0] += travel * c
        self.x[1] += travel * s
        self.x[2] = math.remainder(self.x[2] + turn, 2 * math.pi)
        self.p = f @ self.p @ f.T + g @ q @ g.T
        self.p = 0.5 * (self.p + self.p.T)
        self.stamp_ns = o.stamp_ns

    # ---- detection ----
    def detect(self, rgb):
        gray = cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY)
        _, mask = cv2.threshold(gray, self.threshold, 255, cv2.THRESH_BINARY)
        contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        lamps = []
        for contour in contours:
            area = cv2.contourArea(contour)
            if area < self.min_area:
                continue
            (u, v), radius = cv2.minEnclosingCircle(contour)
            hull = cv2.contourArea(cv2.convexHull(contour))
            if area / (math.pi * radius * radius) < self.min_roundness or hull <= 0 or \
                    area / hull < self.min_solidity:
                continue
            m = cv2.moments(contour)
            lamps.append(((m["m10"] / m["m00"], m["m01"] / m["m00"]), radius))
        return lamps

    # ---- measurement: the lamp centre on the ceiling, in the robot frame ----
    def ceiling_point(self, pixel):
        b = self.camera.rotation @ self.camera.bearing(pixel)
        above = self.ceiling_m - self.camera.translation[2]
        if b[2] <= math.sin(self.min_elevation) * np.linalg.norm(b) or above <= 0:
            return None
        return (self.camera.translation + (above / b[2]) * b)[:2]

    def observe(self, pixel):
        z = self.ceiling_point(pixel)
        if z is None:
            return None
        j = np.zeros((2, 2))
        for k, step in enumerate(((0.5, 0.0), (0.0, 0.5))):
            plus = self.ceiling_point((pixel[0] + step[0], pixel[1] + step[1]))
            minus = self.ceiling_point((pixel[0] - step[0], pixel[1] - step[1]))
            if plus is None or minus is None:
                return None
            j[:, k] = (plus - minus) / 1.0
        return z, self.pixel_sigma ** 2 * j @ j.T

    def model(self, i, z):
        """Residual and Jacobian of lamp i (state index) seen as z = R^T (l - t)."""
        x, y, yaw = self.x[:3]
        c, s = math.cos(yaw), math.sin(yaw)
        rt = np.array([[c, s], [-s, c]])
        d = self.x[i:i + 2] - self.x[:2]
        h = np.zeros((2, len(self.x)))
        h[:, 0:2] = -rt
        h[:, 2] = [-s * d[0] + c * d[1], -c * d[0] - s * d[1]]
        h[:, i:i + 2] = rt
        return z - rt @ d, h

    def on_cameras(self, frames):
        for frame in frames:
            if frame.dropped or frame.camera != self.camera_id:
                continue
            for (pixel, radius) in self.detect(frame.rgb):
                observed = self.observe(pixel)
                if observed is None:
                    continue
                z, r = observed
                detection = {"camera": frame.camera, "type": "lamp", "pixel": list(pixel),
                             "radius_px": radius}
                detection["landmark_id"], detection["new_landmark"] = self.associate(z, r)
                self.pending_detections.append(detection)

    def associate(self, z, r):
        best, best_nis = None, math.inf
        for i in range(3, len(self.x), 2):
            residual, h = self.model(i, z)
            s = h @ self.p @ h.T + r
            nis = float(residual @ np.linalg.solve(s, residual))
            if nis < best_nis:
                best, best_nis = i, nis
        if best is not None and best_nis < self.gate:
            residual, h = self.model(best, z)
            s = h @ self.p @ h.T + r
            k = self.p @ h.T @ np.linalg.inv(s)
            self.x = self.x + k @ residual
            self.x[2] = math.remainder(self.x[2], 2 * math.pi)
            i_kh = np.eye(len(self.x)) - k @ h
            self.p = i_kh @ self.p @ i_kh.T + k @ r @ k.T  # Joseph form
            self.pending_innovations.append({"type": "lamp", "nis": best_nis, "dof": 2,
                                             "accepted": True})
            return (best - 3) // 2, False
        if best_nis <= self.new_lamp or (len(self.x) - 3) // 2 >= self.max_lamps:
            return -1, False  # between the gates: too ambiguous to use
        # P1 eqs. 26-27: l = t + R(yaw) z, its covariance from the robot's and the measurement's.
        c, s = math.cos(self.x[2]), math.sin(self.x[2])
        rot = np.array([[c, -s], [s, c]])
        lamp = self.x[:2] + rot @ z
        gx = np.zeros((2, len(self.x)))
        gx[:, :2] = np.eye(2)
        gx[:, 2] = [-s * z[0] - c * z[1], c * z[0] - s * z[1]]
        pll = gx @ self.p @ gx.T + rot @ r @ rot.T
        plx = gx @ self.p
        n = len(self.x)
        p = np.zeros((n + 2, n + 2))
        p[:n, :n] = self.p
        p[n:, :n] = plx
        p[:n, n:] = plx.T
        p[n:, n:] = pll
        self.x = np.concatenate([self.x, lamp])
        self.p = p
        return (n - 3) // 2, True

    def estimate(self):
        return corridorsim.Estimate(self.x[:3], self.p[:3, :3])

    def detections(self):
        out, self.pending_detections = self.pending_detections, []
        return out

    def innovations(self):
        out, self.pending_innovations = self.pending_innovations, []
        return out

    def landmarks(self):
        out = []
        for k, i in enumerate(range(3, len(self.x), 2)):
            cov = np.zeros((3, 3))
            cov[:2, :2] = self.p[i:i + 2, i:i + 2]
            cov[2, 2] = 1e-4  # the height is an option, not estimated
            out.append({"id": k, "type": "lamp", "position": [self.x[i], self.x[i + 1], self.ceiling_m],
                        "covariance": cov})
        return out


if __name__ == "__main__":
    sys.exit(corridorsim.serve(Lamps))
