"""The protocol room's one exception: bad wire bytes, located by byte offset with the bytes around it."""

from __future__ import annotations

from kinematics.errors import ToolkitError

#: Bytes shown on each side of the offending offset in an error message; enough to recognise the predicate.
SNIPPET_RADIUS_BYTES = 24


def snippet_around(data: bytes | str, offset: int, radius: int = SNIPPET_RADIUS_BYTES) -> bytes:
    """The bytes of ``data`` within ``radius`` of ``offset`` (clipped to the data), for error messages.

    Args:
        data: the whole message (``str`` is taken as ASCII/Latin-1 so offsets stay byte offsets).
        offset: byte offset of the problem; may equal ``len(data)`` (end of input).
        radius: bytes kept on each side.

    Returns:
        The slice ``data[offset - radius : offset + radius]`` as bytes.
    """
    raw = data.encode("latin-1", "replace") if isinstance(data, str) else bytes(data)
    return raw[max(0, offset - radius) : offset + radius]


class ProtocolError(ToolkitError, ValueError):
    """A wire message (or a value about to become one) that breaks the rcssserver3d protocol.

    It is a ``ValueError`` as well, so callers validating user input (say messages, effector values) can
    catch either. Servers catch it at the edge, log it with the offset and snippet, and drop the message.

    Args:
        message: what is wrong, with the expected and the actual value.
        offset: byte offset of the problem in the message (``len(message)`` for a truncated one).
        snippet: the bytes around ``offset`` (see :func:`snippet_around`).
    """

    def __init__(self, message: str, offset: int, snippet: bytes) -> None:
        super().__init__(f"{message} (at byte {offset}, near {snippet!r})")
        self.reason = message
        self.offset = offset
        self.snippet = snippet

    def __reduce__(self) -> tuple[type[ProtocolError], tuple[str, int, bytes]]:
        # Match batches run in worker processes; the default reduce would replay only the formatted text.
        return (type(self), (self.reason, self.offset, self.snippet))

    @classmethod
    def at(cls, message: str, data: bytes | str, offset: int) -> ProtocolError:
        """An error at ``offset`` of ``data``, with the snippet cut from ``data``."""
        return cls(message, offset, snippet_around(data, offset))
