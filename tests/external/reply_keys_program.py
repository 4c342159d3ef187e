#!/usr/bin/python3
"""A pipeline program whose replies carry a misspelt key, for tests/external/reply_keys_test.py.

usage: reply_keys_program.py MODE [AFTER]
Dead reckoning from the wheel distances, an innovation with every 10th estimate and its own
stage_seconds (the time it spent on the messages), then by MODE:
  ok                  every reply right;
  finished_landmarks  `finished` says "landmark" for "landmarks" (its landmarks are lost: the
                      pipeline must fail, what arrived is kept);
  finished_stage      `finished` says "stage_second" for "stage_seconds" (no result lost: a
                      warning);
  estimate_key        the AFTER-th estimate (default 50) carries "covariances" besides its
                      pose and covariance (the pipeline fails at that message; its estimate is
                      kept).
"""

import socket
import sys
import time

from corridorsim.protocol import Connection
from dead_reckoning import DeadReckoning


def main():
    mode = sys.argv[1]
    after = int(sys.argv[2]) if len(sys.argv) > 2 else 50
    connection = Connection(socket.socket(socket.AF_UNIX, socket.SOCK_STREAM, fileno=3))
    start, _blob, _fds = connection.receive()
    pose = DeadReckoning(start)
    connection.send({"type": "ready", "name": "reply_keys_program"})
    n = 0
    busy = 0.0
    for message, _blob, _fds in connection.messages():
        t0 = time.perf_counter()
        kind = message["type"]
        if kind == "odometry":
            n += 1
            reply = pose.step(message)
            if n % 10 == 0:
                reply["innovations"] = [{"type": "lamp", "nis": 1.5, "dof": 2, "accepted": True}]
            if mode == "estimate_key" and n == after:
                reply["covariances"] = reply["covariance"]
        elif kind == "cameras":
            reply = {"type": "processed", "stamp_ns": message["stamp_ns"]}
        elif kind == "finish":
            landmarks = [{"id": 0, "type": "lamp", "status": "converged",
                          "position": [1.0, 0.2, 2.7]}]
            stages = {"dead_reckoning": round(busy, 6)}
            reply = {"type": "finished", "health": {"rejected_odometry": 0},
                     "landmark" if mode == "finished_landmarks" else "landmarks": landmarks,
                     "stage_second" if mode == "finished_stage" else "stage_seconds": stages}
        else:
            print("reply_keys_program: unknown message %r" % kind, file=sys.stderr)
            return 9
        busy += time.perf_counter() - t0
        connection.send(reply)
    return 0


if __name__ == "__main__":
    sys.exit(main())
