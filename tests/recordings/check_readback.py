#!/usr/bin/python3
"""Checks a recording read back by the ecosystem's readers against the run folder's files.

Usage: check_readback.py MESSAGES.jsonl RUN_FOLDER [EXPORT_FOLDER]

MESSAGES.jsonl is what tests/recordings/read_mcap.mjs printed for RUN_FOLDER/recording.mcap
(@mcap/core with @foxglove/rosmsg2-serialization): one JSON line per message in log-time order,
then a summary line. Every comparison is exact: stamps as integer nanoseconds; numbers the run
folder prints are formatted from the recorded doubles with the same printf format and compared as
text (ground_truth.tum, <pipeline>.tum, <pipeline>_cov.txt, sensors/*.csv); images byte for byte
against the --export dataset's lossless PNGs. Exit 0 when everything matches, else 1 with the
first difference.
"""
import csv
import hashlib
import json
import math
import os
import sys


def fail(message):
    print("check_readback: " + message, file=sys.stderr)
    sys.exit(1)


def stamp_ns(header):
    # @foxglove/rosmsg2-serialization reads builtin_interfaces/Time as {sec, nsec}.
    stamp = header["stamp"]
    return int(stamp["sec"]) * 1_000_000_000 + int(stamp["nsec"] if "nsec" in stamp else stamp["nanosec"])


def stamp_text(ns):
    return "%d.%09d" % (ns // 1_000_000_000, ns % 1_000_000_000)


def num(v):
    return {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}.get(v, v) if isinstance(v, str) else v


def g9(v):  # CsvNumber: %.9g, REP 117's non-finite as inf, -inf, nan
    v = num(v)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return "%.9g" % v


def read_messages(path):
    messages, summary = [], None
    with open(path) as f:
        for line in f:
            record = json.loads(line)
            if "summary" in record:
                summary = record["summary"]
            else:
                messages.append(record)
    if summary is None:
        fail(path + ": no summary line")
    return messages, summary


def unsigned_zero(tokens):
    # JSON has no negative zero (JavaScript's JSON.stringify(-0) is "0"): "-0.000000" and
    # "0.000000" are the same number read back.
    return [t[1:] if t.startswith("-") and float(t) == 0 else t for t in tokens]


def tum_lines(path):
    with open(path) as f:
        return [unsigned_zero(l.split()) for l in f if l.strip() and not l.startswith("#")]


def check_truth(by_topic, run):
    truth = [m["message"] for m in by_topic.get("/corridorsim/truth", [])]
    if not truth or truth[0]["kind"] != 0 or truth[-1]["kind"] != 2:
        fail("/corridorsim/truth must start with kind 0 and end with kind 2")
    samples = [t for t in truth if t["kind"] in (0, 1)]
    lines = tum_lines(os.path.join(run, "ground_truth.tum"))
    if len(lines) != len(samples):
        fail("ground_truth.tum has %d poses, /corridorsim/truth %d samples" % (len(lines), len(samples)))
    for line, t in zip(lines, samples):
        # SE3::FromSE2: Eigen's AngleAxis about +z (x and y are 0 * sin(yaw / 2), signed zeros).
        s, c = math.sin(t["yaw"] / 2), math.cos(t["yaw"] / 2)
        want = [stamp_text(stamp_ns(t["header"])), "%.6f" % t["x"], "%.6f" % t["y"], "%.6f" % 0.0,
                "%.9f" % (0.0 * s), "%.9f" % (0.0 * s), "%.9f" % s, "%.9f" % c]
        want = unsigned_zero(want)
        if line != want:
            fail("ground_truth.tum line %s differs from the recording's truth %s" % (line, want))
    tf = by_topic.get("/tf", [])
    if len(tf) != len(samples):
        fail("/tf has %d messages, the truth %d samples" % (len(tf), len(samples)))
    for m, t in zip(tf, samples):
        tr = m["message"]["transforms"][0]
        if (tr["header"]["frame_id"], tr["child_frame_id"]) != ("map", "base_link"):
            fail("/tf is not map -> base_link")
        if stamp_ns(tr["header"]) != stamp_ns(t["header"]) or int(m["log_time"]) != stamp_ns(t["header"]):
            fail("/tf stamp differs from the truth's")
        p = t["pose"]
        if [tr["transform"]["translation"][k] for k in "xyz"] != [p["position"][k] for k in "xyz"] or \
           [tr["transform"]["rotation"][k] for k in "xyzw"] != [p["orientation"][k] for k in "xyzw"]:
            fail("/tf at %s differs from /corridorsim/truth's pose" % stamp_text(stamp_ns(t["header"])))
    return len(samples)


def check_pipelines(by_topic, run):
    with open(os.path.join(run, "metrics.json")) as f:
        metrics = json.load(f)
    names = [n for n in metrics["pipelines"] if os.path.exists(os.path.join(run, n + ".tum"))]
    if not names:
        fail("no pipeline trajectories in " + run)
    for name in names:
        poses = by_topic.get("/slam/%s/pose" % name, [])
        lines = tum_lines(os.path.join(run, name + ".tum"))
        cov = tum_lines(os.path.join(run, name + "_cov.txt"))
        if len(poses) != len(lines) or len(cov) != len(lines):
            fail("%s: %d estimates in the run folder, %d on /slam/%s/pose" % (name, len(lines), len(poses), name))
        for m, line, c in zip(poses, lines, cov):
            msg = m["message"]
            p, q = msg["pose"]["pose"]["position"], msg["pose"]["pose"]["orientation"]
            want = [stamp_text(stamp_ns(msg["header"]))] + ["%.6f" % p[k] for k in "xyz"] + \
                   ["%.9f" % q[k] for k in "xyzw"]
            want = unsigned_zero(want)
            if line != want:
                fail("%s.tum line %s differs from the recording's %s" % (name, line, want))
            k = msg["pose"]["covariance"]
            want_cov = want[:8] + ["0"] * 5 + unsigned_zero(
                ["%.9e" % k[35], "%.9e" % k[0], "%.9e" % k[1], "0", "%.9e" % k[7], "0", "0"])
            if c != want_cov:
                fail("%s_cov.txt line %s differs from the recording's covariance %s" % (name, c, want_cov))
        if len(by_topic.get("/slam/%s/path" % name, [])) != 1:
            fail("/slam/%s/path: expected one message" % name)
        path = by_topic["/slam/%s/path" % name][0]["message"]["poses"]
        if len(path) != len(lines):
            fail("/slam/%s/path has %d poses, the trajectory %d" % (name, len(path), len(lines)))
    return names


def check_sensors(by_topic, run):
    checked = 0
    sensors = os.path.join(run, "sensors")
    if not os.path.isdir(sensors):
        return 0
    for file in sorted(os.listdir(sensors)):
        if file.endswith("_imu.csv"):
            imu = file[: -len("_imu.csv")]
            samples = by_topic.get("/%s/imu" % imu, [])
            truth = by_topic.get("/corridorsim/%s/truth" % imu, [])
            with open(os.path.join(sensors, file)) as f:
                rows = list(csv.reader(f))[1:]
            if len(rows) != len(samples) or len(rows) != len(truth):
                fail("%s: %d rows, /%s/imu %d messages" % (file, len(rows), imu, len(samples)))
            for row, s, t in zip(rows, samples, truth):
                s, t = s["message"], t["message"]
                v = lambda d: [d[k] for k in "xyz"]
                values = v(s["angular_velocity"]) + v(s["linear_acceleration"]) + \
                    v(t["exact_angular_velocity"]) + v(t["exact_linear_acceleration"]) + \
                    v(t["gyroscope_bias"]) + v(t["accelerometer_bias"]) + \
                    v(t["world_from_imu"]["position"]) + \
                    [t["world_from_imu"]["orientation"][k] for k in "xyzw"] + v(t["velocity_in_world"])
                want = [stamp_text(stamp_ns(s["header"]))] + [g9(x) for x in values]
                if row != want:
                    fail("%s row %s differs from the recording's %s" % (file, row[:4], want[:4]))
                if s["orientation_covariance"][0] != -1:
                    fail("/%s/imu: orientation_covariance[0] must be -1 (REP 145)" % imu)
            checked += len(rows)
        if file.endswith("_scans.csv"):
            laser = file[: -len("_scans.csv")]
            scans = by_topic.get("/%s/scan" % laser, [])
            with open(os.path.join(sensors, file)) as f:
                rows = list(csv.reader(f))[1:]
            if len(rows) != len(scans):
                fail("%s: %d sweeps, /%s/scan %d" % (file, len(rows), laser, len(scans)))
            for row, m in zip(rows, scans):
                s = m["message"]
                want = [stamp_text(stamp_ns(s["header"]))] + [g9(r) for r in s["ranges"]]
                if [row[0]] + row[7:] != want:
                    fail("%s: the sweep at %s differs from /%s/scan's ranges" % (file, row[0], laser))
                if s["header"]["frame_id"] != laser + "_link":
                    fail("/%s/scan: frame_id %s" % (laser, s["header"]["frame_id"]))
            checked += len(rows)
    return checked


def check_images(by_topic, export):
    import cv2  # python3-opencv
    rgb_dir = os.path.join(export, "tum_rgbd", "rgb")
    images = by_topic.get("/front/image_raw", [])
    if not images:
        fail("no /front/image_raw messages")
    for m in images:
        msg = m["message"]
        t = stamp_ns(msg["header"])
        png = cv2.imread(os.path.join(rgb_dir, "%d.png" % t), cv2.IMREAD_UNCHANGED)
        if png is None:
            fail("the export has no front frame at %d ns" % t)
        rgb = cv2.cvtColor(png, cv2.COLOR_BGR2RGB)
        if msg["encoding"] != "rgb8" or msg["width"] != rgb.shape[1] or msg["height"] != rgb.shape[0] \
                or msg["step"] != 3 * rgb.shape[1]:
            fail("/front/image_raw at %d: %s %dx%d step %d" % (t, msg["encoding"], msg["width"], msg["height"], msg["step"]))
        if msg["data"]["sha256"] != hashlib.sha256(rgb.tobytes()).hexdigest():
            fail("/front/image_raw at %d ns differs from the export's PNG, byte for byte" % t)
    return len(images)


def main():
    if len(sys.argv) not in (3, 4):
        fail("usage: check_readback.py MESSAGES.jsonl RUN_FOLDER [EXPORT_FOLDER]")
    messages, summary = read_messages(sys.argv[1])
    run = sys.argv[2]
    by_topic = {}
    for m in messages:
        by_topic.setdefault(m["topic"], []).append(m)
    if summary.get("profile") != "ros2":
        fail("profile %r, expected ros2" % summary.get("profile"))
    for topic in ("/tf_static", "/tf", "/ground_truth/odom", "/odom", "/world/markers",
                  "/corridorsim/truth", "/corridorsim/wheel_odometry"):
        if topic not in by_topic:
            fail("no messages on " + topic)
    for m in messages:
        if int(m["log_time"]) < 0:
            fail("negative log time")
    n_truth = check_truth(by_topic, run)
    names = check_pipelines(by_topic, run)
    n_sensors = check_sensors(by_topic, run)
    n_images = check_images(by_topic, sys.argv[3]) if len(sys.argv) == 4 else 0
    if len(by_topic["/odom"]) != len(by_topic["/corridorsim/wheel_odometry"]):
        fail("/odom and /corridorsim/wheel_odometry differ in count")
    with open(os.path.join(run, "events.json")) as f:
        events = json.load(f)
    n_events = len(events.get("events", []))
    if len(by_topic.get("/corridorsim/events", [])) != n_events:
        fail("events.json has %d events, /corridorsim/events %d" % (n_events, len(by_topic.get("/corridorsim/events", []))))
    print("check_readback: ok: %d messages on %d topics; %d truth samples, pipelines %s, %d IMU/scan rows, "
          "%d images byte-equal, %d events" % (len(messages), len(by_topic), n_truth, ", ".join(names),
                                                n_sensors, n_images, n_events))


if __name__ == "__main__":
    main()
