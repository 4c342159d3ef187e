"""The Python client's protocol version 2 (docs/protocol.md, "Version 2") against a harness
played by the test: the negotiation in ready (the sensors a subclass reads, its measurement types),
IMU samples and laser sweeps to on_imu and on_scan (REP 117's +-inf and NaN through the blob), the
innovations of a declared type in their replies, and a corridorsim that speaks version 1 only."""

import math
import socket
import struct
import threading

import numpy as np
import pytest

import corridorsim
from corridorsim.protocol import ProtocolError
from test_client import CALIBRATION, raw_receive, raw_send

IMU = {"id": "imu0",
       "robot_from_imu": {"translation": [0.1, 0.05, 0.25], "rotation": [1, 0, 0, 0, 1, 0, 0, 0, 1]},
       "rate_hz": 1000.0, "gyroscope_noise_density": 1.6968e-4, "gyroscope_random_walk": 1.9393e-5,
       "accelerometer_noise_density": 2.0e-3, "accelerometer_random_walk": 3.0e-3}
LASER = {"id": "scanner",
         "robot_from_laser": {"translation": [0.16, 0.0, 0.3], "rotation": [1, 0, 0, 0, 1, 0, 0, 0, 1]},
         "rate_hz": 37.5, "beams": 4, "range_sigma_m": 0.01}
CALIBRATION_V2 = dict(CALIBRATION, imus=[IMU, dict(IMU, id="imu1")], lasers=[LASER])


def start_message(protocol_max=2, calibration=CALIBRATION_V2):
    message = {"type": "start", "protocol": 1, "pipeline": "mine", "seed": 7, "stamp_ns": 0,
               "pose": [0.0, 0.0, 0.0], "calibration": calibration, "cameras": [],
               "options": {}, "shared_memory_bytes": 0}
    if protocol_max is not None:
        message["protocol_max"] = protocol_max
    return message


class SensorReader(corridorsim.Pipeline):
    """Reads imu0 and every scanner, declares scan_match; reports one innovation per sweep."""

    imus = ["imu0"]
    lasers = True
    measurement_types = [("scan_match", 3), {"name": "gyro_bias", "dof": 1}]

    def on_start(self, calibration, start):
        self.calibration = calibration
        self.samples, self.scans, self.pending = [], [], []

    def on_imu(self, sample):
        self.samples.append(sample)

    def on_scan(self, scan):
        self.scans.append(scan)
        self.pending.append({"type": "scan_match", "nis": 2.5, "dof": 3, "accepted": True})

    def estimate(self):
        return corridorsim.Estimate([0.0, 0.0, 0.0], np.eye(3))

    def innovations(self):
        out, self.pending = self.pending, []
        return out


def serve_in_thread(pipeline):
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
    result = {}

    def client():
        try:
            result["rc"] = corridorsim.serve(pipeline, fd=theirs.detach())
        except Exception as e:  # the test reads it
            result["error"] = e

    thread = threading.Thread(target=client)
    thread.start()
    return ours, thread, result


def finish(sock, thread):
    raw_send(sock, {"type": "finish", "stamp_ns": 100})
    finished = raw_receive(sock)
    sock.close()
    thread.join(10)
    assert not thread.is_alive()
    return finished


def test_ready_says_version_2_with_the_sensors_read_and_the_types_declared():
    pipeline = SensorReader()
    sock, thread, result = serve_in_thread(pipeline)
    raw_send(sock, start_message())
    ready, _ = raw_receive(sock)
    assert ready == {"type": "ready", "name": "SensorReader", "protocol": 2, "imus": ["imu0"],
                     "lasers": ["scanner"],
                     "measurement_types": [{"name": "scan_match", "dof": 3},
                                           {"name": "gyro_bias", "dof": 1}]}
    imu = pipeline.calibration.imus["imu1"]
    assert imu.translation == (0.1, 0.05, 0.25) and imu.rate_hz == 1000.0
    assert pipeline.calibration.lasers["scanner"].beams == 4
    finish(sock, thread)
    assert result.get("rc") == 0


def test_imu_samples_and_sweeps_reach_their_hooks_exactly_and_their_replies_carry_innovations():
    """An imu message of two samples: on_imu twice, one reply; a sweep: on_scan, its reply
    carries the scan_match innovation."""
    pipeline = SensorReader()
    sock, thread, result = serve_in_thread(pipeline)
    raw_send(sock, start_message())
    raw_receive(sock)
    gyro, accel = [0.1, -2.5e-7, 1.0 / 3.0], [0.01, 0.2, 9.81]
    raw_send(sock, {"type": "imu", "stamp_ns": 1000000, "samples": [
        {"stamp_ns": 999000, "sensor": "imu0", "angular_velocity_rad_s": [0, 0, 0],
         "linear_acceleration_m_s2": [0, 0, 9.81]},
        {"stamp_ns": 1000000, "sensor": "imu0", "angular_velocity_rad_s": gyro,
         "linear_acceleration_m_s2": accel}]})
    processed_imu, _ = raw_receive(sock)
    ranges = [1.25, math.inf, -math.inf, math.nan]
    blob = b"pad" + struct.pack("<4f", *ranges)
    raw_send(sock, {"type": "scan", "stamp_ns": 2000000, "sensor": "scanner",
                    "angle_min_rad": -1.5, "angle_increment_rad": 0.01, "time_increment_ns": 37000,
                    "scan_time_ns": 26666667, "range_min_m": 0.1, "range_max_m": 80.0,
                    "ranges": {"encoding": "float32", "count": 4, "offset": 3, "bytes": 16}}, blob)
    processed_scan, _ = raw_receive(sock)
    finish(sock, thread)
    assert result.get("rc") == 0, result
    assert processed_imu == {"type": "processed", "stamp_ns": 1000000}
    assert processed_scan == {"type": "processed", "stamp_ns": 2000000,
                              "innovations": [{"type": "scan_match", "nis": 2.5, "dof": 3,
                                               "accepted": True}]}
    first, sample = pipeline.samples
    assert first.stamp_ns == 999000 and first.linear_acceleration_m_s2 == (0, 0, 9.81)
    assert (sample.stamp_ns, sample.sensor) == (1000000, "imu0")
    assert sample.angular_velocity_rad_s == tuple(gyro)
    assert sample.linear_acceleration_m_s2 == tuple(accel)
    (scan,) = pipeline.scans
    assert (scan.stamp_ns, scan.sensor, scan.time_increment_ns) == (2000000, "scanner", 37000)
    assert scan.ranges.dtype == np.float32 and scan.ranges.flags.writeable
    assert scan.ranges[0] == np.float32(1.25)
    assert scan.ranges[1] == np.inf and scan.ranges[2] == -np.inf and np.isnan(scan.ranges[3])


def test_a_pipeline_that_reads_nothing_of_version_2_says_so_and_asks_for_nothing():
    class Plain(SensorReader):
        imus = lasers = measurement_types = ()

    sock, thread, result = serve_in_thread(Plain())
    raw_send(sock, start_message())
    ready, _ = raw_receive(sock)
    finish(sock, thread)
    assert ready == {"type": "ready", "name": "Plain", "protocol": 2}


def test_against_a_version_1_corridorsim_the_client_speaks_version_1():
    class Plain(SensorReader):
        imus = lasers = measurement_types = ()

    sock, thread, result = serve_in_thread(Plain())
    raw_send(sock, start_message(protocol_max=None, calibration=CALIBRATION))
    ready, _ = raw_receive(sock)
    finish(sock, thread)
    assert ready == {"type": "ready", "name": "Plain"} and result.get("rc") == 0


def test_a_pipeline_that_needs_version_2_refuses_a_version_1_corridorsim():
    sock, thread, result = serve_in_thread(SensorReader())
    raw_send(sock, start_message(protocol_max=None, calibration=CALIBRATION))
    thread.join(10)
    sock.close()
    assert isinstance(result.get("error"), ProtocolError)
    assert "protocol 1 at most" in str(result["error"])


def test_a_sensor_the_robot_lacks_is_refused_naming_those_it_has():
    class Wrong(SensorReader):
        imus = ["imu9"]

    sock, thread, result = serve_in_thread(Wrong())
    raw_send(sock, start_message())
    thread.join(10)
    sock.close()
    assert isinstance(result.get("error"), ValueError)
    assert "imu9" in str(result["error"]) and "imu0, imu1" in str(result["error"])


def test_sensors_may_be_chosen_in_on_start_from_the_calibration():
    class Chooser(SensorReader):
        def on_start(self, calibration, start):
            super().on_start(calibration, start)
            self.imus = sorted(calibration.imus)[1:]
            self.lasers = []
            self.measurement_types = []

    sock, thread, result = serve_in_thread(Chooser())
    raw_send(sock, start_message())
    ready, _ = raw_receive(sock)
    finish(sock, thread)
    assert ready == {"type": "ready", "name": "Chooser", "protocol": 2, "imus": ["imu1"]}
