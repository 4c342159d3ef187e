#!/usr/bin/python3
"""`corridorsim run --record-bag` as a user meets it (docs/recordings.md): a short default run
writes recording.bag (and no recording.mcap), which python3-rosbag (ROS's own reader) opens; its
topics and types are the documented ones, every connection's MD5 is the one genmsg computes from
its stored definition, the message counts and stamps equal the run folder's files (ground_truth.tum
against /tf, <pipeline>.tum against /slam/<pipeline>/pose and its path, the --export dataset's
front images against /front/image_raw, byte for byte), the headers' seq count each topic's
messages, and a second run writes the same bytes. --record-topics keeps the matching topics;
--record-topics without --record or --record-bag exits 2.

usage: bag_run_test.py CORRIDORSIM SOURCE_DIR WORK_DIR
"""

import os
import struct
import sys
import zlib

import rosbag

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "harness"))
from cli_test_support import NO_EXTRAS, fail, fresh_folder, read, run  # noqa: E402

PIPELINES = ["odometry", "p1_harris", "p1_vp_doorplate"]
# Topic -> ROS 1 type: the default scenario's (front RGB-D and lateral cameras, no IMU, no laser).
EXPECTED_TYPES = {
    "/tf": "tf2_msgs/TFMessage",
    "/tf_static": "tf2_msgs/TFMessage",
    "/ground_truth/odom": "nav_msgs/Odometry",
    "/odom": "nav_msgs/Odometry",
    "/world/markers": "visualization_msgs/MarkerArray",
    "/corridorsim/truth": "corridorsim_msgs/Truth",
    "/corridorsim/wheel_odometry": "corridorsim_msgs/WheelOdometry",
    "/corridorsim/camera_set": "corridorsim_msgs/CameraSet",
    "/front/image_raw": "sensor_msgs/Image",
    "/front/camera_info": "sensor_msgs/CameraInfo",
    "/front/depth/image_raw": "sensor_msgs/Image",
    "/lateral/image_raw": "sensor_msgs/Image",
    "/lateral/camera_info": "sensor_msgs/CameraInfo",
    "/corridorsim/front/frame": "corridorsim_msgs/CameraFrame",
    "/corridorsim/lateral/frame": "corridorsim_msgs/CameraFrame",
}
for p in PIPELINES:
    EXPECTED_TYPES["/slam/%s/pose" % p] = "geometry_msgs/PoseWithCovarianceStamped"
    EXPECTED_TYPES["/slam/%s/path" % p] = "nav_msgs/Path"
    EXPECTED_TYPES["/slam/%s/landmarks" % p] = "visualization_msgs/MarkerArray"
# Topics whose messages are recorded at their header's stamp (0 recorded at 1 ns: ROS 1 has no
# earlier time).
STAMPED_AT_HEADER = {t for t, ty in EXPECTED_TYPES.items()
                     if ty not in ("tf2_msgs/TFMessage", "visualization_msgs/MarkerArray",
                                   "nav_msgs/Path")}


def tum(path):
    """[(stamp ns, x, y)] of a TUM file (nine decimals of seconds)."""
    out = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            fields = line.split()
            seconds, _, fraction = fields[0].partition(".")
            out.append((int(seconds) * 10**9 + int(fraction.ljust(9, "0")), float(fields[1]),
                        float(fields[2])))
    return out


def png_rgb8(path):
    """(width, height, bytes) of an 8-bit RGB, non-interlaced PNG (the export's)."""
    data = read(path)
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("%s: not a PNG" % path)
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, color, _, _, interlace = header
    if depth != 8 or color != 2 or interlace != 0:
        fail("%s: not 8-bit RGB non-interlaced" % path)
    raw, stride, out, previous = zlib.decompress(idat), width * 3, bytearray(), bytearray(width * 3)
    for row in range(height):
        kind = raw[row * (stride + 1)]
        line = bytearray(raw[row * (stride + 1) + 1:(row + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - 3] if i >= 3 else 0
            up = previous[i]
            up_left = previous[i - 3] if i >= 3 else 0
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                p = left + up - up_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - up_left)
                line[i] = (line[i] + (left if pa <= pb and pa <= pc else up if pb <= pc
                                      else up_left)) & 0xFF
        out += line
        previous = line
    return width, height, bytes(out)


def read_bag(path):
    """topic -> [(record time ns, message)], checking every connection's MD5 on the way."""
    messages = {}
    with rosbag.Bag(path) as bag:
        for topic, raw, stamp in bag.read_messages(raw=True):
            datatype, data, md5sum, _, pytype = raw
            if pytype._md5sum != md5sum:
                fail("%s (%s): stored MD5 %s, genmsg's of its definition %s"
                     % (topic, datatype, md5sum, pytype._md5sum))
            if EXPECTED_TYPES.get(topic, datatype) != datatype:
                fail("%s: type %s, expected %s" % (topic, datatype, EXPECTED_TYPES[topic]))
            message = pytype()
            message.deserialize(data)
            messages.setdefault(topic, []).append((stamp.to_nsec(), message))
    return messages


def ns(t):
    return t.secs * 10**9 + t.nsecs


def check_full_bag(folder, export):
    if os.path.exists(os.path.join(folder, "recording.mcap")):
        fail("--record-bag alone wrote recording.mcap")
    messages = read_bag(os.path.join(folder, "recording.bag"))
    missing = sorted(set(EXPECTED_TYPES) - set(messages))
    if missing:
        fail("topics missing from the bag: %s (it has %s)" % (missing, sorted(messages)))

    for topic in STAMPED_AT_HEADER:
        for seq, (stamp, m) in enumerate(messages[topic]):
            if stamp != max(ns(m.header.stamp), 1):
                fail("%s: recorded at %d, header stamp %d" % (topic, stamp, ns(m.header.stamp)))
            if m.header.seq != seq:
                fail("%s: message %d has seq %d" % (topic, seq, m.header.seq))

    truth = tum(os.path.join(folder, "ground_truth.tum"))
    tf = [(ns(m.transforms[0].header.stamp), m) for _, m in messages["/tf"]]
    if [t for t, _, _ in truth] != [t for t, _ in tf]:
        fail("/tf: %d stamps, ground_truth.tum %d lines, or their stamps differ"
             % (len(tf), len(truth)))
    for (t, x, y), (_, m) in zip(truth, tf):
        tr = m.transforms[0]
        if (tr.header.frame_id, tr.child_frame_id) != ("map", "base_link"):
            fail("/tf: %s -> %s, expected map -> base_link"
                 % (tr.header.frame_id, tr.child_frame_id))
        if abs(tr.transform.translation.x - x) > 1e-6 or abs(tr.transform.translation.y - y) > 1e-6:
            fail("/tf at %d: (%r, %r), ground_truth.tum (%r, %r)"
                 % (t, tr.transform.translation.x, tr.transform.translation.y, x, y))
    if len(messages["/ground_truth/odom"]) != len(truth):
        fail("/ground_truth/odom: %d messages, ground_truth.tum %d lines"
             % (len(messages["/ground_truth/odom"]), len(truth)))

    for p in PIPELINES:
        estimates = tum(os.path.join(folder, p + ".tum"))
        poses = messages["/slam/%s/pose" % p]
        if [t for t, _, _ in estimates] != [ns(m.header.stamp) for _, m in poses]:
            fail("/slam/%s/pose: %d messages, %s.tum %d lines, or their stamps differ"
                 % (p, len(poses), p, len(estimates)))
        for (t, x, y), (_, m) in zip(estimates, poses):
            position = m.pose.pose.position
            if abs(position.x - x) > 1e-6 or abs(position.y - y) > 1e-6:
                fail("/slam/%s/pose at %d: (%r, %r), %s.tum (%r, %r)"
                     % (p, t, position.x, position.y, p, x, y))
        paths = messages["/slam/%s/path" % p]
        if len(paths) != 1 or [ns(s.header.stamp) for s in paths[0][1].poses] != \
                [t for t, _, _ in estimates]:
            fail("/slam/%s/path: not one path of the %d estimates" % (p, len(estimates)))

    # The front camera's images, byte for byte against the export's PNGs (rgb8, row 0 on top).
    images = messages["/front/image_raw"]
    with open(os.path.join(export, "tum_rgbd", "rgb.txt")) as f:
        listed = [line.split()[1] for line in f if not line.startswith("#") and line.strip()]
    if len(listed) != len(images):
        fail("/front/image_raw: %d images, the export's rgb.txt %d" % (len(images), len(listed)))
    for stamp, image in (images[0], images[-1]):
        png = os.path.join(export, "tum_rgbd", "rgb", "%d.png" % ns(image.header.stamp))
        width, height, pixels = png_rgb8(png)
        if (image.encoding, image.width, image.height, image.step) != ("rgb8", width, height,
                                                                       3 * width):
            fail("/front/image_raw at %d: %s %dx%d step %d, the PNG %dx%d"
                 % (stamp, image.encoding, image.width, image.height, image.step, width, height))
        if bytes(image.data) != pixels:
            fail("/front/image_raw at %d: its bytes differ from %s" % (stamp, png))
    infos = messages["/front/camera_info"]
    if len(infos) != 1 or infos[0][1].width != images[0][1].width or len(infos[0][1].K) != 9:
        fail("/front/camera_info: not one CameraInfo of the image's size")
    print("ok: %d topics, %d messages" % (len(messages), sum(len(v) for v in messages.values())))


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: bag_run_test.py CORRIDORSIM SOURCE_DIR WORK_DIR")
    corridorsim, source, work = sys.argv[1:]
    fresh_folder(work)
    scenario = os.path.join(source, "scenarios", "default.yaml")
    # A 3 s run of the default scenario: its expectations are about the whole path.
    short = ["--set", "duration_s=3", "--set", "expectations=[]"] + NO_EXTRAS
    run(corridorsim,
        ["run", scenario] + short + ["--record-bag", "--out", "a", "--export", "a_export"], 0, work)
    check_full_bag(os.path.join(work, "a"), os.path.join(work, "a_export"))

    # Deterministic: the same run writes the same bag.
    run(corridorsim, ["run", scenario] + short + ["--record-bag", "--out", "b"], 0, work)
    if read(os.path.join(work, "a", "recording.bag")) != read(os.path.join(work, "b",
                                                                           "recording.bag")):
        fail("two identical runs wrote different recording.bag")

    # --record-topics keeps only the matching topics.
    run(corridorsim, ["run", scenario, "--set", "duration_s=1", "--set", "expectations=[]"] +
        NO_EXTRAS + ["--record-bag", "--record-topics", "/tf*,/slam/*/pose", "--out", "c"], 0, work)
    topics = sorted(read_bag(os.path.join(work, "c", "recording.bag")))
    expected = sorted(["/tf", "/tf_static"] + ["/slam/%s/pose" % p for p in PIPELINES])
    if topics != expected:
        fail("--record-topics: the bag has %s, expected %s" % (topics, expected))

    result = run(corridorsim, ["run", scenario] + NO_EXTRAS + ["--record-topics", "/tf", "--out",
                                                                "d"], 2, work)
    if "--record-topics" not in result.stderr:
        fail("--record-topics without a recording: the message does not name it: " + result.stderr)
    print("ok")


if __name__ == "__main__":
    main()
