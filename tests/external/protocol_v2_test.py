#!/usr/bin/python3
"""Protocol version 2 (docs/protocol.md, "Version 2") as a user meets it, on a robot with an IMU
and a laser scanner, each case checked from outside: the run's exit code, its reason, metrics.json,
timing.json and the run folder's sensors/ files.

- a version-1 client (misbehave.py, unchanged) runs as before and is sent no imu or scan message
  (it exits 9 on a message it does not know);
- a version-2 client of the reference Python client reading the IMU and the scanner is given
  every sample and every sweep, equal to sensors/imu0_imu.csv and sensors/scanner_scans.csv
  (stamps exact, values to the files' nine digits, ranges' float32 bits with +-inf and NaN);
  the scan_match innovations it reports (a type it declared, 3 dof) give nis.scan_match in
  metrics.json;
- an innovation of a type it did not declare, a malformed reply to an imu or a scan message, a bad
  declaration and version-2 keys in a version-1 ready fail that pipeline alone (exit 5), with the
  reason, the built-in pipeline beside it scored.

usage: protocol_v2_test.py CORRIDORSIM WORK_DIR
"""

import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "harness"))
from cli_test_support import NO_EXTRAS, fail, fresh_folder, run  # noqa: E402

IMU_RATE_HZ = 200
SCAN_RATE_HZ = 10


def scenario(path, command, options=None):
    text = """name: protocol_v2
seed: 3
world: {layout: straight, length_m: 10.0, doors: {count: 1}, plates: {count: 1}}
path: {kind: round_trip, speed_mps: 0.6}
duration_s: 12
sensors:
  front: {enabled: false}
  lateral: {enabled: false}
  upward: {enabled: false}
  imu0: {type: imu, rate_hz: %d, mount: {x_m: 0.1, y_m: 0.05, z_m: 0.25}}
  scanner: {type: laser, rate_hz: %d}
pipelines:
  odometry: {}
  mine:
    type: external
    command: %s
    timeout_s: 20
    options: %s
""" % (IMU_RATE_HZ, SCAN_RATE_HZ, json.dumps(command), json.dumps(options or {}))
    with open(path, "w") as f:
        f.write(text)
    return path


def client(mode):
    return ["/usr/bin/python3", os.path.join(HERE, "sensor_client.py"), mode]


def csv_rows(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return lines[0].split(","), [line.split(",") for line in lines[1:]]


def stamp_ns(text):
    whole, frac = text.split(".")
    return int(whole) * 10**9 + int(frac)


def nine(value):
    """A number as the sensors/ files write it (harness/run/sensor_recorder.cpp)."""
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return "%.9g" % value


def check_v1_client(binary, work):
    d = os.path.join(work, "v1")
    path = scenario(os.path.join(work, "v1.yaml"),
                    ["/usr/bin/python3", os.path.join(HERE, "misbehave.py"), "ok"])
    run(binary, ["run", path, "--out", d, *NO_EXTRAS], 0, work)
    kinds = json.load(open(os.path.join(d, "timing.json")))["pipelines"]["mine"]["protocol"][
        "round_trip_ms"]
    if sorted(kinds) != ["finish", "odometry", "start"]:
        fail("a version-1 client was sent %s" % sorted(kinds))
    if not os.path.exists(os.path.join(d, "sensors", "imu0_imu.csv")):
        fail("the version-1 run has no IMU")
    print("ok: a version-1 client runs unchanged beside an IMU and a scanner: sent %s only"
          % ", ".join(sorted(kinds)))


def check_imu(d, received):
    header, rows = csv_rows(os.path.join(d, "sensors", "imu0_imu.csv"))
    if header[:7] != ["t", "wx_rad_s", "wy_rad_s", "wz_rad_s", "ax_m_s2", "ay_m_s2", "az_m_s2"]:
        fail("imu0_imu.csv header %s" % header[:7])
    if len(received) != len(rows) or len(rows) < IMU_RATE_HZ * 10:
        fail("the client got %d IMU samples, the file has %d" % (len(received), len(rows)))
    for k, (got, row) in enumerate(zip(received, rows)):
        values = [nine(v) for v in got["gyro"] + got["accel"]]
        if got["stamp_ns"] != stamp_ns(row[0]) or got["sensor"] != "imu0" or values != row[1:7]:
            fail("IMU sample %d: the client got %s %s, the file has %s" % (
                k, got["stamp_ns"], values, row[:7]))
    print("ok: %d IMU samples, each equal to sensors/imu0_imu.csv (stamps exact)" % len(rows))


def check_scans(d, received):
    header, rows = csv_rows(os.path.join(d, "sensors", "scanner_scans.csv"))
    beams = len(header) - 7
    if len(received) != len(rows) or len(rows) < SCAN_RATE_HZ * 10:
        fail("the client got %d sweeps, the file has %d" % (len(received), len(rows)))
    special = 0
    for k, (got, row) in enumerate(zip(received, rows)):
        ranges = [struct.unpack("<f", bytes.fromhex(b))[0] for b in got["bits"]]
        fixed = [nine(got[key]) for key in ("angle_min_rad", "angle_increment_rad")] + \
            [nine(got[key] / 1e9) for key in ("time_increment_ns", "scan_time_ns")] + \
            [nine(got[key]) for key in ("range_min_m", "range_max_m")]
        if got["stamp_ns"] != stamp_ns(row[0]) or got["sensor"] != "scanner" or \
                fixed != row[1:7] or [nine(r) for r in ranges] != row[7:] or len(ranges) != beams:
            fail("sweep %d: the client got %s %s, the file has %s" % (
                k, got["stamp_ns"], fixed, row[:7]))
        special += sum(1 for r in ranges if not math.isfinite(r))
    print("ok: %d sweeps of %d beams, each equal to sensors/scanner_scans.csv (stamps exact; "
          "%d non-finite ranges as REP 117's IEEE values)" % (len(rows), beams, special))
    return len(rows)


def check_v2_client(binary, work):
    d = os.path.join(work, "v2")
    imu_file, scan_file = os.path.join(work, "imu.jsonl"), os.path.join(work, "scans.jsonl")
    path = scenario(os.path.join(work, "v2.yaml"), client("record"),
                    {"imu_file": imu_file, "scan_file": scan_file})
    run(binary, ["run", path, "--out", d, *NO_EXTRAS], 0, work)
    check_imu(d, [json.loads(line) for line in open(imu_file)])
    sweeps = check_scans(d, [json.loads(line) for line in open(scan_file)])
    nis = json.load(open(os.path.join(d, "metrics.json")))["pipelines"]["mine"].get("nis", {})
    if nis.get("scan_match", {}).get("count") != sweeps:
        fail("metrics.json's mine.nis: %s (expected scan_match with %d updates)" % (nis, sweeps))
    kinds = json.load(open(os.path.join(d, "timing.json")))["pipelines"]["mine"]["protocol"][
        "round_trip_ms"]
    if list(kinds) != ["start", "odometry", "imu", "scan", "finish"]:
        fail("timing.json's round trips: %s" % list(kinds))
    print("ok: the declared scan_match gives metrics.json nis.scan_match (%d updates, mean %s); "
          "timing.json has the imu and scan round trips (imu p50 %s ms)"
          % (sweeps, nis["scan_match"].get("mean"), kinds["imu"]["p50"]))


def check_failure(binary, work, mode, reasons):
    d = os.path.join(work, mode)
    path = scenario(os.path.join(work, mode + ".yaml"), client(mode),
                    {"imu_file": os.path.join(work, mode + "_imu.jsonl"),
                     "scan_file": os.path.join(work, mode + "_scans.jsonl")})
    result = run(binary, ["run", path, "--out", d, *NO_EXTRAS], 5, work)
    if "pipeline 'mine' failed" not in result.stderr or any(r not in result.stderr for r in reasons):
        fail("%s: stderr does not give the reason %s:\n%s" % (mode, reasons, result.stderr[-3000:]))
    metrics = json.load(open(os.path.join(d, "metrics.json")))["pipelines"]
    if metrics["mine"].get("health", {}).get("failed") != 1 or "ate_rmse_m" not in metrics["odometry"]:
        fail("%s: metrics.json %s" % (mode, metrics))
    events = json.load(open(os.path.join(d, "events.json")))["events"]
    failed = [e for e in events if e.get("type") == "pipeline_failed"]
    if len(failed) != 1 or reasons[0] not in json.dumps(failed[0]):
        fail("%s: events.json pipeline_failed %s" % (mode, failed))
    print("ok: %s fails that pipeline alone (exit 5): %s" % (mode, failed[0].get("reason", "")[:230]))


def main():
    binary, work = sys.argv[1], os.path.abspath(sys.argv[2])
    fresh_folder(work)
    check_v1_client(binary, work)
    check_v2_client(binary, work)
    check_failure(binary, work, "undeclared",
                  ["unknown type 'wall_line'", "scan_match (3 dof)", "'scan' message"])
    check_failure(binary, work, "bad_imu_reply", ["'imu' message", "out of order"])
    check_failure(binary, work, "bad_scan_reply",
                  ["'scan' message", "detections come with camera sets"])
    check_failure(binary, work, "bad_declaration",
                  ["ready.measurement_types", "shipped landmark type"])
    check_failure(binary, work, "v1_ready_with_sensors",
                  ["'imus' is a key of protocol version 2"])
    print("all protocol version 2 cases passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
