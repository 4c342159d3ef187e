#!/usr/bin/python3
"""Dead reckoning in Python: a port of corridorsim's built-in `odometry` pipeline
(slam/odometry_pipeline.cpp) over the lockstep protocol (docs/protocol.md).

Run beside the built-in one (odometry.yaml), its trajectory, covariance and metrics are
byte-identical to it: the protocol delivers every message and number exactly, and this file does
the same IEEE arithmetic in the same order as the C++ (P1 eqs. 13-17; Eigen sums a 3-term dot
product as a0 + (a1 + a2), a 2-term one as a0 + a1).
"""

import math
import sys

import corridorsim  # corridorsim puts its package on PYTHONPATH for the programs it starts


def normalize_angle(rad):
    """(-pi, pi], as common/pose.cpp's NormalizeAngle."""
    wrapped = math.remainder(rad, 2.0 * math.pi)
    return wrapped + 2.0 * math.pi if wrapped <= -math.pi else wrapped


def dot(terms):
    """A sum in Eigen's order for small fixed sizes: halves, recursively."""
    if len(terms) == 1:
        return terms[0]
    half = len(terms) // 2
    return dot(terms[:half]) + dot(terms[half:])


def matmul(a, b):
    inner = len(b)
    return [[dot([a[i][k] * b[k][j] for k in range(inner)]) for j in range(len(b[0]))]
            for i in range(len(a))]


def transpose(a):
    return [list(row) for row in zip(*a)]


class Odometry(corridorsim.Pipeline):
    def on_start(self, calibration, start):
        self.wheelbase_m = calibration.wheelbase_m
        self.k_m = float(start.options.get("k_m", 0.0001))
        self.x, self.y, self.yaw = start.pose
        self.stamp_ns = start.stamp_ns
        self.covariance = [[0.0] * 3 for _ in range(3)]  # the start pose is known exactly
        self.rejected = 0

    def on_odometry(self, o):
        left, right = o.left_m, o.right_m
        if not (math.isfinite(left) and math.isfinite(right)) or o.stamp_ns < self.stamp_ns:
            self.rejected += 1
            return
        b = self.wheelbase_m
        # P1 eq. 13: mean travel along the midpoint heading, turn by the wheels' difference / B.
        travel = 0.5 * (right + left)
        turn = (right - left) / b
        heading = self.yaw + 0.5 * turn
        c, s = math.cos(heading), math.sin(heading)
        # F and G of P1 eqs. 14-16, Q of eq. 17.
        f = [[1.0, 0.0, -travel * s], [0.0, 1.0, travel * c], [0.0, 0.0, 1.0]]
        lever = travel / (2.0 * b)
        g = [[0.5 * c + lever * s, 0.5 * c - lever * s],
             [0.5 * s - lever * c, 0.5 * s + lever * c],
             [-1.0 / b, 1.0 / b]]
        q = [[self.k_m * abs(left), 0.0], [0.0, self.k_m * abs(right)]]
        self.x, self.y = self.x + travel * c, self.y + travel * s
        self.yaw = normalize_angle(self.yaw + turn)
        # P = F P F^T + G Q G^T, then symmetrised.
        fp = matmul(matmul(f, self.covariance), transpose(f))
        gq = matmul(matmul(g, q), transpose(g))
        p = [[fp[i][j] + gq[i][j] for j in range(3)] for i in range(3)]
        self.covariance = [[0.5 * (p[i][j] + p[j][i]) for j in range(3)] for i in range(3)]
        self.stamp_ns = o.stamp_ns

    def estimate(self):
        return corridorsim.Estimate((self.x, self.y, self.yaw), self.covariance)

    def health(self):
        return {"rejected_odometry": self.rejected}


if __name__ == "__main__":
    sys.exit(corridorsim.serve(Odometry))
