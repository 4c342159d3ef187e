"""The Python client (python/corridorsim) against a harness played by the test: framing, bounds,
descriptor passing, the serve() loop and its replies (docs/protocol.md)."""

import json
import math
import os
import socket
import struct
import threading

import numpy as np
import pytest

import corridorsim
from corridorsim.protocol import HEADER, MAGIC, Connection, ProtocolError


def pair():
    a, b = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
    return Connection(a), b


def raw_send(sock, message, blob=b"", fds=None):
    text = json.dumps(message).encode()
    data = HEADER.pack(MAGIC, len(text), len(blob)) + text + blob
    if fds:
        sock.sendmsg([data], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, struct.pack("i" * len(fds), *fds))])
    else:
        sock.sendall(data)


def raw_receive(sock):
    def exactly(n):
        data = b""
        while len(data) < n:
            chunk = sock.recv(n - len(data))
            if not chunk:
                return None
            data += chunk
        return data
    header = exactly(HEADER.size)
    if header is None:
        return None
    magic, n_json, n_blob = HEADER.unpack(header)
    assert magic == MAGIC
    message = json.loads(exactly(n_json))
    blob = exactly(n_blob) if n_blob else b""
    return message, blob


def test_messages_yields_each_message_until_the_connection_closes_between_messages():
    connection, other = pair()
    for k in range(3):
        raw_send(other, {"type": "odometry", "k": k}, b"%d" % k)
    other.close()
    got = [(message["k"], blob) for message, blob, _fds in connection.messages()]
    assert got == [(0, b"0"), (1, b"1"), (2, b"2")]


def test_messages_raises_when_the_connection_closes_inside_a_message():
    connection, other = pair()
    raw_send(other, {"type": "odometry"})
    other.sendall(HEADER.pack(MAGIC, 100, 0) + b'{"type":')
    other.close()
    messages = connection.messages()
    assert next(messages)[0] == {"type": "odometry"}
    with pytest.raises(ProtocolError):
        next(messages)


def test_a_message_round_trips_with_its_blob_and_descriptor():
    connection, other = pair()
    r, w = os.pipe()
    raw_send(other, {"type": "start", "x": 0.1}, b"\x00\x01\x02", fds=[w])
    message, blob, fds = connection.receive()
    assert message == {"type": "start", "x": 0.1}
    assert blob == b"\x00\x01\x02"
    assert len(fds) == 1
    os.write(fds[0], b"z")  # the received descriptor is the pipe's write end
    assert os.read(r, 1) == b"z"
    for fd in (r, w, fds[0]):
        os.close(fd)


def test_doubles_travel_exactly():
    connection, other = pair()
    values = [0.1, 1 / 3, 2.0 ** -1074, 1.7976931348623157e308, -0.0, math.pi]
    connection.send({"type": "estimate", "values": values})
    message, _ = raw_receive(other)
    assert [struct.pack("<d", v) for v in message["values"]] == [struct.pack("<d", v) for v in values]


def test_a_non_finite_number_is_refused_before_sending_naming_its_key():
    connection, _other = pair()
    with pytest.raises(ValueError, match=r"estimate\.pose\[2\]: a non-finite number"):
        connection.send({"type": "estimate", "pose": [0.0, 1.0, float("nan")]})


def test_a_wrong_magic_or_an_oversized_length_is_refused_before_allocating():
    connection, other = pair()
    other.sendall(b"XXXX" + struct.pack("<II", 10, 0))
    with pytest.raises(ProtocolError, match="CSIM"):
        connection.receive()
    connection, other = pair()
    other.sendall(HEADER.pack(MAGIC, (64 << 20) + 1, 0))
    with pytest.raises(ProtocolError, match="out of bounds"):
        connection.receive()


def test_an_end_between_messages_is_none_and_inside_one_an_error():
    connection, other = pair()
    other.close()
    assert connection.receive() is None
    connection, other = pair()
    other.sendall(HEADER.pack(MAGIC, 100, 0) + b"{")
    other.close()
    with pytest.raises(ProtocolError, match="inside a message"):
        connection.receive()


CALIBRATION = {
    "wheelbase_m": 0.4, "wheel_diameter_m": 0.2, "ticks_per_revolution": 0,
    "cameras": [{"id": "front",
                 "model": {"model": "pinhole_radtan", "width": 4, "height": 2, "fx": 2.0, "fy": 2.0,
                           "cx": 1.5, "cy": 0.5, "distortion": [0, 0, 0, 0, 0]},
                 "robot_from_camera": {"translation": [0.1, 0.0, 0.5],
                                       "rotation": [0, 0, 1, -1, 0, 0, 0, -1, 0]},
                 "depth": {"min_m": 0.5, "max_m": 8.0, "encoding": "depth_f32"}}]}


class Recorder(corridorsim.Pipeline):
    """Remembers what it was given and answers from it."""

    def on_start(self, calibration, start):
        self.calibration, self.start = calibration, start
        self.pose = list(start.pose)
        self.frames = []
        self.pending = []

    def on_odometry(self, odometry):
        self.pose[0] += 0.5 * (odometry.left_m + odometry.right_m)

    def on_cameras(self, frames):
        for f in frames:
            self.frames.append((f.camera, f.dropped, None if f.dropped else np.array(f.rgb),
                                None if f.dropped else np.array(f.depth)))
            if not f.dropped:
                self.pending.append({"camera": f.camera, "type": "lamp", "pixel": [1.0, 1.0],
                                     "radius_px": np.float64(2.0)})

    def estimate(self):
        return corridorsim.Estimate(self.pose, np.eye(3) * 0.01)

    def detections(self):
        out, self.pending = self.pending, []
        return out

    def landmarks(self):
        return [{"id": 0, "type": "lamp", "position": [1.0, 2.0, 2.7], "covariance": np.eye(3)}]

    def maps(self):
        return {".txt": b"map bytes"}

    def health(self):
        return {"rejected_frames": 1}


def harness(sock, transport):
    """Plays corridorsim: start, odometry, a camera set with one frame and one dropped, finish."""
    rgb = np.arange(4 * 2 * 3, dtype=np.uint8).reshape(2, 4, 3)
    depth = np.full((2, 4), 1.5, dtype="<f4")
    size = rgb.nbytes + depth.nbytes
    fds = []
    if transport == "shared_memory":
        fd = os.memfd_create("test-frames")
        os.ftruncate(fd, size)
        os.pwrite(fd, rgb.tobytes() + depth.tobytes(), 0)
        fds = [fd]
    raw_send(sock, {"type": "start", "protocol": 1, "pipeline": "mine", "seed": 7, "stamp_ns": 0,
                    "pose": [1.0, 2.0, 0.5], "calibration": CALIBRATION,
                    "cameras": ["front", "lateral"], "options": {"gain": 0.3},
                    "shared_memory_bytes": size if fds else 0}, fds=fds)
    for fd in fds:
        os.close(fd)
    replies = [raw_receive(sock)]
    raw_send(sock, {"type": "odometry", "stamp_ns": 20, "interval_ns": 20, "left_m": 0.1,
                    "right_m": 0.3, "left_ticks": 0, "right_ticks": 0})
    replies.append(raw_receive(sock))
    frames = [{"camera": "front", "dropped": False, "stamp_ns": 30,
               "rgb": {"encoding": "rgb8", "width": 4, "height": 2, "offset": 0, "bytes": rgb.nbytes},
               "depth": {"encoding": "depth_f32", "width": 4, "height": 2, "offset": rgb.nbytes,
                         "bytes": depth.nbytes}},
              {"camera": "lateral", "dropped": True}]
    blob = b"" if fds else rgb.tobytes() + depth.tobytes()
    raw_send(sock, {"type": "cameras", "stamp_ns": 30, "transport": transport, "frames": frames}, blob)
    replies.append(raw_receive(sock))
    raw_send(sock, {"type": "finish", "stamp_ns": 30})
    replies.append(raw_receive(sock))
    sock.close()
    return replies, rgb, depth


@pytest.mark.parametrize("transport", ["shared_memory", "inline"])
def test_serve_answers_every_message_in_order(transport):
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
    pipeline = Recorder()
    result = {}
    thread = threading.Thread(target=lambda: result.update(rc=corridorsim.serve(pipeline, fd=theirs.detach())))
    thread.start()
    replies, rgb, depth = harness(ours, transport)
    thread.join(10)
    assert not thread.is_alive() and result["rc"] == 0
    (ready, _), (estimate, _), (processed, _), (finished, blob) = replies
    assert ready["type"] == "ready"
    assert pipeline.calibration.wheelbase_m == 0.4
    assert pipeline.calibration.cameras["front"].rotation[1] == (-1, 0, 0)
    assert pipeline.start.options == {"gain": 0.3} and pipeline.start.seed == 7
    assert estimate == {"type": "estimate", "stamp_ns": 20, "pose": [1.2, 2.0, 0.5],
                        "covariance": [0.01, 0.0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 0.01]}
    assert processed["stamp_ns"] == 30
    assert processed["detections"] == [{"camera": "front", "type": "lamp", "pixel": [1.0, 1.0],
                                        "radius_px": 2.0}]
    (camera, dropped, got_rgb, got_depth), (camera2, dropped2, _, _) = pipeline.frames
    assert (camera, dropped, camera2, dropped2) == ("front", False, "lateral", True)
    assert np.array_equal(got_rgb, rgb) and np.array_equal(got_depth, depth)
    assert finished["landmarks"][0]["covariance"] == [1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0]
    assert finished["maps"] == [{"suffix": ".txt", "offset": 0, "bytes": 9}] and blob == b"map bytes"
    assert finished["health"] == {"rejected_frames": 1}


def test_shared_memory_images_are_read_only_views():
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)

    class Writer(Recorder):
        def on_cameras(self, frames):
            with pytest.raises(ValueError):
                frames[0].rgb[0, 0, 0] = 1
            self.checked = True
            super().on_cameras(frames)

    pipeline = Writer()
    thread = threading.Thread(target=corridorsim.serve, args=(pipeline,), kwargs={"fd": theirs.detach()})
    thread.start()
    harness(ours, "shared_memory")
    thread.join(10)
    assert pipeline.checked


def test_a_protocol_version_it_does_not_speak_is_refused():
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
    errors = []

    def client():
        try:
            corridorsim.serve(Recorder(), fd=theirs.detach())
        except ProtocolError as e:
            errors.append(str(e))

    thread = threading.Thread(target=client)
    thread.start()
    raw_send(ours, {"type": "start", "protocol": 99})
    thread.join(10)
    assert errors and "protocol 99" in errors[0]
