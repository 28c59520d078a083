"""Match runner: two teams of agents on our server, with the referee driven as a trainer would.

The agents are hosted in this process (`sim.inprocess`) or in worker processes that think while the engine
steps (`sim.agent_processes`, ``run_match(..., agent_processes=N)``): the same match byte for byte.

The runner plays the role of the human/monitor that starts a real rcssserver3d match: it waits while
agents connect and beam, sends the kick-off (the server's AutomaticKickOff is off, REFERENCE §4.3) and
again at the second half, and watches the world for results (score, falls, possession). Agents come
from a factory the caller injects, because sim/ may not import the agent room (DESIGN.md).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from sim.engine import SimEngine
from sim.inprocess import HostedAgent, InProcessHost

logger = logging.getLogger(__name__)

AgentFactory = Callable[[str, int, int], HostedAgent]  # (team name, unum, robot type) -> agent
FALLEN_TORSO_Z_M = 0.25  # REFERENCE §4.5 "not standing"; §8.1 uses the same height for falls
STANDING_AGAIN_Z_M = 0.30  # hysteresis so a robot wobbling around 0.25 m counts one fall
POSSESSION_RADIUS_M = 0.5


@dataclass(frozen=True)
class MatchConfig:
    """One match.

    players_per_team: 1-11 agents per side. robot_types: type per unum (cycled), REFERENCE §2.5; the
    default is our team's choice (``agent.team.composition.TEAM_TYPES``: the types the shipped motions
    stand up with; sim/ does not import agent/, a test keeps the two equal).
    duration_s: game time to play (600 = two full halves; shorter values stop early).
    kick_off_wait_s: server time given to agents to connect, init and beam before each kick-off.
    seed: the engine's seed (noise, beams). log_path: SimSpark monitor log to write, or None.
    """

    team_left: str = "Left"
    team_right: str = "Right"
    players_per_team: int = 3
    robot_types: tuple[int, ...] = (0, 2, 4)
    duration_s: float = 600.0
    kick_off_wait_s: float = 3.0
    seed: int = 0
    log_path: str | None = None
    match_id: str = "match"


@dataclass
class MatchResult:
    """What a match produced; JSON-serialisable (``asdict``) so batches checkpoint it line by line."""

    match_id: str
    seed: int
    score_left: int = 0
    score_right: int = 0
    falls: dict[str, int] = field(default_factory=lambda: {"left": 0, "right": 0})
    possession: dict[str, float] = field(default_factory=lambda: {"left": 0.0, "right": 0.0})
    cycles: int = 0
    game_time_s: float = 0.0
    wall_s: float = 0.0
    agent_errors: int = 0
    final_play_mode: str = ""


class CrashGuard:
    """Wraps an agent so that an exception in its step costs that cycle, never the match.

    The agent answers ``(syn)`` for the cycle that failed (its robot keeps its last joint velocities, as
    on the real server when an agent is late); the count is in ``errors``.
    """

    def __init__(self, agent: HostedAgent, name: str) -> None:
        self.agent = agent
        self.name = name
        self.errors = 0

    def connect_message(self) -> bytes:
        return self.agent.connect_message()

    def step(self, sense: bytes) -> bytes:
        try:
            return self.agent.step(sense)
        except Exception:  # the edge between the match and a user's agent code
            self.errors += 1
            if self.errors <= 3:
                logger.exception("agent %s raised; it answers (syn) this cycle", self.name)
            return b"(syn)"


class MatchWatcher:
    """Counts falls (torso below 0.25 m after having stood) and possession (nearest robot within 0.5 m)."""

    def __init__(self) -> None:
        self.fallen: dict[tuple[str, int], bool] = {}
        self.falls = {"left": 0, "right": 0}
        self.possession_cycles = {"left": 0, "right": 0}
        self.play_cycles = 0

    def update(self, world: Any, play_mode: str) -> None:
        robots = world.robots()
        for robot in robots:
            key = (robot.team, robot.unum)
            z = robot.torso_pos_m[2]
            if not self.fallen.get(key, False) and z < FALLEN_TORSO_Z_M:
                self.fallen[key] = True
                if robot.team in self.falls:
                    self.falls[robot.team] += 1
            elif self.fallen.get(key, False) and z > STANDING_AGAIN_Z_M:
                self.fallen[key] = False
        if play_mode != "PlayOn":
            return
        self.play_cycles += 1
        bx, by, _ = world.ball_position()
        nearest = min(robots, default=None,
                      key=lambda r: math.hypot(r.torso_pos_m[0] - bx, r.torso_pos_m[1] - by))
        if nearest is not None and nearest.team in self.possession_cycles and \
                math.hypot(nearest.torso_pos_m[0] - bx, nearest.torso_pos_m[1] - by) <= POSSESSION_RADIUS_M:
            self.possession_cycles[nearest.team] += 1

    def possession(self) -> dict[str, float]:
        total = max(1, self.play_cycles)
        return {team: cycles / total for team, cycles in self.possession_cycles.items()}


def run_match(config: MatchConfig, make_agent: AgentFactory,
              progress: Callable[[float, float], None] | None = None, agent_processes: int = 0) -> MatchResult:
    """Play one match headless and return its result.

    Args:
        config: teams, size, duration, seed, log.
        make_agent: builds each agent (team name, unum, robot type).
        progress: called about once per game second with (game time s, duration s).
        agent_processes: 0 hosts the agents in this process (`sim.inprocess`); N >= 1 builds and steps them
            in N worker processes while this one runs the engine (`sim.agent_processes`): the same match
            byte for byte, on more cores.
    """
    started = time.perf_counter()
    if agent_processes > 0:
        from sim.agent_processes import AgentProcessHost

        # The workers fork before the engine exists (nothing of MuJoCo's is copied into them).
        with AgentProcessHost(None, make_agent, agent_processes) as host:
            host.engine = engine = SimEngine(seed=config.seed)
            handles = [host.build(team, unum, robot_type) for unum, robot_type, team in connection_order(config)]
            for handle in handles:
                host.connect(handle)
                host.run(2)
            watched = _play(config, engine, host.start_cycle, host.end_cycle, progress)
            agent_errors = host.stats.agent_errors + host.guard_errors
    else:
        engine = SimEngine(seed=config.seed)
        host = InProcessHost(engine)
        guards: list[CrashGuard] = []
        # Connect one agent per cycle pair: robots built in the same cycle at the same spot knock each other
        # over on the real server (shared/real-server/README.md), and we mirror that connection habit.
        for unum, robot_type, team in connection_order(config):
            guard = CrashGuard(make_agent(team, unum, robot_type), f"{team} {unum}")
            guards.append(guard)
            host.add(guard)
            host.run(2)
        watched = _play(config, engine, lambda: host.run(1), lambda: None, progress)
        agent_errors = host.stats.agent_errors + sum(g.errors for g in guards)
    referee = engine.referee
    return MatchResult(
        match_id=config.match_id, seed=config.seed, score_left=referee.score_left, score_right=referee.score_right,
        falls=dict(watched.falls), possession=watched.possession(), cycles=host.stats.cycles,
        game_time_s=round(referee.game_time_s, 2), wall_s=round(time.perf_counter() - started, 2),
        agent_errors=agent_errors, final_play_mode=referee.play_mode)


def connection_order(config: MatchConfig) -> list[tuple[int, int, str]]:
    """(unum, robot type, team) in the order the agents connect: left 1, right 1, left 2, ..."""
    order = []
    for unum in range(1, config.players_per_team + 1):
        robot_type = config.robot_types[(unum - 1) % len(config.robot_types)]
        for team in (config.team_left, config.team_right):
            order.append((unum, robot_type, team))
    return order


def _play(config: MatchConfig, engine: SimEngine, start_cycle: Callable[[], Any], end_cycle: Callable[[], Any],
          progress: Callable[[float, float], None] | None) -> MatchWatcher:
    """The match after the agents connected: cycles until the duration or game over, kick-offs, the watcher,
    the log. A cycle is ``start_cycle`` (the engine steps), the match's own look at the world, ``end_cycle``
    (the agents' replies reach the engine); in-process the whole cycle is in ``start_cycle``."""
    log_writer = _open_log(config.log_path, engine)
    referee = engine.referee
    watcher = MatchWatcher()
    waited_s = 0.0
    last_progress = -1.0
    cycle_s = engine.world.params.cycle_s
    try:
        while referee.play_mode != "GameOver" and referee.game_time_s < config.duration_s:
            start_cycle()
            watcher.update(engine.world, referee.play_mode)
            if log_writer is not None:
                log_writer.on_cycle(engine.cycle)
            if referee.play_mode == "BeforeKickOff":
                waited_s += cycle_s
                if waited_s >= config.kick_off_wait_s:
                    referee.kick_off(None)
                    waited_s = 0.0
            end_cycle()
            if progress is not None and math.floor(referee.game_time_s) > last_progress:
                last_progress = math.floor(referee.game_time_s)
                progress(referee.game_time_s, config.duration_s)
    finally:
        if log_writer is not None:
            log_writer.close()
    return watcher


def _open_log(path: str | None, engine: SimEngine) -> Any:
    """A SimSpark monitor log of the match (a line every 0.2 s as the server's logger, compact numbers), or None."""
    if path is None:
        return None
    from sim.monitor import MonitorLogWriter, MujocoWorldScene, snapshot_of

    scene = MujocoWorldScene(engine.world)
    return MonitorLogWriter(Path(path), lambda: snapshot_of(scene, engine.referee))


def result_to_json(result: MatchResult) -> dict[str, Any]:
    return asdict(result)
