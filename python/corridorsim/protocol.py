"""The framing of corridorsim's lockstep protocol (docs/protocol.md, "Messages").

A message is a 12-byte header -- the ASCII bytes ``CSIM`` then two little-endian uint32
lengths -- a UTF-8 JSON object of the first length and binary bytes (the "blob") of the second.
A descriptor may ride on a message's first byte (SCM_RIGHTS): corridorsim passes the shared
memory of the images that way with ``start``.
"""

import array
import json
import math
import socket
import struct

#: The version every client speaks: the start message's ``protocol``.
BASE_PROTOCOL_VERSION = 1
#: The newest version this client speaks (docs/protocol.md, "Version 2"): it says so in ``ready``
#: when the start message's ``protocol_max`` offers it.
PROTOCOL_VERSION = 2
MAGIC = b"CSIM"
HEADER = struct.Struct("<4sII")
#: Bounds of a message, as corridorsim checks them (harness/external/protocol.h).
MAX_JSON_BYTES = 64 << 20
MAX_BLOB_BYTES = 512 << 20


class ProtocolError(RuntimeError):
    """corridorsim sent something this client cannot read, or the connection ended early."""


def _finite(value, where):
    """Raises ValueError naming ``where`` if ``value`` holds a non-finite float."""
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError("%s: a non-finite number (%r); JSON has none" % (where, value))
    elif isinstance(value, dict):
        for k, v in value.items():
            _finite(v, "%s.%s" % (where, k))
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            _finite(v, "%s[%d]" % (where, i))


class Connection:
    """One end of the protocol's socket: whole messages in, whole messages out."""

    def __init__(self, sock):
        self._sock = sock

    def close(self):
        self._sock.close()

    def _read_exactly(self, n, fds):
        buffer = bytearray(n)
        view = memoryview(buffer)
        done = 0
        while done < n:
            if fds is not None:
                ancillary_space = socket.CMSG_SPACE(4 * array.array("i").itemsize)
                got, ancillary, _flags, _addr = self._sock.recvmsg_into(
                    [view[done:]], ancillary_space)
                for level, kind, data in ancillary:
                    if level == socket.SOL_SOCKET and kind == socket.SCM_RIGHTS:
                        received = array.array("i")
                        received.frombytes(data[: len(data) - (len(data) % received.itemsize)])
                        fds.extend(received)
            else:
                got = self._sock.recv_into(view[done:])
            if got == 0:
                return None if done == 0 else bytes(buffer[:done])
            done += got
        return bytes(buffer)

    def receive(self):
        """The next message as (dict, blob bytes, list of received descriptors), or None once
        corridorsim has closed the connection between messages."""
        fds = []
        header = self._read_exactly(HEADER.size, fds)
        if header is None:
            return None
        if len(header) < HEADER.size:
            raise ProtocolError("the connection closed inside a message header")
        magic, json_bytes, blob_bytes = HEADER.unpack(header)
        if magic != MAGIC:
            raise ProtocolError("a message does not start with CSIM (got %r)" % magic)
        if not 0 < json_bytes <= MAX_JSON_BYTES or blob_bytes > MAX_BLOB_BYTES:
            raise ProtocolError("a message's lengths (%d, %d) are out of bounds"
                                % (json_bytes, blob_bytes))
        text = self._read_exactly(json_bytes, None)
        blob = self._read_exactly(blob_bytes, None) if blob_bytes else b""
        if text is None or len(text) < json_bytes or (blob_bytes and (blob is None or len(blob) < blob_bytes)):
            raise ProtocolError("the connection closed inside a message")
        message = json.loads(text.decode("utf-8"))
        if not isinstance(message, dict) or not isinstance(message.get("type"), str):
            raise ProtocolError("a message is not a JSON object with a type")
        return message, blob, fds

    def messages(self):
        """Yields each message as receive() returns it, until corridorsim closes the
        connection between messages (a connection cut inside a message raises)."""
        while True:
            received = self.receive()
            if received is None:
                return
            yield received

    def send(self, message, blob=b""):
        """Sends one message. Raises ValueError for a non-finite number (named by its key)."""
        _finite(message, message.get("type", "message"))
        text = json.dumps(message, allow_nan=False, separators=(",", ":")).encode("utf-8")
        if len(text) > MAX_JSON_BYTES or len(blob) > MAX_BLOB_BYTES:
            raise ValueError("a %s message over the protocol's bounds (%d JSON bytes, %d blob "
                             "bytes)" % (message.get("type"), len(text), len(blob)))
        self._sock.sendall(HEADER.pack(MAGIC, len(text), len(blob)) + text + bytes(blob))
