"""Length-prefixed framing of rcssserver3d (agent port 3100 and monitor port 3200, both directions).

Every message is a 4-byte unsigned big-endian length followed by that many bytes, with no terminator
(REFERENCE §3.1). The pure parts (:func:`frame`, :class:`FrameDecoder`) take and return bytes; the two
socket helpers at the bottom are the only I/O and exist so every transport reads frames the same way.
"""

from __future__ import annotations

import socket
import struct

from agent.protocol.errors import ProtocolError

PREFIX_BYTES = 4
#: Largest length the prefix can express.
MAX_PREFIX_VALUE = 0xFFFFFFFF
#: Default cap on one payload. A full monitor state is ~10 kB and a vision sense message ~2 kB, so 1 MiB is
#: generous; the cap lets a server drop a client whose prefix claims gigabytes instead of buffering them.
DEFAULT_MAX_FRAME_BYTES = 1 << 20

_PREFIX = struct.Struct(">I")


def frame(payload: bytes) -> bytes:
    """``payload`` with its 4-byte big-endian length prefix.

    Raises:
        ProtocolError: the payload is longer than the prefix can express (4 GiB - 1).
    """
    if len(payload) > MAX_PREFIX_VALUE:
        raise ProtocolError(f"payload of {len(payload)} bytes exceeds the 4-byte prefix", 0, payload[:16])
    return _PREFIX.pack(len(payload)) + payload


class FrameDecoder:
    """Incremental decoder: feed bytes as they arrive in any chunking, get complete payloads back.

    The stream offset is tracked so an error can say where in the stream the bad prefix began. After an
    error the decoder stays broken (every later :meth:`feed` raises again): the peer's stream can no longer
    be resynchronised, so the caller should drop the connection.

    Args:
        max_frame_bytes: largest accepted payload [bytes]; a longer announced length raises at once,
            before any of the payload is buffered.
    """

    def __init__(self, max_frame_bytes: int = DEFAULT_MAX_FRAME_BYTES) -> None:
        if not 0 <= max_frame_bytes <= MAX_PREFIX_VALUE:
            raise ValueError(f"max_frame_bytes must be in [0, {MAX_PREFIX_VALUE}], got {max_frame_bytes}")
        self.max_frame_bytes = max_frame_bytes
        self._buffer = bytearray()
        self._consumed_bytes = 0  # stream offset of _buffer[0]
        self._error: ProtocolError | None = None

    @property
    def pending_bytes(self) -> int:
        """Bytes received but not yet returned as part of a complete frame (0 at a frame boundary)."""
        return len(self._buffer)

    def feed(self, data: bytes) -> list[bytes]:
        """Add received bytes; return the payloads completed by them, in order (possibly none).

        Raises:
            ProtocolError: a length prefix above ``max_frame_bytes`` (offset = stream offset of the prefix,
                snippet = the prefix bytes).
        """
        if self._error is not None:
            raise self._error
        buffer = self._buffer
        buffer += data
        payloads: list[bytes] = []
        start = 0
        end = len(buffer)
        while end - start >= PREFIX_BYTES:
            (length,) = _PREFIX.unpack_from(buffer, start)
            if length > self.max_frame_bytes:
                self._error = ProtocolError(
                    f"frame length {length} exceeds the maximum of {self.max_frame_bytes} bytes",
                    self._consumed_bytes + start,
                    bytes(buffer[start : start + PREFIX_BYTES]),
                )
                raise self._error
            stop = start + PREFIX_BYTES + length
            if stop > end:
                break
            payloads.append(bytes(buffer[start + PREFIX_BYTES : stop]))
            start = stop
        if start:
            del buffer[:start]
            self._consumed_bytes += start
        return payloads


def _recv_up_to(sock: socket.socket, size: int) -> bytes:
    """Up to ``size`` bytes from ``sock``: fewer only when the peer closed the connection first."""
    chunks = bytearray()
    while len(chunks) < size:
        chunk = sock.recv(size - len(chunks))
        if not chunk:
            break
        chunks += chunk
    return bytes(chunks)


def _truncated(received_bytes: int, tail: bytes) -> ProtocolError:
    return ProtocolError(f"connection closed inside a frame after {received_bytes} bytes", received_bytes, tail[-16:])


def read_frame(sock: socket.socket, max_frame_bytes: int = DEFAULT_MAX_FRAME_BYTES) -> bytes | None:
    """Block until one whole frame has arrived on ``sock``; return its payload.

    Returns:
        The payload, or None when the peer closed the connection cleanly between frames.

    Raises:
        ProtocolError: the peer closed mid-frame (offset = bytes of this frame received, prefix included)
            or announced a payload above ``max_frame_bytes``.
        OSError: the socket failed.
    """
    prefix = _recv_up_to(sock, PREFIX_BYTES)
    if not prefix:
        return None
    if len(prefix) < PREFIX_BYTES:
        raise _truncated(len(prefix), prefix)
    (length,) = _PREFIX.unpack(prefix)
    if length > max_frame_bytes:
        raise ProtocolError(f"frame length {length} exceeds the maximum of {max_frame_bytes} bytes", 0, prefix)
    payload = _recv_up_to(sock, length)
    if len(payload) < length:
        raise _truncated(PREFIX_BYTES + len(payload), prefix + payload)
    return payload


def write_frame(sock: socket.socket, payload: bytes) -> None:
    """Send ``payload`` as one frame (blocks until the kernel took every byte).

    Raises:
        ProtocolError: payload too long for the prefix.
        OSError: the socket failed.
    """
    sock.sendall(frame(payload))
