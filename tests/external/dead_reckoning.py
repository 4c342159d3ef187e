"""Dead reckoning from the wheel distances, shared by the test pipeline programs in this folder
(reply_keys_program.py, supervision_descendants.py; misbehave.py keeps its own copy because
external_test.py runs it copied alone into a work folder)."""

import math

# A fixed, small covariance: these programs test the protocol, not the estimate.
COVARIANCE = [1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-5]


class DeadReckoning:
    """The pose (x, y, yaw) integrated from odometry messages (P1 eq. 13 without the midpoint
    heading: these programs' estimates only need to stay near the truth)."""

    def __init__(self, start):
        self.x, self.y, self.yaw = start["pose"]
        self.wheelbase_m = start["calibration"]["wheelbase_m"]

    def step(self, message):
        """Integrates one odometry message; returns the estimate message for its stamp."""
        left, right = message["left_m"], message["right_m"]
        travel = 0.5 * (left + right)
        self.x += travel * math.cos(self.yaw)
        self.y += travel * math.sin(self.yaw)
        self.yaw = math.remainder(self.yaw + (right - left) / self.wheelbase_m, 2 * math.pi)
        return {"type": "estimate", "stamp_ns": message["stamp_ns"],
                "pose": [self.x, self.y, self.yaw], "covariance": list(COVARIANCE)}
