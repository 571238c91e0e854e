"""Shared helpers of the tests that reach a network peer: a TCP server that answers what it is told."""

from __future__ import annotations

import contextlib
import socket
import struct
import threading

#: Bytes that are not Dask's protocol: a message header announcing 3 EiB, then junk.
JUNK = struct.pack("<Q", int(3.07 * 2**60)) + b"junk"


@contextlib.contextmanager
def tcp_server(answer):
    """A TCP server on a free port of 127.0.0.1 that accepts every connection and sends
    *answer* (bytes; None: nothing, ever); yields its tcp:// address."""
    sock = socket.create_server(("127.0.0.1", 0))
    held = []

    def serve():
        while True:
            try:
                conn, _ = sock.accept()
            except OSError:
                return
            held.append(conn)
            if answer is not None:
                with contextlib.suppress(OSError):
                    conn.sendall(answer)

    threading.Thread(target=serve, daemon=True).start()
    try:
        yield f"tcp://127.0.0.1:{sock.getsockname()[1]}"
    finally:
        sock.close()
        for conn in held:
            conn.close()
