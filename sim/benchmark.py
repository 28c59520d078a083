"""Simulation speed: N in-process agents on one core, as a real-time factor (figures, never assertions).

Each agent does what a light real agent does every cycle: parses its whole sense message with
`agent.protocol.parse_sense` and answers all 22 joint velocities plus ``(syn)`` (head and arms swing, legs
sway a little, so the robots keep standing and the motors keep working). Targets on one core: 1 robot
>= 100x real time, 22 robots >= 5x.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from agent.protocol.constants import CYCLE_S
from agent.protocol.effectors import Init, Scene, format_actions, joint_velocity_template
from agent.protocol.sense import parse_sense
from kinematics.spec import EFFECTOR_NAMES
from sim.engine import SimEngine
from sim.inprocess import InProcessHost

#: Real-time factor goals on one core (DESIGN / issue: 1 robot >= 100x, 22 robots >= 5x).
TARGET_REALTIME_FACTOR = {1: 100.0, 22: 5.0}
#: Robot types per team in connection order: keeps the composition rules of REFERENCE §2.5 for 11.
TEAM_TYPES = (0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 0)
# Amplitude [rad/s] of each effector's velocity wave: head and arms move, legs only sway.
_AMPLITUDE = {"he1": 1.0, "he2": 0.3, "lae1": 0.8, "rae1": 0.8, "lae2": 0.3, "rae2": 0.3, "lae3": 0.5,
              "rae3": 0.5, "lae4": 0.4, "rae4": 0.4}
_LEG_AMPLITUDE = 0.02
# The whole command as one printf template (the same bytes as writing each "(name %.4f)" on its own).
_COMMAND = joint_velocity_template(EFFECTOR_NAMES) + b"(syn)"
_AMPLITUDES = [_AMPLITUDE.get(name, _LEG_AMPLITUDE) for name in EFFECTOR_NAMES]


class WaveAgent:
    """A benchmark agent: scene, init, then 22 joint waves per cycle; parses every sense message.

    ``parse=False`` makes an agent that only counts its messages, to show the simulator's own cost (a figure
    to read beside the real one, never instead of it).
    """

    def __init__(self, team: str, robot_type: int, phase: float, parse: bool = True) -> None:
        self.team = team
        self.robot_type = robot_type
        self.phase = phase
        self.parse = parse
        self.cycles = 0
        self.parsed_joints = 0

    def connect_message(self) -> bytes:
        return format_actions([Scene("rsg/agent/nao/nao_hetero.rsg", self.robot_type)])

    def step(self, sense: bytes) -> bytes:
        if self.parse:
            self.parsed_joints += len(parse_sense(sense).joints)
        self.cycles += 1
        if self.cycles == 1:
            return format_actions([Init(0, self.team)]) + b"(syn)"
        angle = 3.0 * (self.cycles * CYCLE_S) + self.phase
        return _COMMAND % tuple([amplitude * math.sin(angle + i) for i, amplitude in enumerate(_AMPLITUDES)])


@dataclass(frozen=True)
class BenchResult:
    """Figures of one run: simulated and wall seconds of the timed cycles, their ratio, the ratio for the time
    inside ``mujoco.mj_step`` alone, extra motor-bound physics solves, robots lying at the end, and whether
    the agents parsed their sense messages (False only for the simulator-alone figure)."""

    robots: int
    cycles: int
    sim_seconds: float
    wall_seconds: float
    realtime_factor: float
    raw_mujoco_realtime_factor: float
    physics_re_solves: int
    fallen: int
    agents_parse: bool = True

    def as_dict(self) -> dict[str, float | int]:
        return dict(self.__dict__)


def run(robots: int = 22, cycles: int = 500, warmup_cycles: int = 50, seed: int = 0,
        parse: bool = True) -> BenchResult:
    """Connect ``robots`` agents (two teams), let them settle, then time ``cycles`` cycles.

    raw_mujoco_realtime_factor counts only the time inside ``mujoco.mj_step`` in the timed cycles; with
    ``parse=False`` the agents skip parsing (the simulator's own speed, labelled by ``agents_parse``).
    """
    engine = SimEngine(seed=seed)
    host = InProcessHost(engine)
    for i in range(robots):
        team, index = ("Left", i // 2) if i % 2 == 0 else ("Right", i // 2)
        host.add(WaveAgent(team, TEAM_TYPES[index % len(TEAM_TYPES)], phase=0.7 * i, parse=parse))
    host.run(warmup_cycles)
    world = engine.world
    world.mujoco_wall_s = 0.0
    re_solves = world.motors.re_solves
    start = time.perf_counter()
    host.run(cycles)
    wall = time.perf_counter() - start
    sim_seconds = cycles * world.params.cycle_s
    fallen = sum(1 for r in world.robots() if r.torso_pos_m[2] < 0.25)
    return BenchResult(robots, cycles, sim_seconds, wall, sim_seconds / wall,
                       sim_seconds / max(world.mujoco_wall_s, 1e-9), world.motors.re_solves - re_solves, fallen,
                       parse)


#: Issue 15 item 6 ("Speed"): an 11 v 11 match of our full agents on 2 cores, and the engine alone for 1 robot.
TARGET_MATCH_RATIO = 1.5
TARGET_ENGINE_RATIO = 100.0


@dataclass(frozen=True)
class MatchSpeed:
    """Figures of one timed match: ``ratio`` = cycles x 20 ms / wall s (all simulated time, the kick-off waits
    too), ``game_ratio`` = game seconds / wall s (the game clock stops before each kick-off); CPU seconds of
    the engine's process and of the agent workers (0 in-process), so that a figure measured beside other
    work on the same cores can be read: the wall time of a loaded machine is not the code's."""

    players_per_team: int
    agent_processes: int
    cycles: int
    game_seconds: float
    wall_seconds: float
    ratio: float
    game_ratio: float
    engine_process_cpu_s: float
    worker_cpu_s: float
    score: str
    agent_errors: int

    def as_dict(self) -> dict[str, float | int | str]:
        return dict(self.__dict__)


def match_speed(make_agent: Any, players_per_team: int = 11, duration_s: float = 20.0, agent_processes: int = 2,
                seed: int = 0) -> MatchSpeed:
    """Time one match of ``make_agent``'s agents (`sim.match.run_match`, no log), agents built included."""
    import resource

    from sim.match import MatchConfig, run_match

    def cpu(who: int) -> float:
        usage = resource.getrusage(who)
        return usage.ru_utime + usage.ru_stime

    own, children = cpu(resource.RUSAGE_SELF), cpu(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = run_match(MatchConfig(players_per_team=players_per_team, duration_s=duration_s, seed=seed), make_agent,
                       agent_processes=agent_processes)
    wall = time.perf_counter() - start
    return MatchSpeed(players_per_team, agent_processes, result.cycles, result.game_time_s, round(wall, 3),
                      round(result.cycles * CYCLE_S / wall, 3), round(result.game_time_s / wall, 3),
                      round(cpu(resource.RUSAGE_SELF) - own, 2), round(cpu(resource.RUSAGE_CHILDREN) - children, 2),
                      f"{result.score_left}:{result.score_right}", result.agent_errors)
