"""Serve the whole simulator over TCP: `SimEngine` + referee behind a `SimServer`, with the monitor feed,
trainer commands and the monitor log wired in (what ``motion-studio serve`` runs)."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

from agent.protocol.errors import ProtocolError
from sim.tcp_server import DEFAULT_AGENT_PORT, DEFAULT_HOST, DEFAULT_MONITOR_PORT, SimServer

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class ServeOptions:
    """What `motion-studio serve` sets: bind address, ports (monitor None = none), modes, seed, log file.

    automatic_kick_off: kick off by itself ``kick_off_wait_s`` after the first agent arrived (rcssserver3d's
    ``AutomaticKickOff``; its default is off: a monitor or trainer sends ``(kickOff Left|Right|None)``).
    kick_off_wait_s: the wait of an automatic kick-off (None: the rule's ``WaitBeforeKickOff``, 30 s).
    log_step_cycles: cycles between log lines (10 = 0.2 s, the server's ``$monitorLoggerStep`` and the frame
    period RoboViz's log player assumes; 2 = every monitor frame, five times the size).
    """

    host: str = DEFAULT_HOST
    agent_port: int = DEFAULT_AGENT_PORT
    monitor_port: int | None = DEFAULT_MONITOR_PORT
    sync: bool = True
    real_time: bool = False
    seed: int | None = None
    log_path: str | None = None
    log_step_cycles: int = 10
    sync_timeout_s: float | None = None
    automatic_kick_off: bool = False
    kick_off_wait_s: float | None = None


def build_simulation_server(options: ServeOptions, engine: object | None = None) -> tuple[SimServer, Callable[[], None]]:
    """The simulator behind a `SimServer`: engine, monitor feed, trainer commands and the log writer.

    Args:
        options: see `ServeOptions`.
        engine: an engine with ``world`` and ``referee`` attributes (a new ``sim.engine.SimEngine`` if None).

    Returns:
        The bound server (ports known) and a function that closes the log; call it after the server stops.
    """
    from sim.monitor import MonitorLogWriter, MujocoWorldScene, WorldMonitorFeed, snapshot_of
    from sim.rules.trainer import apply_trainer_message

    if engine is None:
        from sim.engine import SimEngine
        from sim.referee import Referee
        from sim.rules.params import default_config

        rules = {"automatic_kick_off": options.automatic_kick_off}
        if options.kick_off_wait_s is not None:
            rules["wait_before_kick_off_s"] = options.kick_off_wait_s
        engine = SimEngine(seed=options.seed, sync=options.sync,  # type: ignore[arg-type]
                           referee=Referee(default_config(**rules), seed=options.seed))
    world, referee = engine.world, engine.referee  # type: ignore[attr-defined]
    scene = MujocoWorldScene(world)
    if getattr(referee, "body_pose_source", None) is None and not hasattr(world, "robot_body_poses"):
        referee.body_pose_source = scene.robot_body_poses  # enables the self-collision rule

    def snapshot():
        return snapshot_of(scene, referee)

    def trainer(payload: bytes) -> None:
        try:
            apply_trainer_message(payload, referee, world)
        except ProtocolError as error:
            logger.warning("trainer message rejected: %s", error)

    writer = MonitorLogWriter(options.log_path, snapshot, options.log_step_cycles) if options.log_path else None
    server = SimServer(engine, host=options.host, agent_port=options.agent_port,  # type: ignore[arg-type]
                       monitor_port=options.monitor_port, sync=options.sync, real_time=options.real_time,
                       monitor=WorldMonitorFeed(snapshot), trainer=trainer,
                       on_cycle=writer.on_cycle if writer is not None else None,
                       sync_timeout_s=options.sync_timeout_s)
    server.bind()
    return server, (writer.close if writer is not None else (lambda: None))
