"""Monitor output in the SimSpark format (REFERENCE §5.1, §5.3): messages, streams, the log file writer.

A monitor message is three S-expressions: the game state list, ``(RSG 0 1)`` or ``(RDS 0 1)``, and the scene
graph (sim.monitor_scene). A `SceneSnapshot` freezes one moment (game state from the referee, ball and body
transforms from the world); a `MonitorStream` turns snapshots into messages for one consumer, tracking
what that consumer has already been sent (team names, scores, play mode, fouls, transforms), as the
server's monitor items do. `MonitorLogWriter` writes a stream to a file, one message per line without the
length prefix; `WorldMonitorFeed` serves the TCP monitor port.
"""

from __future__ import annotations

import gzip

import logging
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, TextIO

from sim.monitor_scene import (IDENTITY, Decimals, Matrix, Node, SceneWriter, ball_node, number, pose_matrix, robot_node,
                               static_scene, translation)
from sim.rules.params import PLAY_MODES, RefereeConfig, default_config
from sim.rules.self_collision import BodyPoseArrays
from agent.protocol.constants import CYCLE_S
from sim.errors import MonitorLogError

logger = logging.getLogger(__name__)

# REFERENCE §5.3: a log line every monitor step, a full state every 3 s and on every scene change.
DEFAULT_FULL_STATE_EVERY_S = 3.0
# The server's $monitorLoggerStep (0.2 s), which RoboViz's log player also assumes per frame. Measured
# (benchmarks/bench_monitor_log.py): a 10-minute 11 v 11 match 10.5 MB gzipped (93 MB plain), 3 v 3 3.3 MB;
# for 60 s of 11 v 11, a line every 0.04 s would be 5.2 MB (x10 for a match), the server's own number
# spelling at 0.2 s 3.0 MB.
DEFAULT_LOG_STEP_CYCLES = 10
DEFAULT_LOG_DECIMALS: Decimals = (2, 3)


@dataclass(frozen=True)
class GameView:
    """The game state a monitor shows. time_s: game time; half 1/2; play_mode_index per §4.2; fouls: every
    foul so far as (index, type, team 1|2, unum); pass_wait_*: seconds before that team may score after a
    pass mode, or None."""

    time_s: float = 0.0
    half: int = 1
    score_left: int = 0
    score_right: int = 0
    play_mode_index: int = 0
    team_left: str | None = None
    team_right: str | None = None
    fouls: tuple[tuple[int, int, int, int], ...] = ()
    pass_wait_left: float | None = None
    pass_wait_right: float | None = None


@dataclass(frozen=True)
class RobotView:
    """One robot for the monitor: side "left"/"right" (None before init), uniform number, robot type and the
    world transform (column-major 4x4) of each SimSpark body by name."""

    side: str | None
    unum: int
    robot_type: int
    bodies: Mapping[str, Matrix] = field(default_factory=dict)


@dataclass(frozen=True)
class SceneSnapshot:
    """One moment of the match: game state, ball transform, robots in connection order."""

    game: GameView
    ball: Matrix = translation(0.0, 0.0, 0.042)
    robots: tuple[RobotView, ...] = ()

    def structure(self) -> tuple[tuple[str | None, int, int], ...]:
        """What changes the scene-graph shape: a different value means a full state is due."""
        return tuple((r.side, r.unum, r.robot_type) for r in self.robots)


def environment_predicates(config: RefereeConfig) -> str:
    """The constant part of a full game-state list (server order; GameStateItem::GetInitialPredicates)."""
    c = config
    values = (("FieldLength", c.field_length_m), ("FieldWidth", c.field_width_m), ("FieldHeight", c.field_height_m),
              ("GoalWidth", c.goal_width_m), ("GoalDepth", c.goal_depth_m), ("GoalHeight", c.goal_height_m),
              ("BorderSize", c.border_size_m), ("FreeKickDistance", c.free_kick_distance_m),
              ("WaitBeforeKickOff", c.wait_before_kick_off_s), ("AgentRadius", c.agent_radius_m),
              ("BallRadius", c.ball_radius_m), ("BallMass", c.ball_mass_kg),
              ("RuleGoalPauseTime", c.goal_pause_time_s), ("RuleKickInPauseTime", c.kick_in_pause_time_s),
              ("RuleHalfTime", c.half_time_s), ("PassModeMinOppBallDist", c.pass_mode_min_opp_ball_dist_m),
              ("PassModeDuration", c.pass_mode_duration_s))
    return "".join(f"({name} {number(value)})" for name, value in values) + \
        "(play_modes " + " ".join(PLAY_MODES) + ")"


class MonitorStream:
    """Messages for one monitor consumer; full states reset what it is known to have.

    Args:
        config: rule parameters for the environment constants of full states.
        decimals: places of transform rotation and translation numbers (None: the server's spelling; see
            `SceneWriter`).
    """

    def __init__(self, config: RefereeConfig | None = None, decimals: Decimals = None) -> None:
        self.config = config or default_config()
        self._environment = environment_predicates(self.config)
        self._static = static_scene()
        self._scene = SceneWriter(decimals)
        self._structure: object = None
        self._sent_left = self._sent_right = False
        self._half: int | None = None
        self._score_left: int | None = None
        self._score_right: int | None = None
        self._play_mode: int | None = None
        self._last_foul = 0
        self.last_was_full = False

    def message(self, snapshot: SceneSnapshot, full: bool = False) -> str:
        """The next message; a full state when asked, at the first call and when the robots changed."""
        structure = snapshot.structure()
        self.last_was_full = full or structure != self._structure
        if self.last_was_full:
            self._structure = structure
            return self._full(snapshot)
        return "(" + self._game(snapshot.game) + ")(RDS 0 1)" + self._scene.diff(self._nodes(snapshot))

    def _full(self, snapshot: SceneSnapshot) -> str:
        self._sent_left = self._sent_right = False
        self._half = self._score_left = self._score_right = self._play_mode = None
        return ("(" + self._environment + self._game(snapshot.game) + ")(RSG 0 1)"
                + self._scene.full(self._nodes(snapshot)))

    def _nodes(self, snapshot: SceneSnapshot) -> list[Node]:
        nodes = list(self._static)
        nodes.append(ball_node(snapshot.ball))
        nodes.extend(robot_node(r.side, r.unum, r.robot_type, r.bodies, *_type4_scales(r.robot_type))
                     for r in snapshot.robots)
        return nodes

    def _game(self, game: GameView) -> str:
        """Time always; team names once; half, scores and play mode when changed; pass waits; new fouls."""
        parts = [f"(time {number(game.time_s)})"]
        if not self._sent_left and game.team_left:
            parts.append(f"(team_left {game.team_left})")
            self._sent_left = True
        if not self._sent_right and game.team_right:
            parts.append(f"(team_right {game.team_right})")
            self._sent_right = True
        if game.half != self._half:
            self._half = game.half
            parts.append(f"(half {game.half})")
        if game.score_left != self._score_left:
            self._score_left = game.score_left
            parts.append(f"(score_left {game.score_left})")
        if game.score_right != self._score_right:
            self._score_right = game.score_right
            parts.append(f"(score_right {game.score_right})")
        if game.play_mode_index != self._play_mode:
            self._play_mode = game.play_mode_index
            parts.append(f"(play_mode {game.play_mode_index})")
        if game.pass_wait_left is not None:
            parts.append(f"(pass_mode_score_wait_left {number(game.pass_wait_left)})")
        if game.pass_wait_right is not None:
            parts.append(f"(pass_mode_score_wait_right {number(game.pass_wait_right)})")
        for index, foul_type, team, unum in game.fouls:
            if index > self._last_foul:
                parts.append(f"(foul {index} {foul_type} {team} {unum})")
                self._last_foul = index
        return "".join(parts)


def _type4_scales(robot_type: int) -> tuple[float, tuple[float, float, float] | None]:
    """Foot and toe mesh scales of naolegtoe.rsg for robot type 4 (foot length minus the toe)."""
    if robot_type != 4:
        return (1.0, None)
    from kinematics.spec import TOE_FOOT_SIZE_M, TOE_SIZE_M
    foot_y, toe_y, toe_z = TOE_FOOT_SIZE_M[1], TOE_SIZE_M[1], TOE_SIZE_M[2]
    return (foot_y / 0.16, (0.08, 0.08 * toe_y / foot_y, 0.08 * toe_z / TOE_FOOT_SIZE_M[2]))


# ---- snapshots from the running simulation -----------------------------------------------------------
class RefereeLike(Protocol):
    play_mode_index: int
    game_time_s: float
    half: int
    score_left: int
    score_right: int
    team_names: dict[str, str | None]
    fouls: list  # sim.referee.Foul

    def pass_mode_score_wait_s(self, side: str) -> float | None: ...


class SceneSource(Protocol):
    """What the monitor needs from the world besides the referee (sim.world.World provides it)."""

    def ball_pose(self) -> tuple[tuple[float, float, float], tuple[float, ...]]:
        """Ball centre [m] and row-major 3x3 rotation."""

    def robot_body_poses(self) -> Sequence[tuple[str | None, int, int, Mapping[str, tuple[tuple[float, float, float],
                                                                                         tuple[float, ...]]]]]:
        """Per robot in connection order: (side or None, unum, robot type, {SimSpark body name: (centre [m],
        row-major 3x3 rotation)})."""


def game_view(referee: RefereeLike) -> GameView:
    """The referee's state as a monitor shows it."""
    return GameView(time_s=referee.game_time_s, half=referee.half, score_left=referee.score_left,
                    score_right=referee.score_right, play_mode_index=referee.play_mode_index,
                    team_left=referee.team_names.get("left"), team_right=referee.team_names.get("right"),
                    fouls=tuple(f.monitor_tuple() for f in referee.fouls),
                    pass_wait_left=referee.pass_mode_score_wait_s("left"),
                    pass_wait_right=referee.pass_mode_score_wait_s("right"))


def snapshot_of(world: SceneSource, referee: RefereeLike) -> SceneSnapshot:
    """Freeze the world and the referee into a `SceneSnapshot`."""
    position, rotation = world.ball_pose()
    robots = tuple(RobotView(side, unum, robot_type,
                             {name: pose_matrix(pos, rot) for name, (pos, rot) in bodies.items()})
                   for side, unum, robot_type, bodies in world.robot_body_poses())
    return SceneSnapshot(game_view(referee), pose_matrix(position, rotation), robots)


class MujocoWorldScene:
    """`SceneSource` over sim.world.World, reading body poses from its compiled model and data.

    Used until the world offers ``ball_pose``/``robot_body_poses`` itself; body frames of the generated
    model are SimSpark's (body centre, axes x right / y forward / z up at zero pose), so ``xpos``/``xmat``
    are exactly the transforms the server sends.
    """

    def __init__(self, world: object) -> None:
        self.world = world
        self._model_id = 0
        self._ids: dict[int, dict[str, int]] = {}

    def ball_pose(self) -> tuple[tuple[float, float, float], tuple[float, ...]]:
        w = self.world
        body = w.ball_body  # type: ignore[attr-defined]
        return tuple(w.data.xpos[body]), tuple(w.data.xmat[body])  # type: ignore[attr-defined,return-value]

    def robot_body_poses(self) -> list[tuple[str | None, int, int, dict[str, tuple[tuple[float, float, float],
                                                                                tuple[float, ...]]]]]:
        w = self.world
        model, data = w.model, w.data  # type: ignore[attr-defined]
        if id(model) != self._model_id:  # robots joined or left: the model was recompiled
            self._model_id = id(model)
            self._ids.clear()
        out = []
        centres = w.body_centres() if hasattr(w, "body_centres") else data.xpos  # ODE's joint drift included
        for robot in w.by_key.values():  # type: ignore[attr-defined]
            if robot.key not in self._ids:
                self._ids[robot.key] = {b.name: model.body(robot.prefix + b.name).id for b in robot.spec.bodies}
            out.append((robot.side, robot.unum or 0, robot.robot_type,
                        BodyPoseArrays(self._ids[robot.key], centres, data.xmat)))
        return out


class WorldMonitorFeed:
    """The TCP server's monitor feed: one snapshot per monitor step, one stream per connection.

    Args:
        snapshot_fn: returns the current `SceneSnapshot` (e.g. ``lambda: snapshot_of(world, referee)``).
        config: rule parameters for the environment constants.
    """

    def __init__(self, snapshot_fn: Callable[[], SceneSnapshot], config: RefereeConfig | None = None) -> None:
        self.snapshot_fn = snapshot_fn
        self.config = config

    def snapshot(self) -> SceneSnapshot:
        return self.snapshot_fn()

    def new_stream(self) -> MonitorStream:
        return MonitorStream(self.config)


#: zlib level of ``.gz`` monitor logs. An 11 v 11 log line (40 kB, every 0.2 s) takes 5.1 ms at level 9 and 1.25 ms
#: at 6 (0.25 ms at 1), on the engine process's path every cycle waits for: level 9 cost about 3 % of a match's wall
#: time for a file 6 % smaller than level 6's (level 1: 46 % larger). Measured 2026-11-27 on a 60 s match's log.
LOG_GZIP_LEVEL = 6


def _open_log_for_writing(path: Path) -> TextIO:
    """A text stream for a log file; ``.gz`` compresses at ``LOG_GZIP_LEVEL``."""
    if path.suffix == ".gz":
        return gzip.open(path, "wt", compresslevel=LOG_GZIP_LEVEL, encoding="ascii",  # type: ignore[return-value]
                         newline="\n")
    return open(path, "w", encoding="ascii", newline="\n")


class MonitorLogWriter:
    """Writes a match log: one monitor message per line, no length prefix (REFERENCE §5.3).

    Call `on_cycle(cycle)` after every simulation cycle; a line is written every ``step_cycles`` cycles
    (default 10 = 0.2 s, the server's logger step; 2 = every monitor frame, 0.04 s), a full state at the
    first line, every ``full_state_every_s`` and whenever robots join or leave; lines in between are diffs
    (``(RDS 0 1)``, only the transforms that moved more than 0.005), as the server's own logs.

    Args:
        out: a path (opened for writing, closed by `close`) or an open text stream.
        snapshot_fn: returns the current snapshot.
        step_cycles: cycles between lines.
        full_state_every_s: seconds between periodic full states.
        config: rule parameters for the environment constants.
        decimals: places of transform rotation and translation numbers (None: the server's six significant
            digits). The default (2, 3) stays inside the 0.005 the server's own diffs allow and is what
            brings a 10-minute 11 v 11 log under 20 MB gzipped.
    """

    def __init__(self, out: str | Path | TextIO, snapshot_fn: Callable[[], SceneSnapshot],
                 step_cycles: int = DEFAULT_LOG_STEP_CYCLES, full_state_every_s: float = DEFAULT_FULL_STATE_EVERY_S,
                 config: RefereeConfig | None = None, decimals: Decimals = DEFAULT_LOG_DECIMALS) -> None:
        if step_cycles < 1:
            raise MonitorLogError(f"step_cycles must be >= 1, got {step_cycles}")
        self._owns = not hasattr(out, "write")
        self._out: TextIO = _open_log_for_writing(Path(out)) if self._owns else out  # type: ignore[arg-type]
        self.snapshot_fn = snapshot_fn
        self.step_cycles = step_cycles
        self.full_every_cycles = max(1, round(full_state_every_s / CYCLE_S))
        self.stream = MonitorStream(config, decimals)
        self.lines = 0
        self._last_full_cycle: int | None = None
        self._last_cycle: int | None = None
        self._written_cycle: int | None = None

    def on_cycle(self, cycle: int) -> None:
        """Write the line due at this cycle, if any."""
        self._last_cycle = cycle
        if self._last_full_cycle is not None and cycle % self.step_cycles != 0:
            return
        full = self._last_full_cycle is None or cycle - self._last_full_cycle >= self.full_every_cycles
        self.write(self.snapshot_fn(), full=full, cycle=cycle)

    def write(self, snapshot: SceneSnapshot, full: bool = False, cycle: int = 0) -> None:
        """Write one message line now."""
        text = self.stream.message(snapshot, full=full)
        if self.stream.last_was_full:
            self._last_full_cycle = cycle
        self._out.write(text + "\n")
        self.lines += 1
        self._written_cycle = cycle

    def close(self) -> None:
        """Write the last cycle's state unless its line is already there (with a line every 0.2 s the end of
        a match, its final score or a last play mode, would otherwise be lost), then close."""
        if self._last_cycle is not None and self._last_cycle != self._written_cycle:
            self.write(self.snapshot_fn(), cycle=self._last_cycle)
        self._out.flush()
        if self._owns:
            self._out.close()


__all__ = ["GameView", "IDENTITY", "MonitorLogWriter", "MonitorStream", "MujocoWorldScene", "RobotView", "SceneSnapshot",
           "WorldMonitorFeed", "environment_predicates", "game_view", "snapshot_of"]
