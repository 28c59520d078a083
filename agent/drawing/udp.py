"""The UDP edge of RoboViz drawing: where to send (option or environment variable) and the sender.

Drawing is off unless asked for. UDP never blocks the agent: a RoboViz that is not running costs a dropped
datagram (or an ICMP error, counted and ignored), never a late answer to the server.
"""

from __future__ import annotations

import logging
import socket
from collections.abc import Iterable, Mapping

from agent.agent import Agent
from agent.drawing.beliefs import belief_packets
from agent.errors import ConfigError

logger = logging.getLogger(__name__)

#: RoboViz's draw port (REFERENCE §5.5) and the variable that turns drawing on (``HOST[:PORT]``).
DEFAULT_DRAW_PORT = 32769
DEFAULT_DRAW_HOST = "127.0.0.1"
ENV_VAR = "NAO3D_ROBOVIZ_DRAW"
#: Cycles between drawn frames: 10 frames a second are plenty for eyes and keep the traffic small.
DEFAULT_EVERY_CYCLES = 5


def parse_address(text: str) -> tuple[str, int]:
    """``HOST``, ``HOST:PORT`` or ``:PORT`` (IPv4 or a host name) -> (host, port); host defaults to 127.0.0.1,
    port to 32769.

    Raises:
        ConfigError: a port that is not 1-65535.
    """
    host, _, port_text = text.strip().rpartition(":") if ":" in text else (text.strip(), "", "")
    host = host or DEFAULT_DRAW_HOST
    if not port_text:
        return host, DEFAULT_DRAW_PORT
    if not port_text.isdigit() or not 1 <= int(port_text) <= 65535:
        raise ConfigError(f"RoboViz draw port must be 1-65535, got {port_text!r} in {text!r}", "roboviz-draw")
    return host, int(port_text)


class RoboVizDrawer:
    """Sends an agent's belief drawings to RoboViz over UDP every ``every_cycles`` calls of `draw`.

    Args:
        host, port: RoboViz's address (its draw port is 32769).
        every_cycles: draw one frame in this many cycles.
    """

    def __init__(self, host: str = DEFAULT_DRAW_HOST, port: int = DEFAULT_DRAW_PORT,
                 every_cycles: int = DEFAULT_EVERY_CYCLES) -> None:
        if every_cycles < 1:
            raise ConfigError(f"every_cycles must be >= 1, got {every_cycles}", "every_cycles")
        self.address = (host, port)
        self.every_cycles = every_cycles
        self.frames = 0
        self.send_errors = 0
        self._cycle = 0
        self._socket = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self._socket.setblocking(False)

    def draw(self, agent: Agent) -> None:
        """Called once per cycle after ``agent.step``: sends a frame on every ``every_cycles``-th call."""
        self._cycle += 1
        if self._cycle % self.every_cycles:
            return
        packets = belief_packets(agent)
        if packets:
            self.send(packets)
            self.frames += 1

    def send(self, packets: Iterable[bytes]) -> None:
        """One datagram per packet (RoboViz reads one command per datagram)."""
        for packet in packets:
            try:
                self._socket.sendto(packet, self.address)
            except OSError as error:   # RoboViz not running, buffer full: drawing must never stop the agent
                self.send_errors += 1
                if self.send_errors == 1:
                    logger.warning("RoboViz drawing to %s:%d failed (%s); going on without it", *self.address, error)

    def close(self) -> None:
        self._socket.close()


def drawer_from_env(environ: Mapping[str, str], option: str | None = None) -> RoboVizDrawer | None:
    """The drawer the user asked for: the ``--roboviz-draw`` option's address, else ``NAO3D_ROBOVIZ_DRAW``,
    else None (drawing off, the default).

    Raises:
        ConfigError: a bad address.
    """
    text = option if option is not None else environ.get(ENV_VAR, "")
    if not text.strip():
        return None
    host, port = parse_address(text)
    return RoboVizDrawer(host, port)
