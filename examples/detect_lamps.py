#!/usr/bin/python3
"""A small detector of ceiling lamps in upward images, as a worked example of developing a
detector on a `corridorsim dataset` and scoring it with `corridorsim score` (docs/datasets.md).

    /usr/bin/python3 examples/detect_lamps.py DIR [--camera upward] > detections.json

Reads DIR/<camera>/annotations.json for the image list (the labels are not looked at), finds
bright blobs (the lamps are the only saturated surfaces of a corridor ceiling: a threshold, a
morphological opening against isolated noisy pixels, cv2.findContours), fits each with
cv2.minEnclosingCircle and writes COCO results on stdout: one detection per blob with its circle
and box in COCO's pixel convention (pixel centres at +0.5) and its circularity
4 pi area / perimeter^2 as the score. Needs Debian's python3-opencv (run it with /usr/bin/python3).
"""

import argparse
import json
import math
import sys
from pathlib import Path

import cv2
import numpy as np

LAMP_CATEGORY = 3  # docs/datasets.md: the dataset's fixed category ids
THRESHOLD = 250  # grey level of a lit lamp's face (it saturates; lit walls stay below)
MIN_AREA_PX = 3  # blobs smaller than this are noise


def detect(image_bgr):
    """Circles (cx, cy, r) in COCO pixels and their scores, for one image."""
    grey = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY)
    _, mask = cv2.threshold(grey, THRESHOLD, 255, cv2.THRESH_BINARY)
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(mask, connectivity=8)
    found = []
    for k in range(1, count):
        area = int(stats[k, cv2.CC_STAT_AREA])
        if area < MIN_AREA_PX:
            continue
        x0, y0 = stats[k, cv2.CC_STAT_LEFT], stats[k, cv2.CC_STAT_TOP]
        w, h = stats[k, cv2.CC_STAT_WIDTH], stats[k, cv2.CC_STAT_HEIGHT]
        blob = (labels[y0:y0 + h, x0:x0 + w] == k).astype(np.uint8)
        # Padded so that a blob touching its box still has a closed outline.
        contours, _ = cv2.findContours(np.pad(blob, 1), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        outline = max(contours, key=len)
        (_, _), enclosing_r = cv2.minEnclosingCircle(outline)
        # Circularity as the share of the enclosing circle the blob fills (1 for a disc; the
        # outline's 4 pi A / P^2 is too coarse for blobs a few pixels wide). Enclosing circle
        # of pixel centres: half a pixel more reaches the blob's edge.
        circularity = min(1.0, area / (math.pi * (enclosing_r + 0.5)**2))
        # The centre is the blob's centroid, the radius its outline's mean distance from it (the
        # dataset's circle is the rim's mean distance too: near the fisheye's edge a lamp is an
        # ellipse), plus the half pixel from outline pixel centres to the blob's edge.
        cx, cy = centroids[k]
        points = outline.reshape(-1, 2) + np.array([x0 - 1, y0 - 1])  # undo the box and padding
        r = float(np.mean(np.hypot(points[:, 0] - cx, points[:, 1] - cy))) + 0.5
        found.append(((cx + 0.5, cy + 0.5, r), circularity))
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dataset", type=Path, help="dataset folder (corridorsim dataset --out)")
    parser.add_argument("--camera", default="upward", help="camera folder (default upward)")
    args = parser.parse_args()
    camera_dir = args.dataset / args.camera
    annotations = camera_dir / "annotations.json"
    try:
        images = json.loads(annotations.read_text())["images"]
    except (OSError, ValueError, KeyError) as error:
        sys.exit(f"detect_lamps.py: {annotations}: {error}")
    detections = []
    for image in images:
        path = camera_dir / image["file_name"]
        bgr = cv2.imread(str(path), cv2.IMREAD_COLOR)
        if bgr is None:
            sys.exit(f"detect_lamps.py: {path}: cannot be read")
        for (cx, cy, r), score in detect(bgr):
            detections.append({
                "image_id": image["id"],
                "category_id": LAMP_CATEGORY,
                "circle": [round(cx, 3), round(cy, 3), round(r, 3)],
                "bbox": [round(cx - r, 3), round(cy - r, 3), round(2 * r, 3), round(2 * r, 3)],
                "score": round(score, 4),
            })
    json.dump(detections, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
