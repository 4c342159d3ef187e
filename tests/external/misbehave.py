#!/usr/bin/python3
"""A pipeline program that misbehaves on purpose, for tests/external/external_test.py.

usage: misbehave.py MODE [AFTER]
Dead reckoning from the wheel distances (a plain Euler step) until the AFTER-th odometry
message (default 50), then MODE: ok (never misbehaves), exit, crash, hang, malformed, oversized,
wrong_type, wrong_stamp, infinite, nan, detection_without_camera, orphan (starts a child that
would outlive it; then behaves), spam (writes 3 MB to stderr; then behaves), slow (sleeps up to
3 ms before each reply, seeded by the message: a different pace, the same answers).
The options `pid_file` and `child_pid_file` (if given) receive its pid and its child's. At start
it checks what it was given: descriptors 0-3 only, the connection at 3, a read-only shared memory.
"""

import json
import math
import os
import signal
import socket
import struct
import subprocess
import sys
import time
import zlib

import corridorsim
from corridorsim.protocol import HEADER, MAGIC, Connection


def check_descriptors():
    fds = sorted(int(n) for n in os.listdir("/proc/self/fd"))
    # listdir's own descriptor of /proc/self/fd is in the list, and closed by now.
    extra = [fd for fd in fds if fd > 3 and os.path.exists("/proc/self/fd/%d" % fd)]
    if extra:
        targets = [os.readlink("/proc/self/fd/%d" % fd) for fd in extra]
        print("misbehave: inherited descriptors %s: %s" % (extra, targets), file=sys.stderr)
        sys.exit(9)


def main():
    mode = sys.argv[1]
    after = int(sys.argv[2]) if len(sys.argv) > 2 else 50
    check_descriptors()
    if os.environ.get("CORRIDORSIM_PROTOCOL_FD") != "3":
        print("misbehave: CORRIDORSIM_PROTOCOL_FD is not 3", file=sys.stderr)
        sys.exit(9)
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM, fileno=3)
    connection = Connection(sock)
    start, _blob, fds = connection.receive()
    options = start["options"]
    if "pid_file" in options:
        with open(options["pid_file"], "w") as f:
            f.write(str(os.getpid()))
    if fds:
        import mmap
        try:
            mmap.mmap(fds[0], start["shared_memory_bytes"], prot=mmap.PROT_READ | mmap.PROT_WRITE)
            print("misbehave: the shared memory is writable", file=sys.stderr)
            sys.exit(9)
        except (PermissionError, OSError):
            pass
    x, y, yaw = start["pose"]
    b = start["calibration"]["wheelbase_m"]
    connection.send({"type": "ready"})
    if mode == "orphan":
        child = subprocess.Popen(["sleep", "300"])
        if "child_pid_file" in options:
            with open(options["child_pid_file"], "w") as f:
                f.write(str(child.pid))
    if mode == "spam":
        for i in range(3000):
            sys.stderr.write("spam line %05d %s\n" % (i, "x" * 1000))
        sys.stderr.write("misbehave: the last spam line\n")
        sys.stderr.flush()
    n = 0
    while True:
        received = connection.receive()
        if received is None:
            return 0
        message, _blob, _fds = received
        kind = message["type"]
        stamp = message["stamp_ns"]
        if mode == "slow":
            time.sleep((zlib.crc32(str(stamp).encode()) % 3000) / 1e6)
        if kind == "odometry":
            n += 1
            travel = 0.5 * (message["left_m"] + message["right_m"])
            x += travel * math.cos(yaw)
            y += travel * math.sin(yaw)
            yaw = math.remainder(yaw + (message["right_m"] - message["left_m"]) / b, 2 * math.pi)
            reply = {"type": "estimate", "stamp_ns": stamp, "pose": [x, y, yaw],
                     "covariance": [1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-5]}
            if n == after and mode not in ("ok", "slow", "orphan", "spam"):
                print("misbehave: %s at odometry message %d" % (mode, n), file=sys.stderr, flush=True)
                if mode == "exit":
                    sys.exit(3)
                if mode == "crash":
                    os.kill(os.getpid(), signal.SIGSEGV)
                if mode == "hang":
                    time.sleep(3600)
                if mode == "malformed":
                    sock.sendall(b"this is not a message at all")
                    time.sleep(3600)
                if mode == "oversized":
                    sock.sendall(HEADER.pack(MAGIC, 0x7fffffff, 0))
                    time.sleep(3600)
                if mode == "wrong_type":
                    reply = {"type": "processed", "stamp_ns": stamp}
                if mode == "wrong_stamp":
                    reply["stamp_ns"] = stamp + 1
                if mode == "infinite":
                    text = json.dumps(reply).replace("[%r," % x, "[1e999,", 1).encode()
                    sock.sendall(HEADER.pack(MAGIC, len(text), 0) + text)
                    continue
                if mode == "nan":
                    text = json.dumps(dict(reply, pose=[float("nan"), y, yaw])).encode()
                    sock.sendall(HEADER.pack(MAGIC, len(text), 0) + text)
                    continue
                if mode == "detection_without_camera":
                    reply["detections"] = [{"camera": "front", "type": "lamp", "pixel": [1, 1],
                                            "radius_px": 3}]
            connection.send(reply)
        elif kind == "cameras":
            connection.send({"type": "processed", "stamp_ns": stamp})
        elif kind == "finish":
            connection.send({"type": "finished", "health": {"rejected_odometry": 0}})
        else:
            print("misbehave: unknown message %r" % kind, file=sys.stderr)
            return 9


if __name__ == "__main__":
    sys.exit(main())
