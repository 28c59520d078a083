"""One real rcssserver3d, its monitor link and one agent's connection: the session the real-server rollouts
(kicks, stand-ups) run their cycles in.

Why one class: the kick and stand-up benches each carried a copy of the start-up order (server, a second for
it to listen, monitor, agent socket, the agent's first message) and of the shutdown (socket, monitor, server,
whatever fails); a fix to one (e.g. stopping the server when the connection fails) has to reach both.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from agent.agent import Agent, AgentConfig
from agent.protocol.effectors import Action
from agent.protocol.framing import read_frame, write_frame
from agent.world_model import WorldModel
from motion_studio.realserver.process import AGENT_PORT, MonitorLink, RealServer, connect

#: Seconds the server gets to listen before the monitor and the agent connect.
LISTEN_WAIT_S = 1.0
#: A sense message missing this long is a stalled server [s].
STALL_S = 10.0


class RealSession:
    """A real server started in this network namespace (``netns.sh``), its monitor link and the connection
    of one agent (``team``, ``unum``, ``robot_type``) driven by ``behavior``.

    Raises:
        OSError: the server did not accept the monitor or the agent (the server is stopped first).
    """

    def __init__(self, scripts: Path, workdir: Path, behavior: Callable[[WorldModel], list[Action]],
                 team: str, unum: int, robot_type: int = 0) -> None:
        workdir.mkdir(parents=True, exist_ok=True)
        self.workdir = workdir
        self.log_path = workdir / "server.log"
        self.server = RealServer(scripts, self.log_path)
        try:
            time.sleep(LISTEN_WAIT_S)
            self.monitor = MonitorLink()
            self.sock = connect(AGENT_PORT)
            self.sock.settimeout(STALL_S)
        except BaseException:
            self.server.stop()
            raise
        self.agent = Agent(AgentConfig(team, unum, robot_type, say=False), behavior)
        write_frame(self.sock, self.agent.connect_message())

    def read(self) -> bytes:
        """The next sense message.

        Raises:
            RuntimeError: the server closed the connection.
        """
        payload = read_frame(self.sock)
        if payload is None:
            raise RuntimeError("the real server closed the connection")
        return payload

    def answer(self, reply: bytes) -> None:
        write_frame(self.sock, reply)

    def step(self) -> None:
        """One cycle: the sense message in, the agent's answer out."""
        self.answer(self.agent.step(self.read()))

    def send(self, command: str) -> None:
        """A trainer command on the monitor port."""
        self.monitor.send(command)

    def log_size(self) -> int:
        return self.log_path.stat().st_size

    def collisions_since(self, offset: int = 0) -> int:
        """Self-collisions the server reported since byte ``offset`` of its log (it freezes self-colliding
        joints and prints each pair per cycle, REFERENCE §4.5)."""
        with open(self.log_path, "rb") as log:
            log.seek(offset)
            return log.read().count(b"ANALYSECOLLISIONS")

    def close(self) -> None:
        try:
            self.sock.close()
        finally:
            try:
                self.monitor.close()
            finally:
                self.server.stop()
