"""The real rcssserver3d 0.7.3 as a process: a fresh server (server.sh), the re-exec into a private network
namespace (netns.sh; the server binds 0.0.0.0), the agent connection and the monitor link.

Needs the server built by ``<scripts>/build.sh``; never used by tests.
"""

from __future__ import annotations

import logging
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

from agent.protocol.framing import read_frame, write_frame
from kinematics.child_process import set_parent_death_signal
from motion_studio.realserver.paths import DIR_VARIABLE

#: netns.sh sets this inside the namespace.
IN_NETNS_VARIABLE = "SS_IN_NETNS"
AGENT_PORT, MONITOR_PORT = 3100, 3200
logger = logging.getLogger(__name__)


def in_netns() -> bool:
    """Whether this process runs inside netns.sh's private namespace."""
    return os.environ.get(IN_NETNS_VARIABLE) == "1"


def reexec_in_netns(scripts: Path, argv: Sequence[str]) -> None:
    """Replace this process by ``argv`` run inside ``scripts/netns.sh`` (no return), unless already inside.

    ``NAO3D_REAL_SERVER_DIR`` is set to ``scripts`` so the new process finds the same scripts.
    """
    if in_netns():
        return
    os.environ[DIR_VARIABLE] = str(scripts)
    netns = str(scripts / "netns.sh")
    sys.stdout.flush()
    os.execvp(netns, [netns, *argv])


def _die_with_parent() -> None:
    """In the server's child before its exec: SIGKILL when the process that started it ends."""
    set_parent_death_signal(signal.SIGKILL)


class RealServer:
    """A fresh real rcssserver3d (server.sh) in this namespace; stopped with SIGINT, as it wants.

    Args:
        scripts: the folder holding server.sh.
        log_path: where the server's output goes.
    """

    def __init__(self, scripts: Path, log_path: Path) -> None:
        # sync mode, not real time, a monitor frame every cycle (server.sh reads these)
        env = dict(os.environ, SS_SYNC="1", SS_REALTIME="0", SS_MONITOR_STEP="0.02")
        self.log = open(log_path, "w")
        # The kernel signals the server when this process dies (server.sh execs it, and the setting survives the
        # exec): a real match killed with SIGTERM left its server running at 87 % of a core for 40 min.
        # RealServer is made in each process's main thread, where PR_SET_PDEATHSIG is safe. The signal is SIGKILL:
        # rcssserver3d 0.7.3 does not end on SIGTERM but spins at a full core (measured 2026-11-27: three such
        # orphans of killed real matches and tuners ran for 35-55 min), and only SIGINT or SIGKILL end it.
        self.process = subprocess.Popen(["bash", str(scripts / "server.sh")], env=env, stdout=self.log,
                                        stderr=subprocess.STDOUT, start_new_session=True,
                                        preexec_fn=_die_with_parent)

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(5)
        self.log.close()


def connect(port: int, timeout_s: float = 20.0, host: str = "127.0.0.1") -> socket.socket:
    """A TCP connection to ``host``:``port``, retried until ``timeout_s`` (the server takes a moment)."""
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            sock = socket.create_connection((host, port), timeout=10)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            return sock
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.2)


class MonitorLink:
    """The monitor connection: a thread keeps every frame (raw, parsed afterwards); trainer commands go out.

    ``failure`` says why the reader stopped before `close` (a socket error, bad framing, or the server closing the
    connection), else None. Why keep it: the frames are the runs' ground truth, and a dead reader also leaves the
    server's monitor output unread (a server whose monitor client does not read stalled a kick-off once), so a
    harness must be able to report it instead of a silent gap.
    """

    def __init__(self, port: int = MONITOR_PORT, host: str = "127.0.0.1") -> None:
        self.sock = connect(port, host=host)
        self.frames: list[bytes] = []
        self.failure: str | None = None
        self._closing = False
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()

    def _read(self) -> None:
        try:
            while (payload := read_frame(self.sock)) is not None:
                self.frames.append(payload)
            reason = "the server closed the connection"
        except (OSError, ValueError) as error:
            reason = f"{type(error).__name__}: {error}"
        if not self._closing:
            self.failure = f"monitor reader stopped after {len(self.frames)} frames: {reason}"
            logger.warning("%s", self.failure)

    def send(self, command: str) -> None:
        write_frame(self.sock, command.encode())

    def close(self) -> None:
        self._closing = True
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.sock.close()
        self.thread.join(5)
