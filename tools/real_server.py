"""The real rcssserver3d 0.7.3 for the measuring tools: a fresh server process and the monitor connection.

Needs the server built by ../shared/real-server/build.sh and a private network namespace (the server binds
0.0.0.0; ../shared/real-server/netns.sh). Never used by tests.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import threading
import time
from pathlib import Path

from agent.protocol.framing import read_frame, write_frame

REAL_SERVER_DIR = Path("/work/shared/real-server")


class RealServer:
    """A fresh real rcssserver3d (server.sh) in this namespace; stopped with SIGINT, as it wants."""

    def __init__(self, log_path: Path) -> None:
        # sync mode, not real time, a monitor frame every cycle (server.sh reads these)
        env = dict(os.environ, SS_SYNC="1", SS_REALTIME="0", SS_MONITOR_STEP="0.02")
        self.log = open(log_path, "w")
        self.process = subprocess.Popen(["bash", str(REAL_SERVER_DIR / "server.sh")], env=env, stdout=self.log,
                                        stderr=subprocess.STDOUT, start_new_session=True)

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(5)
        self.log.close()


def connect(port: int, timeout_s: float = 20.0) -> socket.socket:
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            sock = socket.create_connection(("127.0.0.1", port), timeout=10)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            return sock
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.2)


class MonitorLink:
    """The monitor connection: a thread keeps every frame (raw, parsed afterwards); trainer commands go out."""

    def __init__(self, port: int = 3200) -> None:
        self.sock = connect(port)
        self.frames: list[bytes] = []
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()

    def _read(self) -> None:
        try:
            while (payload := read_frame(self.sock)) is not None:
                self.frames.append(payload)
        except (OSError, ValueError):
            return

    def send(self, command: str) -> None:
        write_frame(self.sock, command.encode())

    def close(self) -> None:
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.sock.close()
        self.thread.join(5)
