"""Length-prefixed framing: pure encoder/decoder (any chunking) and the blocking socket helpers."""

from __future__ import annotations

import socket
import struct
from collections.abc import Iterator

import pytest
from hypothesis import given
from hypothesis import strategies as st

from agent.protocol.errors import ProtocolError
from agent.protocol.framing import FrameDecoder, frame, read_frame, write_frame
from tests.agent.protocol_samples import received


def test_frame_prefixes_the_big_endian_length() -> None:
    assert frame(b"(syn)") == b"\x00\x00\x00\x05(syn)"
    assert frame(b"") == b"\x00\x00\x00\x00"
    assert frame(b"x" * 258)[:4] == b"\x00\x00\x01\x02"


def test_decoder_returns_real_messages_fed_byte_by_byte() -> None:
    messages = received()[:20]
    stream = b"".join(frame(m) for m in messages)
    decoder = FrameDecoder()
    out: list[bytes] = []
    for index in range(len(stream)):
        out += decoder.feed(stream[index : index + 1])
    assert out == messages
    assert decoder.pending_bytes == 0


@given(
    payloads=st.lists(st.binary(max_size=300), max_size=12),
    cuts=st.lists(st.integers(min_value=0, max_value=4000), max_size=30),
)
def test_decoder_is_independent_of_chunking(payloads: list[bytes], cuts: list[int]) -> None:
    stream = b"".join(frame(p) for p in payloads)
    bounds = sorted({0, len(stream), *(c for c in cuts if c < len(stream))})
    decoder = FrameDecoder(max_frame_bytes=300)
    out: list[bytes] = []
    for start, stop in zip(bounds, bounds[1:]):
        out += decoder.feed(stream[start:stop])
    assert out == payloads
    assert decoder.pending_bytes == 0


def test_decoder_holds_a_partial_frame_until_it_completes() -> None:
    decoder = FrameDecoder()
    data = frame(b"(time (now 1.00))")
    assert decoder.feed(data[:9]) == []
    assert decoder.pending_bytes == 9
    assert decoder.feed(data[9:]) == [b"(time (now 1.00))"]


def test_oversized_prefix_is_rejected_with_its_stream_offset() -> None:
    decoder = FrameDecoder(max_frame_bytes=1024)
    huge = struct.pack(">I", 1025)
    assert decoder.feed(frame(b"(syn)") + huge[:2]) == [b"(syn)"]
    with pytest.raises(ProtocolError) as error:
        decoder.feed(huge[2:] + b"(he1")
    assert error.value.offset == 9  # the 9-byte (syn) frame came first
    assert error.value.snippet == huge
    assert "1025" in str(error.value) and "byte 9" in str(error.value)
    with pytest.raises(ProtocolError):  # the stream cannot be resynchronised: stays broken
        decoder.feed(b"")


def test_default_cap_is_one_mebibyte() -> None:
    FrameDecoder().feed(struct.pack(">I", 1 << 20))
    with pytest.raises(ProtocolError):
        FrameDecoder().feed(struct.pack(">I", (1 << 20) + 1))


@pytest.fixture
def socket_pair() -> Iterator[tuple[socket.socket, socket.socket]]:
    left, right = socket.socketpair()
    left.settimeout(5)
    right.settimeout(5)
    yield left, right
    left.close()
    right.close()


def test_socket_helpers_round_trip(socket_pair: tuple[socket.socket, socket.socket]) -> None:
    sender, receiver = socket_pair
    for message in received()[:3] + [b""]:
        write_frame(sender, message)
        assert read_frame(receiver) == message
    sender.close()
    assert read_frame(receiver) is None  # clean close between frames


def test_read_frame_reports_a_truncated_payload(socket_pair: tuple[socket.socket, socket.socket]) -> None:
    sender, receiver = socket_pair
    sender.sendall(struct.pack(">I", 10) + b"(sy")
    sender.close()
    with pytest.raises(ProtocolError) as error:
        read_frame(receiver)
    assert error.value.offset == 7  # 4 prefix bytes + 3 payload bytes arrived


def test_read_frame_reports_a_truncated_prefix(socket_pair: tuple[socket.socket, socket.socket]) -> None:
    sender, receiver = socket_pair
    sender.sendall(b"\x00\x00")
    sender.close()
    with pytest.raises(ProtocolError) as error:
        read_frame(receiver)
    assert error.value.offset == 2


def test_read_frame_rejects_an_oversized_prefix(socket_pair: tuple[socket.socket, socket.socket]) -> None:
    sender, receiver = socket_pair
    sender.sendall(struct.pack(">I", 5000))
    with pytest.raises(ProtocolError) as error:
        read_frame(receiver, max_frame_bytes=4096)
    assert error.value.offset == 0
