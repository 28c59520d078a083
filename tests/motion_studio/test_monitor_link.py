"""``MonitorLink`` (the real server's monitor connection) says why its reader stopped, over a real loopback socket:
a reader that died silently left a harness without ground truth and the server's monitor output unread."""

from __future__ import annotations

import socket
import struct
import time

import pytest

from motion_studio.realserver.process import MonitorLink


@pytest.fixture()
def listener():
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    yield server
    server.close()


def _frame(payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + payload


def _wait_for(condition, timeout_s: float = 5.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.01)


def test_a_frame_cut_short_is_reported_with_the_frames_read_before(listener: socket.socket):
    link = MonitorLink(listener.getsockname()[1])
    peer, _ = listener.accept()
    peer.sendall(_frame(b"(time 0.02)") + _frame(b"(time 0.04)") + struct.pack(">I", 100) + b"(time")
    peer.close()
    _wait_for(lambda: not link.thread.is_alive())
    assert link.frames == [b"(time 0.02)", b"(time 0.04)"]
    assert link.failure is not None and "after 2 frames" in link.failure and "ProtocolError" in link.failure
    link.close()


def test_the_server_closing_the_connection_is_a_failure_but_closing_it_ourselves_is_not(listener: socket.socket):
    port = listener.getsockname()[1]
    link = MonitorLink(port)
    peer, _ = listener.accept()
    peer.sendall(_frame(b"(time 0.02)"))
    peer.close()
    _wait_for(lambda: not link.thread.is_alive())
    assert link.failure == "monitor reader stopped after 1 frames: the server closed the connection"
    link.close()

    ours = MonitorLink(port)
    peer, _ = listener.accept()
    peer.sendall(_frame(b"(time 0.02)"))
    _wait_for(lambda: len(ours.frames) == 1)
    ours.close()
    peer.close()
    assert not ours.thread.is_alive() and ours.failure is None
