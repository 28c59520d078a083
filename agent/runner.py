"""TCP transport for one agent: connect, frame, call ``Agent.step``, answer, reconnect; ``python -m agent``.

Everything stateful about the game lives in :class:`~agent.agent.Agent`; this module owns only the socket,
the retry policy and the log. Policy:

* connecting: ``connect_attempts`` tries with exponential backoff (``backoff_s`` doubling up to
  ``backoff_max_s``); none answering raises :class:`~agent.errors.ServerUnreachable` (exit code 2 from the CLI);
* a lost connection (closed, reset, silent for ``read_timeout_s``, a broken length prefix) starts a fresh
  Agent on a new connection, at most ``max_reconnects`` times;
* a malformed sense message is logged and counted, answered with ``(syn)`` (the server waits for it in sync
  mode), and the agent goes on with the next one.
"""

from __future__ import annotations

import argparse
import logging
import math
import os
import socket
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NoReturn

from agent.agent import Agent, AgentConfig
from agent.drawing.udp import DEFAULT_DRAW_HOST, DEFAULT_DRAW_PORT, RoboVizDrawer, drawer_from_env
from agent.drawing.udp import ENV_VAR as DRAW_ENV_VAR
from agent.player import BEHAVIORS, DEFAULT_BEHAVIOR, agent_factory
from agent.errors import ConfigError, ServerUnreachable
from agent.localization import DEFAULT_LOCALIZER, LOCALIZERS
from agent.protocol.errors import ProtocolError
from agent.protocol.framing import read_frame, write_frame
from agent.team.composition import parse_robot_type, robot_type_for

logger = logging.getLogger(__name__)

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 3100
SYN_ONLY = b"(syn)"


@dataclass(frozen=True)
class ConnectionPolicy:
    """Retry and timeout settings of the transport."""

    connect_attempts: int = 5
    """Connection attempts before giving up."""
    backoff_s: float = 0.5
    """Wait after the first failed attempt [s]; doubles each time."""
    backoff_max_s: float = 4.0
    """Longest wait between attempts [s]."""
    read_timeout_s: float = 10.0
    """A server silent this long counts as lost [s]."""
    max_reconnects: int = 3
    """New connections after a lost one before giving up."""


@dataclass
class RunStats:
    """What happened during :func:`run`."""

    connections: int = 0
    cycles: int = 0
    bad_messages: int = 0
    lost_connections: int = 0


def connect(host: str, port: int, policy: ConnectionPolicy, stop: threading.Event | None = None) -> socket.socket:
    """A connected TCP socket, after up to ``policy.connect_attempts`` tries with backoff.

    Raises:
        ServerUnreachable: no attempt succeeded.
    """
    wait = policy.backoff_s
    error: OSError | None = None
    for attempt in range(1, policy.connect_attempts + 1):
        try:
            sock = socket.create_connection((host, port), timeout=policy.read_timeout_s)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            return sock
        except OSError as exc:
            error = exc
            logger.info("connect to %s:%d failed (attempt %d/%d): %s", host, port, attempt,
                        policy.connect_attempts, exc)
        if attempt < policy.connect_attempts:
            if stop is not None and stop.wait(wait):
                break
            if stop is None:
                time.sleep(wait)
            wait = min(wait * 2.0, policy.backoff_max_s)
    raise ServerUnreachable(f"no server answered at {host}:{port} after {policy.connect_attempts} attempt(s)"
                            f" (last error: {error})", policy.connect_attempts)


STATUS_EVERY_CYCLES = 250  # one status line per 5 s of server time: enough to watch, little to read


def status_line(agent: Agent) -> str:
    """What a person watching the agent wants to know: game state, self pose, ball, teammates heard."""
    world = agent.world
    pose = world.pose
    where = "not localized" if pose is None else \
        f"pose ({pose.x_m:.2f}, {pose.y_m:.2f}, {math.degrees(pose.heading_rad):.0f} deg)"
    ball = world.ball
    ball_text = "ball unseen" if ball is None or ball.x_m is None else f"ball ({ball.x_m:.2f}, {ball.y_m:.2f})"
    seen = {unum: (round(t.x_m, 1), round(t.y_m, 1)) for unum, t in sorted(world.teammates.items())
            if t.source == "vision" and t.x_m is not None}
    # the age of each teammate's last message, whether or not it is also seen: a teammate seen nearby but
    # unheard for seconds (its say turns lost) once read as "not heard" in this line
    heard = {unum: f"{world.now_s - r.heard_s:.1f} s ago" for unum, r in sorted(world.reports.items())}
    return (f"t={world.now_s:.2f} {world.game.play_mode} #{world.unum} {where}, {ball_text}, "
            f"teammates seen {seen}, last heard {heard}, last said {agent.said[-1] if agent.said else '-'}")


def serve(sock: socket.socket, agent: Agent, stats: RunStats, stop: threading.Event | None = None,
          drawer: RoboVizDrawer | None = None) -> None:
    """Play one connection until the server closes it or ``stop`` is set (drawing to RoboViz with ``drawer``).

    Raises:
        OSError: the socket failed or timed out.
        ProtocolError: the frame stream broke (a truncated frame or an absurd length prefix).
    """
    write_frame(sock, agent.connect_message())
    while stop is None or not stop.is_set():
        payload = read_frame(sock)
        if payload is None:
            return
        try:
            reply = agent.step(payload)
        except ProtocolError as error:
            stats.bad_messages += 1
            logger.warning("skipped malformed sense message %d: %s", stats.cycles, error)
            reply = SYN_ONLY
        stats.cycles += 1
        write_frame(sock, reply)
        if drawer is not None:   # after the answer: drawing never delays the server
            drawer.draw(agent)
        if stats.cycles % STATUS_EVERY_CYCLES == 0:
            logger.info("%s", status_line(agent))


def run(config: AgentConfig, host: str = DEFAULT_HOST, port: int = DEFAULT_PORT,
        policy: ConnectionPolicy | None = None, stop: threading.Event | None = None,
        make_agent: Callable[[AgentConfig], Agent] = Agent, drawer: RoboVizDrawer | None = None) -> RunStats:
    """Connect and play until the server goes away for good or ``stop`` is set; ``drawer`` draws the
    agent's beliefs in RoboViz (off when None).

    Raises:
        ServerUnreachable: no server at the start, or none came back after a lost connection.
    """
    policy = policy or ConnectionPolicy()
    stats = RunStats()
    reconnects = 0
    while True:
        # The agent is built before connecting, never between the connection and its (scene ...): building
        # one (motion library, kinematics, first imports) takes 0.1-1 s, and the real server in sync mode,
        # waiting that long for a new connection's first message, stalls every agent for good (each times
        # out, all reconnect in the same cycle and their robots, built at one spot, knock each other over).
        agent = make_agent(config)
        sock = connect(host, port, policy, stop)
        stats.connections += 1
        logger.info("connected to %s:%d as %s #%d (type %d)", host, port, config.team, config.unum,
                    config.robot_type)
        try:
            with sock:
                serve(sock, agent, stats, stop, drawer)
            reason = "closed by the server"
        except (OSError, ProtocolError) as error:
            reason = str(error) or type(error).__name__
        if stop is not None and stop.is_set():
            return stats
        stats.lost_connections += 1
        reconnects += 1
        if reconnects > policy.max_reconnects:
            raise ServerUnreachable(f"connection to {host}:{port} lost ({reason}) and {policy.max_reconnects} "
                                    "reconnection(s) used up", stats.connections)
        logger.warning("connection to %s:%d lost (%s); reconnecting (%d/%d)", host, port, reason, reconnects,
                       policy.max_reconnects)


def _robot_type_arg(text: str) -> int | str:
    """``--type``: 0-4 or ``auto``."""
    try:
        value = parse_robot_type(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return "auto" if value is None else value


class _OneLineErrorParser(argparse.ArgumentParser):
    """argparse with its errors on one line (no usage block above them): the toolkit's CLI rule (issue 16)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {' '.join(message.split())} (see {self.prog} --help)\n")


def _port_arg(text: str) -> int:
    port = int(text)
    if not 1 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"port must be 1-65535, got {port}")
    return port


def build_parser() -> argparse.ArgumentParser:
    """The usual rcssserver3d agent flags."""
    parser = _OneLineErrorParser(prog="python -m agent", description="Run one Nao soccer agent over TCP.")
    parser.add_argument("--host", default=DEFAULT_HOST, help="server address (default 127.0.0.1)")
    parser.add_argument("--port", type=_port_arg, default=DEFAULT_PORT, help="agent port (default 3100)")
    parser.add_argument("--team", default="Nao3D", help="team name (default Nao3D)")
    parser.add_argument("--unum", type=int, default=0, help="uniform number 1-11, 0 = next free (default 0)")
    parser.add_argument("--type", dest="robot_type", type=_robot_type_arg, default="auto",
                        help="robot type 0-4, or auto: our team's type for the unum (agent.team.composition: "
                             "0, 2, 4 cycled; 0 when --unum is 0) (default auto)")
    parser.add_argument("--localization", default=DEFAULT_LOCALIZER, choices=sorted(LOCALIZERS),
                        help=f"self-localization method (default {DEFAULT_LOCALIZER})")
    parser.add_argument("--behavior", default=DEFAULT_BEHAVIOR, choices=sorted(BEHAVIORS),
                        help=f"what the agent does: soccer plays with the shipped motions, idle only connects, "
                             f"beams, localizes and talks (default {DEFAULT_BEHAVIOR})")
    parser.add_argument("--attempts", type=int, default=ConnectionPolicy.connect_attempts,
                        help="connection attempts before giving up (default 5)")
    parser.add_argument("--roboviz-draw", nargs="?", const=f"{DEFAULT_DRAW_HOST}:{DEFAULT_DRAW_PORT}", default=None,
                        metavar="HOST:PORT",
                        help=f"draw the agent's beliefs, target and role in RoboViz over UDP (default off; the "
                             f"flag alone sends to {DEFAULT_DRAW_HOST}:{DEFAULT_DRAW_PORT}; the environment "
                             f"variable {DRAW_ENV_VAR}=HOST:PORT turns it on too)")
    parser.add_argument("--log-level", default="INFO", help="logging level (default INFO)")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """CLI entry: returns the process exit code (0 done, 2 bad options or no server)."""
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    robot_type = robot_type_for(args.unum) if args.robot_type == "auto" else args.robot_type
    return run_cli(args.host, args.port, args.team, args.unum, robot_type, args.localization, args.attempts,
                   args.behavior, args.roboviz_draw)


def run_cli(host: str, port: int, team: str, unum: int, robot_type: int, localization: str = DEFAULT_LOCALIZER,
            attempts: int = ConnectionPolicy.connect_attempts, behavior: str = DEFAULT_BEHAVIOR,
            roboviz_draw: str | None = None) -> int:
    """Run with user-facing error handling: a clear message on stderr and a non-zero code on failure.

    ``roboviz_draw``: RoboViz's HOST:PORT for belief drawings (None: ``NAO3D_ROBOVIZ_DRAW``, else off)."""
    try:
        config = AgentConfig(team=team, unum=unum, robot_type=robot_type, localization=localization)
        drawer = drawer_from_env(os.environ, roboviz_draw)
        if drawer is not None:
            logger.info("drawing beliefs to RoboViz at %s:%d (UDP)", *drawer.address)
        stats = run(config, host, port, ConnectionPolicy(connect_attempts=max(1, attempts)),
                    make_agent=agent_factory(behavior), drawer=drawer)
    except ConfigError as error:
        print(f"agent: bad option {error.field}: {error}", file=sys.stderr)
        return 2
    except ServerUnreachable as error:
        print(f"agent: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    print(f"agent: done after {stats.cycles} cycles ({stats.bad_messages} malformed messages skipped)",
          file=sys.stderr)
    return 0
