"""A SLAM pipeline in Python, run by corridorsim in lockstep (docs/protocol.md).

Subclass :class:`Pipeline`, then call :func:`serve` with it from the program a scenario names::

    pipelines:
      mine:
        type: external
        command: [python3, my_slam.py]
        cameras: [upward]

corridorsim starts the program, sends it the calibration and the start pose, then every wheel
odometry message and camera set in the order the robot produced them, each answered before the
next is sent, and finally ``finish``. Estimates, detections, innovations and landmarks go back in
the replies, and are scored as a built-in pipeline's are.
"""

import mmap
import os
import socket
import sys

from .protocol import PROTOCOL_VERSION, Connection, ProtocolError

try:
    import numpy as _np
except ImportError:  # images need numpy; odometry-only pipelines do not
    _np = None


class CameraCalibration:
    """One camera as the robot's calibration holds it.

    id: "front", "lateral" or "upward".
    model: the intrinsics as a dict in the form of intrinsics.json (docs/frames.md): ``model``
        ("pinhole_radtan" or "kannala_brandt"), ``width``, ``height``, ``fx``, ``fy``, ``cx``,
        ``cy`` and ``distortion`` ([k1, k2, p1, p2, k3] or [k1, k2, k3, k4]).
    translation: the optical centre in the robot frame (m), 3 floats.
    rotation: robot_R_camera, 3 rows of 3 floats (camera axes: x right, y down, z forward).
    depth: None, or a dict with ``min_m``, ``max_m`` and ``encoding`` ("depth_f32") for a
        depth camera.
    """

    def __init__(self, json):
        self.id = json["id"]
        self.model = json["model"]
        self.translation = tuple(json["robot_from_camera"]["translation"])
        r = json["robot_from_camera"]["rotation"]
        self.rotation = (tuple(r[0:3]), tuple(r[3:6]), tuple(r[6:9]))
        self.depth = json.get("depth")


class Calibration:
    """What the robot knows about itself: nominal values, never the simulator's real ones.

    wheelbase_m, wheel_diameter_m, ticks_per_revolution (0: distances unquantised) and
    ``cameras``, a dict of :class:`CameraCalibration` by id (every enabled camera).
    """

    def __init__(self, json):
        self.wheelbase_m = json["wheelbase_m"]
        self.wheel_diameter_m = json["wheel_diameter_m"]
        self.ticks_per_revolution = json["ticks_per_revolution"]
        self.cameras = {c["id"]: CameraCalibration(c) for c in json["cameras"]}


class Start:
    """The rest of the start message.

    pipeline: the pipeline's name in the scenario. seed: the pipeline's own seed (draw every
    random number from it and runs repeat exactly). stamp_ns, pose: the start stamp and the true
    start pose (x m, y m, yaw rad): estimates start there, with zero covariance. cameras: the
    cameras it reads (``cameras:`` in the scenario). options: ``options:`` of the scenario as
    given (a dict of JSON types).
    """

    def __init__(self, json):
        self.pipeline = json["pipeline"]
        self.seed = json["seed"]
        self.stamp_ns = json["stamp_ns"]
        self.pose = tuple(json["pose"])
        self.cameras = list(json["cameras"])
        self.options = json["options"]


class Odometry:
    """Wheel odometry since the previous message: the control input u = (s_l, s_r) of P1 eq. 13.

    stamp_ns (end of the interval), interval_ns, left_m and right_m (signed wheel distances),
    left_ticks and right_ticks (the encoder counts they came from).
    """

    __slots__ = ("stamp_ns", "interval_ns", "left_m", "right_m", "left_ticks", "right_ticks")

    def __init__(self, json):
        self.stamp_ns = json["stamp_ns"]
        self.interval_ns = json["interval_ns"]
        self.left_m = json["left_m"]
        self.right_m = json["right_m"]
        self.left_ticks = json["left_ticks"]
        self.right_ticks = json["right_ticks"]


class CameraFrame:
    """One camera of a camera set.

    camera: its id. dropped: True when the frame due was lost (then the images are None).
    stamp_ns: its stamp. rgb: a read-only numpy array (height, width, 3) of uint8, R G B, row 0
    on top. depth: None, or a read-only (height, width) float32 array of metres along the
    optical axis, 0 where invalid. With the shared-memory transport the arrays are views of
    memory the next camera set overwrites: copy (``numpy.array(frame.rgb)``) what you keep.
    """

    __slots__ = ("camera", "dropped", "stamp_ns", "rgb", "depth")

    def __init__(self, camera, dropped, stamp_ns, rgb, depth):
        self.camera = camera
        self.dropped = dropped
        self.stamp_ns = stamp_ns
        self.rgb = rgb
        self.depth = depth


class Estimate:
    """A pose estimate: pose (x m, y m, yaw rad) and its 3x3 covariance over (x, y, yaw), yaw
    last (a nested sequence or a numpy array)."""

    __slots__ = ("pose", "covariance")

    def __init__(self, pose, covariance):
        self.pose = pose
        self.covariance = covariance


class Pipeline:
    """The base of a Python pipeline. Override what you need; the defaults do nothing.

    The calls come in this order: on_start once; then on_odometry and on_cameras in the robot's
    order, each followed by the reply (estimate() after every on_odometry; detections() and
    innovations() after every call); then finish() once, followed by landmarks(), detections(),
    innovations(), maps(), health() and stage_seconds().
    """

    def on_start(self, calibration, start):
        """calibration: :class:`Calibration`; start: :class:`Start`."""

    def on_odometry(self, odometry):
        """odometry: :class:`Odometry`."""

    def on_cameras(self, frames):
        """frames: list of :class:`CameraFrame`, one per camera read that was due at this stamp
        (in the order of ``cameras:``)."""

    def estimate(self):
        """The current estimate: an :class:`Estimate`, or a (pose, covariance) pair. Asked after
        every odometry message. Every number must be finite."""
        raise NotImplementedError("a Pipeline must implement estimate()")

    def detections(self):
        """What was detected in the frames since the last call: a list of dicts with ``camera``,
        ``type`` ("door_plate", "corner", "lamp", "door", "vanishing_point"), ``pixel`` [u, v]
        and, as the type needs, ``radius_px``, ``box_px``, ``label``, ``open``,
        ``column_bearings_rad``, ``score``, ``recognition_score``, ``landmark_id``,
        ``new_landmark`` (docs/protocol.md)."""
        return []

    def innovations(self):
        """Landmark updates since the last call: dicts with ``type``, ``nis``, ``dof`` and
        ``accepted`` (NIS statistics of metrics.json)."""
        return []

    def finish(self):
        """The run ended: the last message has come."""

    def landmarks(self):
        """The final map: dicts with ``id``, ``type``, ``position`` [x, y, z] (world, m) and
        optionally ``covariance`` (9 numbers or 3x3), ``status`` ("converged" or
        "initializing"), ``label`` and ``points`` ([{"role", "position", "covariance"}])."""
        return []

    def maps(self):
        """Map files: a dict suffix -> bytes, written as maps/<pipeline><suffix>."""
        return {}

    def health(self):
        """Counters: a dict of non_positive_covariance, rejected_updates, rejected_odometry,
        rejected_frames."""
        return {}

    def stage_seconds(self):
        """Seconds per stage of your own (timing, not metrics): a dict name -> seconds."""
        return {}


def _flat3x3(matrix, where):
    rows = [list(row) for row in matrix] if not hasattr(matrix, "tolist") else matrix.tolist()
    if len(rows) == 9 and not isinstance(rows[0], list):
        return [float(v) for v in rows]
    if len(rows) != 3 or any(len(r) != 3 for r in rows):
        raise ValueError("%s: a 3x3 matrix is needed" % where)
    return [float(v) for row in rows for v in row]


def _estimate_json(estimate, stamp_ns):
    if isinstance(estimate, Estimate):
        pose, covariance = estimate.pose, estimate.covariance
    else:
        pose, covariance = estimate
    pose = [float(v) for v in (pose.tolist() if hasattr(pose, "tolist") else pose)]
    if len(pose) != 3:
        raise ValueError("estimate(): the pose is (x, y, yaw)")
    return {"type": "estimate", "stamp_ns": stamp_ns, "pose": pose,
            "covariance": _flat3x3(covariance, "estimate().covariance")}


def _plain(value):
    """numpy scalars and arrays as plain JSON types."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _put_any(reply, key, value, kind):
    """reply[key]: what the pipeline gave (`value`, as a `kind`, list or dict, of plain JSON
    types), when it gave any."""
    if value:
        reply[key] = _plain(kind(value))


def _with_extras(reply, pipeline):
    _put_any(reply, "detections", pipeline.detections(), list)
    _put_any(reply, "innovations", pipeline.innovations(), list)
    return reply


class _Images:
    """Where the images of a camera set are: the shared memory, or the message's blob."""

    def __init__(self, fd, size):
        self._memory = mmap.mmap(fd, size, prot=mmap.PROT_READ) if fd is not None and size else None

    def frames(self, message, blob):
        source = self._memory if message["transport"] == "shared_memory" else blob
        frames = []
        for f in message["frames"]:
            if f["dropped"]:
                frames.append(CameraFrame(f["camera"], True, None, None, None))
                continue
            frames.append(CameraFrame(f["camera"], False, f["stamp_ns"],
                                      self._array(source, f["rgb"]), self._array(source, f.get("depth"))))
        return frames

    @staticmethod
    def _array(source, image):
        if image is None:
            return None
        if _np is None:
            raise RuntimeError("camera frames need numpy (python3-numpy)")
        if image["encoding"] == "rgb8":
            dtype, shape = _np.uint8, (image["height"], image["width"], 3)
        elif image["encoding"] == "depth_f32":
            dtype, shape = _np.dtype("<f4"), (image["height"], image["width"])
        else:
            raise ProtocolError("unknown image encoding %r" % image["encoding"])
        count = shape[0] * shape[1] * (3 if len(shape) == 3 else 1)
        array = _np.frombuffer(source, dtype=dtype, count=count, offset=image["offset"])
        return array.reshape(shape)


def serve(pipeline, fd=None):
    """Runs the protocol loop with ``pipeline`` (a Pipeline subclass, or an instance) on the
    connection corridorsim passed (descriptor $CORRIDORSIM_PROTOCOL_FD, 3), until corridorsim
    closes it after ``finish``. Returns 0; raises on a protocol error (the program then exits
    with a traceback, which the run's <pipeline>.log keeps)."""
    if isinstance(pipeline, type):
        pipeline = pipeline()
    if fd is None:
        fd = int(os.environ.get("CORRIDORSIM_PROTOCOL_FD", "3"))
    connection = Connection(socket.socket(socket.AF_UNIX, socket.SOCK_STREAM, fileno=fd))
    received = connection.receive()
    if received is None:
        raise ProtocolError("the connection closed before the start message")
    start, _blob, fds = received
    if start["type"] != "start":
        raise ProtocolError("the first message is %r, not start" % start["type"])
    if start["protocol"] != PROTOCOL_VERSION:
        raise ProtocolError("corridorsim speaks protocol %r; this client speaks %d"
                            % (start["protocol"], PROTOCOL_VERSION))
    images = _Images(fds[0] if fds else None, start["shared_memory_bytes"])
    for extra in fds[1:]:
        os.close(extra)
    pipeline.on_start(Calibration(start["calibration"]), Start(start))
    connection.send({"type": "ready", "name": type(pipeline).__name__})
    while True:
        received = connection.receive()
        if received is None:
            raise ProtocolError("the connection closed before finish")
        message, blob, fds = received
        for extra in fds:
            os.close(extra)
        kind = message["type"]
        if kind == "odometry":
            pipeline.on_odometry(Odometry(message))
            connection.send(_with_extras(_estimate_json(pipeline.estimate(), message["stamp_ns"]),
                                         pipeline))
        elif kind == "cameras":
            pipeline.on_cameras(images.frames(message, blob))
            connection.send(_with_extras({"type": "processed", "stamp_ns": message["stamp_ns"]},
                                         pipeline))
        elif kind == "finish":
            pipeline.finish()
            reply = _with_extras({"type": "finished"}, pipeline)
            landmarks = []
            for landmark in pipeline.landmarks():
                landmark = dict(_plain(landmark))
                if "covariance" in landmark:
                    landmark["covariance"] = _flat3x3(landmark["covariance"], "landmark covariance")
                for point in landmark.get("points", []):
                    if "covariance" in point:
                        point["covariance"] = _flat3x3(point["covariance"], "point covariance")
                landmarks.append(landmark)
            if landmarks:
                reply["landmarks"] = landmarks
            map_blob = bytearray()
            maps = []
            for suffix, data in pipeline.maps().items():
                maps.append({"suffix": suffix, "offset": len(map_blob), "bytes": len(data)})
                map_blob += data
            if maps:
                reply["maps"] = maps
            _put_any(reply, "health", pipeline.health(), dict)
            _put_any(reply, "stage_seconds", pipeline.stage_seconds(), dict)
            connection.send(reply, bytes(map_blob))
            # corridorsim closes the connection now; wait for that, then end.
            connection.receive()
            connection.close()
            return 0
        else:
            raise ProtocolError("unknown message type %r" % kind)
