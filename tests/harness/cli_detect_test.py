#!/usr/bin/env python3
"""`corridorsim detect` as a user runs it, on frames `corridorsim snapshot` renders: the vanishing
point within a few px of the frame's ground truth, every corner's depth the median of its 3x3
window in front_depth.png, no point for a wall seen head-on, the same bytes twice, and exit code 2
with one message naming the file for bad input.

Usage: cli_detect_test.py CORRIDORSIM SOURCE_DIR WORK_DIR"""

import json
import os
import shutil
import struct
import subprocess
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_test_support import fail, run  # noqa: E402

# tests/support/feature_tolerances.h: kRenderedVanishingPointPx.
RENDERED_VANISHING_POINT_PX = 4.0


def read_png(path):
    """Grey or RGB, 8 or 16 bits, not interlaced (what OpenCV writes): (width, height, rows)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    assert interlace == 0 and colour in (0, 2), path
    channels = 1 if colour == 0 else 3
    bpp = channels * depth // 8
    stride = width * bpp
    raw = zlib.decompress(idat)
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 0xFF
            elif f == 2:
                line[i] = (line[i] + b) & 0xFF
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 0xFF
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF
        prev = line
        if depth == 16:
            rows.append([(line[2 * i] << 8) | line[2 * i + 1] for i in range(width * channels)])
        else:
            rows.append(list(line))
    return width, height, rows


def write_png(path, width, height, depth, channels, value):
    """A constant image: `depth` bits, 1 or 3 channels."""
    colour = 0 if channels == 1 else 2
    sample = value.to_bytes(depth // 8, "big") * channels
    raw = b"".join(b"\x00" + sample * width for _ in range(height))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) +
                chunk(b"IEND", b""))


def median3x3(depth_rows, width, height, x, y):
    values = sorted(depth_rows[v][u] / 5000.0 for v in range(y - 1, y + 2)
                    for u in range(x - 1, x + 2)
                    if 0 <= u < width and 0 <= v < height and depth_rows[v][u] > 0)
    if not values:
        return None
    n = len(values)
    return values[n // 2] if n % 2 else 0.5 * (values[n // 2 - 1] + values[n // 2])


def main():
    binary, source, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scenario = os.path.join(source, "scenarios", "default.yaml")

    # Down the corridor, straight and at an angle: the vanishing point against the truth.
    for pose in ("10,0,0", "20,0.3,8"):
        snap = os.path.join(work, "snap_" + pose.replace(",", "_"))
        run(binary, ["snapshot", scenario, "--pose", pose, "--out", snap], 0, source)
        image, depth = os.path.join(snap, "front_rgb.png"), os.path.join(snap, "front_depth.png")
        overlay = os.path.join(work, "overlay_" + pose.replace(",", "_") + ".png")
        out = run(binary, ["detect", image, "--depth", depth, "--out", overlay], 0, source).stdout
        again = run(binary, ["detect", image, "--depth", depth], 0, source).stdout
        if out != again:
            fail(pose + ": two runs printed different JSON")
        if not os.path.isfile(overlay) or open(overlay, "rb").read(8) != b"\x89PNG\r\n\x1a\n":
            fail(pose + ": no overlay PNG written")
        doc = json.loads(out)
        if doc["camera"] != "front" or (doc["width"], doc["height"]) != (640, 480):
            fail(pose + ": unexpected header " + json.dumps(doc)[:200])
        truth = json.load(open(os.path.join(snap, "frame_ground_truth.json")))
        points = [p for p in truth["cameras"]["front"]["vanishing_points"]
                  if p["camera_in_segment"] and p["in_image"]]
        if len(points) != 1:
            fail(pose + ": expected one true vanishing point in the image, got %d" % len(points))
        vp = doc["vanishing_point"]
        if not vp["found"] or vp["status"] != "found":
            fail(pose + ": no vanishing point: " + json.dumps(vp["quality"]))
        error = ((vp["pixel"][0] - points[0]["pixel"][0]) ** 2 +
                 (vp["pixel"][1] - points[0]["pixel"][1]) ** 2) ** 0.5
        print("%s: vanishing point (%.2f, %.2f), truth (%.2f, %.2f), error %.2f px, %d lines" %
              (pose, vp["pixel"][0], vp["pixel"][1], points[0]["pixel"][0],
               points[0]["pixel"][1], error, vp["quality"]["line_count"]))
        if error > RENDERED_VANISHING_POINT_PX:
            fail(pose + ": vanishing point %.2f px from the truth" % error)
        if len(vp["lines"]) != vp["quality"]["line_count"] or vp["quality"]["line_count"] < 4:
            fail(pose + ": lines and line_count disagree or too few lines")

        # Every corner's depth: the median of the valid depths of its 3x3 window.
        width, height, depth_rows = read_png(depth)
        corners = doc["corners"]
        if corners["count"] < 10 or corners["count"] != len(corners["items"]):
            fail(pose + ": %d corners" % corners["count"])
        with_depth = 0
        for c in corners["items"]:
            x, y = int(round(c["pixel"][0])), int(round(c["pixel"][1]))
            expected = median3x3(depth_rows, width, height, x, y)
            if (expected is None) != (c["depth_m"] is None) or (
                    expected is not None and abs(expected - c["depth_m"]) > 1e-5):
                fail("%s: corner at %s has depth %s, expected %s" %
                     (pose, c["pixel"], c["depth_m"], expected))
            with_depth += c["depth_m"] is not None
        if with_depth == 0 or with_depth != corners["with_depth"]:
            fail(pose + ": with_depth %d, counted %d" % (corners["with_depth"], with_depth))

    # A wall seen head-on: no vanishing point. The lateral camera: no vanishing point section.
    wall = os.path.join(work, "wall")
    run(binary, ["snapshot", scenario, "--pose", "10,0,90", "--out", wall], 0, source)
    doc = json.loads(run(binary, ["detect", os.path.join(wall, "front_rgb.png")], 0,
                         source).stdout)
    if doc["vanishing_point"]["found"]:
        fail("a wall seen head-on gave a vanishing point " + str(doc["vanishing_point"]["pixel"]))
    lateral = json.loads(run(binary, ["detect", os.path.join(wall, "lateral_rgb.png"),
                                      "--camera", "lateral"], 0, source).stdout)
    if "vanishing_point" in lateral or lateral["camera"] != "lateral" or any(
            c["depth_m"] is not None for c in lateral["corners"]["items"]):
        fail("the lateral camera's document: " + json.dumps(lateral)[:300])

    # Bad input: exit 2, one message naming the file, nothing on stdout.
    image = os.path.join(work, "snap_10_0_0", "front_rgb.png")
    small_depth = os.path.join(work, "small_depth.png")
    write_png(small_depth, 320, 240, 16, 1, 5000)
    rgb_depth = os.path.join(work, "rgb_depth.png")
    write_png(rgb_depth, 640, 480, 8, 3, 100)
    huge = os.path.join(work, "huge.png")
    write_png(huge, 9000, 2, 8, 1, 0)
    not_png = os.path.join(work, "not_a.png")
    open(not_png, "w").write("hello\n")
    missing = os.path.join(work, "missing.png")
    deep = os.path.join(work, "deep.json")
    open(deep, "w").write("[" * 100000)
    for args, pattern in (
            ([image, "--camera", "upward", "--intrinsics", deep],
             deep + ":1:65: more than 64 nested arrays and objects"),
            ([image, "--out", work], "command line: --out: '" + work + "' is a folder"),
            ([missing], missing + ": cannot be opened"),
            ([not_png], not_png + ": is not a PNG image"),
            ([work], work + ": is not a regular file"),
            ([huge], huge + ": is 9000x2 px: each side must lie in [1, 8192]"),
            ([image, "--depth", small_depth], small_depth + ": --depth: the depth image is 320x240"),
            ([image, "--depth", rgb_depth], rgb_depth + ": --depth: expected a 16-bit"),
            ([image, "--depth", missing], missing + ": cannot be opened"),
            ([image, "--camera", "rear"], "command line: --camera: expected front, lateral or upward"),
            ([image, "--camera", "lateral", "--depth", small_depth],
             "command line: --depth: only the front camera"),
            ([image, "--out", os.path.join(work, "no", "o.png")], "command line: --out: the folder")):
        result = run(binary, ["detect"] + args, 2, source)
        lines = result.stderr.strip().splitlines()
        if len(lines) != 1 or pattern not in lines[0] or result.stdout:
            fail("detect %s: expected one message containing '%s', got:\n%s%s" %
                 (" ".join(args), pattern, result.stderr, result.stdout))

    # A file name that is not UTF-8 is written with U+FFFD in its place (it stopped the JSON
    # document with exit 1).
    odd = os.path.join(os.fsencode(work), b"\xff.png")
    shutil.copyfile(image, odd)
    result = subprocess.run([os.fsencode(binary), b"detect", odd], cwd=source, capture_output=True)
    if result.returncode != 0:
        fail("detect on a non-UTF-8 file name: exit %d\n%s" % (result.returncode, result.stderr))
    doc = json.loads(result.stdout.decode("utf-8"))
    if not doc["image"].endswith("\ufffd.png"):
        fail("detect on a non-UTF-8 file name: image " + repr(doc["image"]))
    print("ok")


if __name__ == "__main__":
    main()
