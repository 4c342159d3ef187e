"""A dataset or an export as pandas DataFrames (`corridorsim.Dataset`, docs/analysis.md): the
frames of each camera with their image, label, truth and depth paths, and the COCO boxes. Files are
read through corridorsim.dataset_files' strict readers."""

import os
import re

import numpy as np
import pandas as pd

from . import dataset_files, files
from .files import InputError

__all__ = ["Dataset", "load_image"]


def load_image(path):
    """An image file as a numpy array: with OpenCV (cv2) when it is installed, the values as
    stored (uint8 or uint16), channels in RGB order; else with matplotlib.image.imread (PNG as
    float32 in [0, 1]; Pillow reads 16-bit RGB label PNGs at 8 bits: install python3-opencv for
    exact labels). Raises InputError when the file is missing or not an image."""
    if not os.path.isfile(path):
        raise InputError(path, None, "missing")
    try:
        import cv2
    except ImportError:
        cv2 = None
    if cv2 is not None:
        image = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        if image is None:
            raise InputError(path, None, "not an image OpenCV can read")
        if image.ndim == 3 and image.shape[2] in (3, 4):
            image = np.ascontiguousarray(image[..., [2, 1, 0] + ([3] if image.shape[2] == 4
                                                                  else [])])
        return image
    import matplotlib.image
    try:
        return matplotlib.image.imread(path)
    except (OSError, ValueError, SyntaxError) as e:
        raise InputError(path, None, f"not an image: {e}") from None


# An export's cameras (docs/export.md): frame index file, its reader, the image file name prefix
# relative to the export root (COCO file_name) and the depth index.
_EXPORT_CAMERAS = {
    "front": ("tum_rgbd/rgb.txt", dataset_files.read_tum_file_list, "tum_rgbd/"),
    "lateral": ("euroc/mav0/cam1/data.csv", dataset_files.read_euroc_file_list, "euroc/mav0/cam1/data/"),
    "upward": ("euroc/mav0/cam0/data.csv", dataset_files.read_euroc_file_list, "euroc/mav0/cam0/data/"),
}
_DATASET_NAME = re.compile(r"w([0-9]{3,6})_f([0-9]{4,6})\.json")


class Dataset(files.FolderReader):
    """A detector dataset of `corridorsim dataset` (docs/datasets.md, layout 'dataset') or the
    folder of `corridorsim run --export` (docs/export.md, layout 'export').

    Attributes and methods:
      path, layout   the folder; 'dataset' or 'export'
      manifest       dataset.json as parsed ('dataset'; None for an export)
      cameras        the cameras with frames ('dataset': dataset.json's; 'export': front when
                     tum_rgbd/rgb.txt exists, lateral and upward when euroc's cam1, cam0 do,
                     then the named cameras of euroc/mav0/cameras.yaml in cam<N> order)
      frames(camera) DataFrame, one row per frame in order. 'dataset': image_id, file_name
                     (relative to <camera>/), world_index, frame_index, world_seed, width,
                     height (from annotations.json; before it exists, from the truth files:
                     no image_id, width, height, world_seed), path, labels_path, truth_path,
                     depth_path (None without depth). 'export': t_ns (int64, exact), t (s),
                     file_name (relative to the export root, as COCO's), path, labels_path,
                     truth_path (labels/<camera>/<t_ns>.png/.json), depth_path (depth
                     cameras: front's depth.txt, a cam<N>'s depth.csv)
      image(camera, i, kind='image')   frame i's image ('image', 'labels' or 'depth') as a numpy
                     array, read now (load_image: OpenCV when installed, else matplotlib)
      truth(camera, i)   frame i's ground truth JSON (dict)
      coco(camera)   the COCO file with the camera's labels, parsed: a dataset's
                     <camera>/annotations.json, an export's coco/plates.json (front and lateral
                     share it); None when there is none
      annotations(camera)  DataFrame, one row per annotation of the camera's images: id,
                     image_id, file_name, category_id, category, x, y, w, h (bbox, COCO pixel
                     edges), area, then every other key (nested objects as 'a.b')
    """

    def __init__(self, path):
        super().__init__(path)
        if os.path.exists(os.path.join(path, "dataset.json")):
            self.layout = "dataset"
            self.manifest = dataset_files.read_dataset_manifest(os.path.join(path, "dataset.json"))
            self.cameras = list(self.manifest["cameras"])
        elif any(os.path.exists(os.path.join(path, p)) for p in
                 ["tum_rgbd", "euroc", "labels", "coco", "odometry.csv"]):
            self.layout = "export"
            self.manifest = None
            # The named cameras (euroc/mav0/cam2/, ...) as cameras.yaml numbers them.
            listed = os.path.join(path, "euroc", "mav0", "cameras.yaml")
            named = dataset_files.read_euroc_camera_list(listed) if os.path.exists(listed) else []
            self._export_named = {name: cam for cam, name in named
                                  if name not in _EXPORT_CAMERAS}
            self.cameras = [c for c in ["front", "lateral", "upward"]
                            if os.path.exists(os.path.join(path, _EXPORT_CAMERAS[c][0]))]
            self.cameras += sorted(self._export_named, key=self._export_named.get)
        else:
            raise InputError(path, None, "neither a dataset (dataset.json) nor an export "
                             "(tum_rgbd/, euroc/, labels/, coco/)")

    def __repr__(self):
        return f"Dataset({self.path!r}, layout={self.layout!r})"

    def _check_camera(self, camera):
        if camera not in self.cameras:
            raise KeyError(f"{self.path}: no camera '{camera}' (cameras: "
                           f"{', '.join(self.cameras)})")

    def frames(self, camera):
        self._check_camera(camera)
        if ("frames", camera) not in self._cache:
            make = self._dataset_frames if self.layout == "dataset" else self._export_frames
            self._cache[("frames", camera)] = make(camera)
        return self._cache[("frames", camera)]

    def _dataset_frames(self, camera):
        root = os.path.join(self.path, camera)
        coco_path = os.path.join(root, "annotations.json")
        if os.path.exists(coco_path):
            coco = self.coco(camera)
            rows = [{"image_id": im["id"], "file_name": im["file_name"],
                     "world_index": im.get("world_index"), "frame_index": im.get("frame_index"),
                     "world_seed": im.get("world_seed"), "width": im["width"],
                     "height": im["height"]} for im in coco["images"]]
        else:
            truth_dir = os.path.join(root, "truth")
            names = sorted(os.listdir(truth_dir)) if os.path.isdir(truth_dir) else []
            rows = []
            for name in names:
                m = _DATASET_NAME.fullmatch(name)
                if m is None:
                    continue
                if len(rows) == dataset_files.MAX_COCO_ITEMS:
                    raise InputError(truth_dir, None, f"more than {dataset_files.MAX_COCO_ITEMS} frames")
                rows.append({"file_name": f"images/{name[:-len('.json')]}.png",
                             "world_index": int(m.group(1)), "frame_index": int(m.group(2))})
        frame = pd.DataFrame(rows, columns=["image_id", "file_name", "world_index", "frame_index",
                                            "world_seed", "width", "height"])
        stems = [os.path.splitext(os.path.basename(f))[0] for f in frame["file_name"]]
        frame["path"] = [os.path.join(root, f) for f in frame["file_name"]]
        frame["labels_path"] = [os.path.join(root, "labels", s + ".png") for s in stems]
        frame["truth_path"] = [os.path.join(root, "truth", s + ".json") for s in stems]
        has_depth = os.path.isdir(os.path.join(root, "depth"))
        frame["depth_path"] = [os.path.join(root, "depth", s + ".png") if has_depth else None
                               for s in stems]
        return frame

    def _export_files(self, camera):
        """The camera's frame index, its reader, the images' prefix (relative to the root), and
        its depth index with the depth images' folder (the index is absent without depth)."""
        if camera in _EXPORT_CAMERAS:
            index, reader, prefix = _EXPORT_CAMERAS[camera]
        else:
            folder = f"euroc/mav0/cam{self._export_named[camera]}/"
            index, reader, prefix = folder + "data.csv", dataset_files.read_euroc_file_list, \
                folder + "data/"
        if camera == "front":
            return index, reader, prefix, "tum_rgbd/depth.txt", "tum_rgbd/"
        folder = os.path.dirname(index)
        return index, reader, prefix, folder + "/depth.csv", folder + "/depth/"

    def _export_frames(self, camera):
        index, reader, prefix, depth_index, depth_prefix = self._export_files(camera)
        index_path = os.path.join(self.path, index)
        listed = reader(index_path)
        relative = [prefix + name for _, name in listed]
        depth = {}
        if os.path.exists(os.path.join(self.path, depth_index)):
            depth = {t: os.path.join(self.path, depth_prefix, name)
                     for t, name in reader(os.path.join(self.path, depth_index))}
        stamps = [t for t, _ in listed]
        labels = os.path.join(self.path, "labels", camera)
        return pd.DataFrame({
            "t_ns": np.array(stamps, dtype=np.int64),
            "t": np.array(stamps, dtype=np.int64) / 1e9,
            "file_name": relative,
            "path": [os.path.join(self.path, r) for r in relative],
            "labels_path": [os.path.join(labels, f"{t}.png") for t in stamps],
            "truth_path": [os.path.join(labels, f"{t}.json") for t in stamps],
            "depth_path": [depth.get(t) for t in stamps],
        })

    def _frame_row(self, camera, index):
        frames = self.frames(camera)
        if not 0 <= index < len(frames):
            raise IndexError(f"{self.path}: camera '{camera}' has {len(frames)} frames, no frame "
                             f"{index}")
        return frames.iloc[index]

    def image(self, camera, index, kind="image"):
        column = {"image": "path", "labels": "labels_path", "depth": "depth_path"}.get(kind)
        if column is None:
            raise ValueError(f"kind: expected 'image', 'labels' or 'depth', got {kind!r}")
        path = self._frame_row(camera, index)[column]
        if path is None:
            raise InputError(self.path, None, f"camera '{camera}' has no {kind} images")
        return load_image(path)

    def truth(self, camera, index):
        return files.read_json_object(self._frame_row(camera, index)["truth_path"])

    def coco(self, camera):
        self._check_camera(camera)
        if self.layout == "dataset":
            path = os.path.join(self.path, camera, "annotations.json")
        elif camera in ("front", "lateral"):
            path = os.path.join(self.path, "coco", "plates.json")
        else:
            return None
        if not os.path.exists(path):
            return None
        return self._cached_coco(path)

    def _cached_coco(self, path):
        if ("coco", path) not in self._cache:
            self._cache[("coco", path)] = dataset_files.read_coco(path)
        return self._cache[("coco", path)]

    def annotations(self, camera):
        fixed = ["id", "image_id", "file_name", "category_id", "category", "x", "y", "w", "h",
                 "area"]
        coco = self.coco(camera)
        if coco is None:
            return pd.DataFrame({c: [] for c in fixed})
        images = {im["id"]: im["file_name"] for im in coco["images"]}
        if self.layout == "export":
            prefix = self._export_files(camera)[2]
            images = {i: f for i, f in images.items() if f.startswith(prefix)}
        categories = {c["id"]: c["name"] for c in coco["categories"]}
        rows = []
        for a in coco["annotations"]:
            if a["image_id"] not in images:
                continue
            x, y, w, h = (float(v) for v in a["bbox"])
            row = {"id": a["id"], "image_id": a["image_id"], "file_name": images[a["image_id"]],
                   "category_id": a["category_id"], "category": categories[a["category_id"]],
                   "x": x, "y": y, "w": w, "h": h, "area": a.get("area", w * h)}
            for key, value in a.items():
                if key in ("id", "image_id", "category_id", "bbox", "area"):
                    continue
                if isinstance(value, dict):
                    for sub, v in value.items():
                        row.setdefault(f"{key}.{sub}", v)
                else:
                    row.setdefault(key, value)
            rows.append(row)
        frame = pd.DataFrame(rows)
        if frame.empty:
            return pd.DataFrame({c: [] for c in fixed})
        return frame
