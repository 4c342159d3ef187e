#!/usr/bin/python3
"""A pipeline program of protocol version 2, for tests/external/protocol_v2_test.py.

usage: sensor_client.py MODE
Dead reckoning from the wheel distances (dead_reckoning.py). It reads the IMU `imu0` and the
scanner `scanner` and declares the measurement type scan_match (3 dof). MODE:
- record: through the reference client (corridorsim.serve): writes every IMU sample and sweep it
  was given to the files `imu_file` and `scan_file` of its options (one JSON line each, ranges as
  their float32 bits in hex) and reports a scan_match innovation for every sweep;
- undeclared: like record, but its first sweep's innovation is of the type wall_line, which it
  did not declare;
- bad_imu_reply: answers its 10th imu message with a stamp that is not the message's;
- bad_scan_reply: answers its 2nd sweep with a detection (no camera goes with a sweep);
- bad_declaration: declares the measurement type lamp (a shipped type's name) in ready;
- v1_ready_with_sensors: asks for imu0 in a ready reply of version 1.
The last four speak the protocol themselves, on the framing of corridorsim.protocol.
"""

import json
import os
import socket
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import corridorsim  # noqa: E402
from corridorsim.protocol import Connection  # noqa: E402
from dead_reckoning import DeadReckoning  # noqa: E402

DECLARED = [{"name": "scan_match", "dof": 3}]


class Recorder(corridorsim.Pipeline):
    imus = ["imu0"]
    lasers = ["scanner"]
    measurement_types = [("scan_match", 3)]

    def __init__(self, mode):
        self.mode = mode

    def on_start(self, calibration, start):
        self.dead_reckoning = DeadReckoning({"pose": list(start.pose),
                                             "calibration": {"wheelbase_m": calibration.wheelbase_m}})
        self.imu_file = open(start.options["imu_file"], "w")
        self.scan_file = open(start.options["scan_file"], "w")
        self.last = None
        self.pending = []

    def on_odometry(self, odometry):
        self.last = self.dead_reckoning.step({"left_m": odometry.left_m, "right_m": odometry.right_m,
                                              "stamp_ns": odometry.stamp_ns})

    def on_imu(self, sample):
        self.imu_file.write(json.dumps({"stamp_ns": sample.stamp_ns, "sensor": sample.sensor,
                                        "gyro": sample.angular_velocity_rad_s,
                                        "accel": sample.linear_acceleration_m_s2}) + "\n")

    def on_scan(self, scan):
        bits = [struct.pack("<f", r).hex() for r in scan.ranges]
        self.scan_file.write(json.dumps({"stamp_ns": scan.stamp_ns, "sensor": scan.sensor,
                                         "angle_min_rad": scan.angle_min_rad,
                                         "angle_increment_rad": scan.angle_increment_rad,
                                         "time_increment_ns": scan.time_increment_ns,
                                         "scan_time_ns": scan.scan_time_ns,
                                         "range_min_m": scan.range_min_m,
                                         "range_max_m": scan.range_max_m, "bits": bits}) + "\n")
        kind = "wall_line" if self.mode == "undeclared" else "scan_match"
        # A NIS that follows the sweep (its count of finite ranges), chi-square-like in size.
        finite = sum(1 for r in scan.ranges if r == r and abs(r) != float("inf"))
        self.pending.append({"type": kind, "nis": 1.0 + (finite % 7) * 0.5, "dof": 3,
                             "accepted": True})

    def estimate(self):
        return self.last["pose"], [self.last["covariance"][0:3], self.last["covariance"][3:6],
                                   self.last["covariance"][6:9]]

    def innovations(self):
        out, self.pending = self.pending, []
        return out

    def finish(self):
        self.imu_file.close()
        self.scan_file.close()


def raw(mode):
    connection = Connection(socket.socket(socket.AF_UNIX, socket.SOCK_STREAM, fileno=3))
    start, _blob, _fds = connection.receive()
    ready = {"type": "ready", "protocol": 2, "imus": ["imu0"], "lasers": ["scanner"],
             "measurement_types": DECLARED}
    if mode == "bad_declaration":
        ready["measurement_types"] = [{"name": "lamp", "dof": 2}]
    if mode == "v1_ready_with_sensors":
        ready = {"type": "ready", "imus": ["imu0"]}
    connection.send(ready)
    dead_reckoning = DeadReckoning(start)
    imus = scans = 0
    for message, _blob, _fds in connection.messages():
        kind, stamp = message["type"], message.get("stamp_ns")
        if kind == "odometry":
            connection.send(dead_reckoning.step(message))
        elif kind in ("imu", "scan", "cameras"):
            reply = {"type": "processed", "stamp_ns": stamp}
            imus += kind == "imu"
            scans += kind == "scan"
            if mode == "bad_imu_reply" and kind == "imu" and imus == 10:
                print("sensor_client: a wrong stamp for imu message 10", file=sys.stderr, flush=True)
                reply["stamp_ns"] = stamp + 1
            if mode == "bad_scan_reply" and kind == "scan" and scans == 2:
                print("sensor_client: a detection for sweep 2", file=sys.stderr, flush=True)
                reply["detections"] = [{"camera": "front", "type": "lamp", "pixel": [1, 1],
                                        "radius_px": 3}]
            connection.send(reply)
        elif kind == "finish":
            connection.send({"type": "finished"})
        else:
            print("sensor_client: unknown message %r" % kind, file=sys.stderr)
            return 9
    return 0


def main():
    mode = sys.argv[1]
    if mode in ("record", "undeclared"):
        return corridorsim.serve(Recorder(mode))
    return raw(mode)


if __name__ == "__main__":
    sys.exit(main())
