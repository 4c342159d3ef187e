#!/usr/bin/python3
"""A pipeline program (docs/protocol.md) that leaves descendants behind, for
tests/harness/cli_supervision_test.py: at start it starts two `sleep 300`, one in its own
process group and one that leaves it (setpgid(0, 0)), both with its stdout and stderr, and writes
their pids and its own to PID_DIR/{program,same_group,own_group}.pid. Then dead reckoning from
the wheel distances; MODE hang: it stops answering at the first odometry message (the run waits).

usage: supervision_descendants.py PID_DIR MODE   (MODE: ok | hang)
"""

import os
import socket
import subprocess
import sys
import time

from corridorsim.protocol import Connection
from dead_reckoning import DeadReckoning


def write_pid(pid_dir, name, pid):
    path = os.path.join(pid_dir, name + ".pid")
    with open(path + ".tmp", "w") as f:
        f.write(str(pid))
    os.rename(path + ".tmp", path)


def main():
    pid_dir, mode = sys.argv[1], sys.argv[2]
    connection = Connection(socket.socket(socket.AF_UNIX, socket.SOCK_STREAM, fileno=3))
    start, _blob, _fds = connection.receive()
    pose = DeadReckoning(start)
    same = subprocess.Popen(["sleep", "300"], stdin=subprocess.DEVNULL)
    own = subprocess.Popen(["sleep", "300"], stdin=subprocess.DEVNULL, preexec_fn=os.setpgrp)
    write_pid(pid_dir, "same_group", same.pid)
    write_pid(pid_dir, "own_group", own.pid)
    write_pid(pid_dir, "program", os.getpid())
    connection.send({"type": "ready"})
    for message, _blob, _fds in connection.messages():
        kind = message["type"]
        if kind == "odometry":
            if mode == "hang":
                time.sleep(3600)
            connection.send(pose.step(message))
        elif kind == "cameras":
            connection.send({"type": "processed", "stamp_ns": message["stamp_ns"]})
        elif kind == "finish":
            connection.send({"type": "finished", "health": {}})
        else:
            return 9
    return 0


if __name__ == "__main__":
    sys.exit(main())
