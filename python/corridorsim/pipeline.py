"""A SLAM pipeline in Python, run by corridorsim in lockstep (docs/protocol.md).

Subclass :class:`Pipeline`, then call :func:`serve` with it from the program a scenario names::

    pipelines:
      mine:
        type: external
        command: [python3, my_slam.py]
        cameras: [upward]

corridorsim starts the program, sends it the calibration and the start pose, then every wheel
odometry message, IMU sample, laser sweep and camera set in the order the robot produced them,
each answered before the next is sent, and finally ``finish``. Estimates, detections, innovations
and landmarks go back in the replies, and are scored as a built-in pipeline's are.

The client speaks protocol version 2 when corridorsim offers it (``protocol_max``): a subclass
names the IMUs and scanners it reads (``imus``, ``lasers``: only those are sent) and the
measurement types of its own it reports (``measurement_types``)::

    class ScanMatcher(corridorsim.Pipeline):
        lasers = ["scanner"]                    # or True: every scanner of the robot
        measurement_types = [("scan_match", 3)]

        def on_scan(self, scan): ...            # a LaserScan; innovations() may then report
                                                # {"type": "scan_match", "nis": ..., "dof": 3}
"""

import array
import mmap
import os
import socket
import sys

from .protocol import BASE_PROTOCOL_VERSION, PROTOCOL_VERSION, Connection, ProtocolError

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


def _mount(json):
    """(translation, rotation) of a mount: 3 floats (m) and 3 rows of 3 floats."""
    r = json["rotation"]
    return tuple(json["translation"]), (tuple(r[0:3]), tuple(r[3:6]), tuple(r[6:9]))


class ImuCalibration:
    """One IMU as the robot's calibration holds it (protocol version 2).

    id: its name in the scenario. translation, rotation: its mount, the IMU's body axes in the
    robot frame (m; robot_R_imu, 3 rows of 3). rate_hz. gyroscope_noise_density (rad/s/sqrt(Hz)),
    gyroscope_random_walk (rad/s^2/sqrt(Hz)), accelerometer_noise_density (m/s^2/sqrt(Hz)),
    accelerometer_random_walk (m/s^3/sqrt(Hz)): Kalibr's imu.yaml figures, 0 without noise.
    """

    def __init__(self, json):
        self.id = json["id"]
        self.translation, self.rotation = _mount(json["robot_from_imu"])
        self.rate_hz = json["rate_hz"]
        for key in ("gyroscope_noise_density", "gyroscope_random_walk",
                    "accelerometer_noise_density", "accelerometer_random_walk"):
            setattr(self, key, json[key])


class LaserCalibration:
    """One planar laser scanner as the robot's calibration holds it (protocol version 2).

    id: its name in the scenario. translation, rotation: its mount (x the 0 rad beam, z the scan
    plane's normal) in the robot frame. rate_hz, beams (per sweep), range_sigma_m (0 without
    noise); the rest of a sweep's geometry comes with each :class:`LaserScan`.
    """

    def __init__(self, json):
        self.id = json["id"]
        self.translation, self.rotation = _mount(json["robot_from_laser"])
        self.rate_hz = json["rate_hz"]
        self.beams = json["beams"]
        self.range_sigma_m = json["range_sigma_m"]


class Calibration:
    """What the robot knows about itself: nominal values, never the simulator's real ones.

    wheelbase_m, wheel_diameter_m, ticks_per_revolution (0: distances unquantised),
    ``cameras``, a dict of :class:`CameraCalibration` by id (every enabled camera), ``imus`` and
    ``lasers``, dicts of :class:`ImuCalibration` and :class:`LaserCalibration` by id (every IMU
    and scanner; empty from a corridorsim that speaks version 1 only).
    """

    def __init__(self, json):
        self.wheelbase_m = json["wheelbase_m"]
        self.wheel_diameter_m = json["wheel_diameter_m"]
        self.ticks_per_revolution = json["ticks_per_revolution"]
        self.cameras = {c["id"]: CameraCalibration(c) for c in json["cameras"]}
        self.imus = {c["id"]: ImuCalibration(c) for c in json.get("imus", [])}
        self.lasers = {c["id"]: LaserCalibration(c) for c in json.get("lasers", [])}


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


class ImuSample:
    """One IMU sample (protocol version 2), in the IMU's own frame, with the axes and units of
    ROS's sensor_msgs/Imu: stamp_ns, sensor (the IMU's id), angular_velocity_rad_s (gyroscope,
    3 floats) and linear_acceleration_m_s2 (accelerometer: specific force, +9.81 on z at rest).
    """

    __slots__ = ("stamp_ns", "sensor", "angular_velocity_rad_s", "linear_acceleration_m_s2")

    def __init__(self, json):
        self.stamp_ns = json["stamp_ns"]
        self.sensor = json["sensor"]
        self.angular_velocity_rad_s = tuple(json["angular_velocity_rad_s"])
        self.linear_acceleration_m_s2 = tuple(json["linear_acceleration_m_s2"])


class LaserScan:
    """One sweep of a planar laser scanner (protocol version 2), as ROS's sensor_msgs/LaserScan.

    stamp_ns: its first beam; beam i points at angle_min_rad + i * angle_increment_rad and fires
    at stamp_ns + i * time_increment_ns (the sweep arrives once its last beam fired).
    scan_time_ns (between sweeps), range_min_m, range_max_m. ranges: float32 metres, REP 117's
    +inf (no return within range_max_m), -inf (closer than range_min_m) and NaN (lost); a numpy
    array when numpy is there, else an array.array("f"), of its own (no copy needed).
    """

    __slots__ = ("stamp_ns", "sensor", "angle_min_rad", "angle_increment_rad",
                 "time_increment_ns", "scan_time_ns", "range_min_m", "range_max_m", "ranges")

    def __init__(self, json, blob):
        for key in self.__slots__[:-1]:
            setattr(self, key, json[key])
        ranges = json["ranges"]
        if ranges["encoding"] != "float32" or ranges["bytes"] != 4 * ranges["count"]:
            raise ProtocolError("a scan's ranges: unknown encoding %r" % ranges["encoding"])
        data = bytes(blob[ranges["offset"]:ranges["offset"] + ranges["bytes"]])
        if len(data) != ranges["bytes"]:
            raise ProtocolError("a scan's ranges lie outside its blob")
        if _np is not None:
            self.ranges = _np.frombuffer(data, dtype="<f4").copy()
        else:
            self.ranges = array.array("f", data)
            if sys.byteorder != "little":
                self.ranges.byteswap()


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

    The calls come in this order: on_start once; then on_odometry, on_imu, on_scan and
    on_cameras in the robot's order (at one stamp: odometry, IMU samples, sweeps, camera set),
    each followed by the reply (estimate() after every on_odometry; detections() and
    innovations() after every call); then finish() once, followed by landmarks(), detections(),
    innovations(), maps(), health() and stage_seconds().

    What it reads and reports of protocol version 2 (docs/protocol.md), read after on_start (so
    on_start may set them from the calibration or the options):

    - ``imus``, ``lasers``: the ids of the IMUs and scanners it reads (only their samples and
      sweeps are sent: a pipeline that reads none pays nothing), or True for every one the
      calibration lists. Default: none.
    - ``measurement_types``: the measurement types of its own whose innovations and detections it
      reports (a list of (name, dof) pairs or {"name", "dof"} dicts; a name is
      [a-z][a-z0-9_]{0,31} and not a shipped landmark type's). metrics.json gets
      ``nis.<name>``. Default: none.

    A pipeline that uses none of them runs against a corridorsim that speaks version 1 only too.
    """

    imus = ()
    lasers = ()
    measurement_types = ()

    def on_start(self, calibration, start):
        """calibration: :class:`Calibration`; start: :class:`Start`."""

    def on_odometry(self, odometry):
        """odometry: :class:`Odometry`."""

    def on_imu(self, sample):
        """sample: :class:`ImuSample`, of an IMU in ``imus``, in stamp order. corridorsim sends
        the samples between two other messages in one imu message: on_imu is called for each,
        then innovations() once for the reply (no detections: those come with camera sets)."""

    def on_scan(self, scan):
        """scan: :class:`LaserScan`, of a scanner in ``lasers``, once its last beam fired. Its
        reply carries innovations() (no detections)."""

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
        """Updates since the last call: dicts with ``type`` (a shipped landmark type or one of
        ``measurement_types``, whose dof it must have), ``nis``, ``dof`` and ``accepted`` (NIS
        statistics of metrics.json)."""
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


def _sensor_ids(wanted, offered, what):
    """The ids a pipeline reads: ``wanted`` (ids, or True for all of ``offered``), checked."""
    if wanted is True:
        return list(offered)
    ids = [str(i) for i in wanted]
    unknown = [i for i in ids if i not in offered]
    if unknown:
        raise ValueError("%s: %s not of this robot (it has %s)"
                         % (what, ", ".join(unknown), ", ".join(offered) or "none"))
    return ids


def _declared_types(types):
    """measurement_types as [{"name", "dof"}]: from (name, dof) pairs or such dicts."""
    out = []
    for t in types:
        name, dof = (t["name"], t["dof"]) if isinstance(t, dict) else t
        out.append({"name": str(name), "dof": int(dof)})
    return out


def _ready(pipeline, calibration, protocol_max):
    """The ready reply: version 2 when corridorsim offers it, with what the pipeline reads and
    declares; version 1 (today's exchange) otherwise, if the pipeline needs nothing of 2."""
    reply = {"type": "ready", "name": type(pipeline).__name__}
    if protocol_max < PROTOCOL_VERSION:
        if pipeline.imus or pipeline.lasers or pipeline.measurement_types:
            raise ProtocolError("this corridorsim speaks protocol %d at most: no IMUs, scanners "
                                "or measurement types of your own (version 2)" % protocol_max)
        return reply
    imus = _sensor_ids(pipeline.imus, calibration.imus, "imus")
    lasers = _sensor_ids(pipeline.lasers, calibration.lasers, "lasers")
    types = _declared_types(pipeline.measurement_types)
    reply["protocol"] = PROTOCOL_VERSION
    if imus:
        reply["imus"] = imus
    if lasers:
        reply["lasers"] = lasers
    if types:
        reply["measurement_types"] = types
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
    if start["protocol"] != BASE_PROTOCOL_VERSION:
        raise ProtocolError("corridorsim speaks protocol %r; this client speaks %d to %d"
                            % (start["protocol"], BASE_PROTOCOL_VERSION, PROTOCOL_VERSION))
    images = _Images(fds[0] if fds else None, start["shared_memory_bytes"])
    for extra in fds[1:]:
        os.close(extra)
    calibration = Calibration(start["calibration"])
    pipeline.on_start(calibration, Start(start))
    connection.send(_ready(pipeline, calibration, start.get("protocol_max", BASE_PROTOCOL_VERSION)))
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
        elif kind == "imu":
            # The samples since the last message, in order: one call each, one reply for all.
            for sample in message["samples"]:
                pipeline.on_imu(ImuSample(sample))
            connection.send(_with_extras({"type": "processed", "stamp_ns": message["stamp_ns"]},
                                         pipeline))
        elif kind == "scan":
            pipeline.on_scan(LaserScan(message, blob))
            connection.send(_with_extras({"type": "processed", "stamp_ns": message["stamp_ns"]},
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
