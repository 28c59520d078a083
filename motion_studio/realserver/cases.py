"""The skill cases measured on both servers: where the robot stands, what it plays, the trainer commands that
put it (and the ball) there, and the scripted falls before a stand-up.

Timeline of every case on both servers: CONNECT_CYCLES (scene, init, the agent's own beam), the trainer
commands (move with no beam noise, ball, PlayOn), ``settle_cycles`` standing still (the drop from z = 0.4
settles), then the skill for the case's cycles. A case with ``fall`` first plays FALL_SCRIPT (raw joint
velocities) for FALL_SCRIPT_CYCLES cycles, then the skill.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields, replace
from pathlib import Path

from agent.motion import MotionController, MotionLibrary, MotionRequest, default_library, load_dynamic_params
from agent.protocol.effectors import Action, JointVelocity
from agent.skills.base import PlayMotion, Skill
from agent.skills.behavior import SkillBehavior
from agent.skills.dribble import Dribble, DribbleConfig
from agent.skills.kick import KickToward
from agent.skills.standup import StandUp
from agent.skills.turn import TurnBy
from agent.skills.walk_ball import WalkToBall
from agent.world_model import WorldModel
from motion_studio.realserver.git_export import export_motions, short_revision
from agent.protocol.constants import CYCLE_S, HALF_LENGTH_M
from motion_studio.skill_bench import dribble as dribble_bench

#: Cycles before the move (scene, init, the agent's own beam), as motion_studio.scenarios.CONNECT_CYCLES.
CONNECT_CYCLES = 6
#: Cycles standing still after the move before the skill starts (the drop from z = 0.4 settles).
SETTLE_CYCLES = 40
TEAM, UNUM = "Check", 1


# ---- cases ---------------------------------------------------------------------------------------------
class SkillSequence(Skill):
    """Skills one after the other; each for a number of cycles (None: until done)."""

    def __init__(self, *parts: tuple[Skill | None, int | None]) -> None:
        super().__init__()
        self.parts = parts
        self.name = " then ".join(p.name if p else "idle" for p, _ in parts)
        self.reset()

    def reset(self) -> None:
        super().reset()
        self._index, self._cycles = 0, 0
        for skill, _ in self.parts:
            if skill is not None:
                skill.reset()

    @property
    def current(self) -> Skill | None:
        """The part being played (None: an idle part, or all done)."""
        return self.parts[self._index][0] if self._index < len(self.parts) else None

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        while self._index < len(self.parts):
            skill, cycles = self.parts[self._index]
            finished = (cycles is not None and self._cycles >= cycles) or (
                cycles is None and skill is not None and skill.done)
            if not finished:
                self._cycles += 1
                return skill.step(world, motion) if skill is not None else MotionRequest(None)
            self._index, self._cycles = self._index + 1, 0
        self.done = True
        return MotionRequest(None)


@dataclass(frozen=True)
class Case:
    """One measured run: a skill from a standstill at a spot, for a number of cycles."""

    name: str
    make_skill: Callable[[], Skill | None]
    cycles: int
    position_m: tuple[float, float] = (-8.0, 0.0)
    heading_deg: float = 0.0
    ball_m: tuple[float, float] | None = (0.0, 8.0)
    """Where the ball lies (out of the way unless the case kicks it)."""
    fall: str | None = None
    """"back"/"front": the skill starts with a scripted fall (raw joint velocities, FALL_SCRIPT)."""
    recover_falls: bool = False
    walk_cycles: int | None = None
    """For a walk: the cycles it is requested (the rest is its stop)."""
    motion: str | None = None
    """The motion the case needs (cases whose motion the library lacks are skipped)."""
    kick: bool = False
    """The ball goes where the motion's constants ``ball_forward_m``/``ball_left_m`` want it (robot frame, walk
    stance; the stand before the kick moves the torso STAND_SHIFT_M forward)."""
    ball_beyond_m: float = 0.0
    """For a kick: the ball this much farther along the kick line than the motion's spot [m]."""
    settle_cycles: int = SETTLE_CYCLES
    """Cycles standing still between the move and the skill."""
    start: int = 0
    """Which lying start of a stand-up case (0: the case as shipped; see :func:`vary_fall`)."""
    fall_speed_scale: float = 1.0
    """Factor on every joint velocity of the fall script."""
    fall_stop_shift_cycles: int = 0
    """Cycles added to the fall script's stop step (its last step)."""
    robot_type: int = 0
    """The robot type (0-4) that plays the case, with that type's motions (``--type`` of ``motion-studio real
    skills``)."""
    dribble: tuple[float, float] | None = None
    """For a dribble: (direction from the ball's start to the target [deg], the ball's way measured along it [m])
    (``motion_studio.skill_bench.dribble.measure``, from the skill's start after STAND_CYCLES)."""

    @property
    def skill_cycle(self) -> int:
        """The first cycle of the skill phase (sense message index)."""
        return CONNECT_CYCLES + self.settle_cycles


def _walk(name: str, seconds: float = 10.0, stop_s: float = 2.0) -> Case:
    walk = int(seconds / CYCLE_S)
    return Case(name, lambda: SkillSequence((PlayMotion(name, repeat=True), walk), (None, None)),
                walk + int(stop_s / CYCLE_S), walk_cycles=walk)


CASES: dict[str, Case] = {
    "stand": Case("stand", lambda: PlayMotion("stand"), 200),
    "turn_left": Case("turn_left", lambda: PlayMotion("turn_left", repeat=True), 400),
    "turn_right": Case("turn_right", lambda: PlayMotion("turn_right", repeat=True), 400),
    "turn_by_90": Case("turn_by_90", lambda: TurnBy(90.0), 400),
    "walk_forward": _walk("walk_forward"),
    "walk_fast": _walk("walk_fast"),
    "walk_backward": replace(_walk("walk_backward"), position_m=(-3.0, 0.0)),
    "walk_left": replace(_walk("walk_left"), position_m=(-5.0, -4.0)),
    "walk_right": replace(_walk("walk_right"), position_m=(-5.0, 4.0)),
    "orbit_left": _walk("orbit_left", seconds=5.0),
    "orbit_right": _walk("orbit_right", seconds=5.0),
    "standup_back": Case("standup_back", StandUp, 500, fall="back"),
    "standup_front": Case("standup_front", StandUp, 500, fall="front"),
    "standup_side": Case("standup_side", StandUp, 500, fall="side", motion="roll_to_back"),
}
#: Torso moved forward by the stand motion from the zero pose [m] (measured: real 0.032, ours 0.033).
STAND_SHIFT_M = 0.032
STAND_CYCLES = 60
#: Cycles of the dribble_push case after the stand (8 s: the first touches and the ball's roll).
DRIBBLE_PUSH_CYCLES = 400


def _kick(name: str) -> Case:
    return Case(name, lambda: SkillSequence((PlayMotion("stand"), STAND_CYCLES), (PlayMotion(name), None),
                                            (None, None)), STAND_CYCLES + 300, motion=name, kick=True)


for _name in ("kick", "kick_left", "kick_strong", "kick_strong_left"):
    CASES[_name] = _kick(_name)
#: The right kick with the ball 8 mm beyond its spot: the real server kicks it as far as from the spot (4.01 m,
#: ``python -m motion_studio.realserver.kick_check kick --offsets-cm=0,0.5,0.8,1,1.5``, 2026-11-27), ours 1.79 m
#: (the foot meets the ball with its sole: the contact normal points down; see tests/sim/test_real_skill_traces.py).
CASES["kick_beyond_8mm"] = replace(_kick("kick"), name="kick_beyond_8mm", ball_beyond_m=0.008)
#: Requests of the distance-controlled kick cases kick_<d>m [m] (the shipped kick-distance table's range).
CONTROLLED_KICK_M = (1, 2, 3, 4)


def _controlled_kick(distance_m: int) -> Case:
    """The right kick from its spot asked for ``distance_m`` (``MotionRequest.distance_m``, the controller's
    kick-distance table)."""
    name = f"kick_{distance_m}m"
    return Case(name, lambda: SkillSequence((PlayMotion("stand"), STAND_CYCLES),
                                            (PlayMotion("kick", distance_m=float(distance_m)), None), (None, None)),
                STAND_CYCLES + 300, motion="kick", kick=True)


for _distance in CONTROLLED_KICK_M:
    CASES[f"kick_{_distance}m"] = _controlled_kick(_distance)
#: Distances of the kick line-up cases kick_lineup_<d>cm, robot torso to ball before the stand [cm]: the kick-off
#: spot (``agent.formation.KICK_OFF_SPOT_M``) puts the taker 0.5 m behind the ball and the beam adds +-5 cm.
KICK_LINEUP_CM = (45, 50, 55)


def _kick_lineup(distance_cm: int) -> Case:
    """The kick skill's line-up and kick toward the opponent goal (``KickToward``, as a set-piece taker starts it)
    from ``distance_cm`` straight behind the ball, aimed at the opponent goal's centre: on the real server its kick
    grazed the ball from 45 and 55 cm (9 of 18 starts of a grid with headings -8/0/+8 deg) until the loose window
    ended at 4.5 cm."""
    def skill() -> Skill:
        return SkillSequence((PlayMotion("stand"), STAND_CYCLES), (KickToward(HALF_LENGTH_M, 0.0), None), (None, None))

    return Case(f"kick_lineup_{distance_cm}cm", skill, STAND_CYCLES + 900, ball_m=(-8.0 + distance_cm / 100.0, 0.0), motion="kick")


for _distance in KICK_LINEUP_CM:
    CASES[f"kick_lineup_{_distance}cm"] = _kick_lineup(_distance)


@dataclass(frozen=True)
class DribbleSkill:
    """A dribble case's skill: the stand (looking down at the ball) for STAND_CYCLES, then ``Dribble`` toward
    ``target_m`` with ``config`` (``with_dribble_config`` changes it, ``motion-studio real skills --dribble``)."""

    target_m: tuple[float, float]
    config: DribbleConfig = DribbleConfig()

    def __call__(self) -> Skill:
        look_down = dribble_bench.LOOK_DOWN_DEG
        return SkillSequence((PlayMotion("stand", repeat=True, head_deg=look_down), STAND_CYCLES),
                             (Dribble(*self.target_m, self.config), None))


def _dribble(name: str, position_m: tuple[float, float], direction_deg: float, way_m: float,
             target_m: float) -> Case:
    """The benchmark's dribble (``motion_studio.skill_bench.dribble``): the robot facing +x in the walk stance,
    the ball BALL_AHEAD_M in front of its torso, the target ``target_m`` from the ball along ``direction_deg``."""
    ball = (position_m[0] + dribble_bench.BALL_AHEAD_M, position_m[1])
    direction = math.radians(direction_deg)
    target = (ball[0] + target_m * math.cos(direction), ball[1] + target_m * math.sin(direction))
    cycles = STAND_CYCLES + int(dribble_bench.LIMIT_S / CYCLE_S)
    return Case(name, DribbleSkill(target), cycles, position_m=position_m, ball_m=ball, dribble=(direction_deg, way_m))


def parse_dribble_settings(settings: list[str]) -> dict[str, float]:
    """``NAME=VALUE`` words (``DribbleConfig`` fields that hold one number) as a dict of overrides.

    Raises:
        ValueError: a word without ``=``, an unknown or non-numeric field, or a value that is no number (the
            message names the word and lists the fields).
    """
    default = DribbleConfig()
    numeric = sorted(f.name for f in fields(DribbleConfig) if isinstance(getattr(default, f.name), float))
    overrides: dict[str, float] = {}
    for word in settings:
        name, sep, value = word.partition("=")
        name = name.strip()
        if not sep or name not in numeric:
            raise ValueError(f"{word!r}: expected NAME=VALUE with NAME one of {', '.join(numeric)}")
        try:
            number = float(value)
        except ValueError:
            number = math.nan
        if not math.isfinite(number):
            raise ValueError(f"{word!r}: {value.strip()!r} is not a number")
        overrides[name] = number
    return overrides


def changed_dribble_settings(config: DribbleConfig) -> dict[str, object]:
    """The fields of ``config`` that differ from the shipped ``DribbleConfig`` (what ``--dribble`` changed)."""
    default = DribbleConfig()
    return {f.name: getattr(config, f.name) for f in fields(DribbleConfig)
            if getattr(config, f.name) != getattr(default, f.name)}


def with_dribble_config(case: Case, overrides: Mapping[str, float]) -> Case:
    """``case`` with its dribble's ``DribbleConfig`` fields changed (other cases as they are): to try a dribble
    setting on both servers before it goes into the code."""
    if not overrides or not isinstance(case.make_skill, DribbleSkill):
        return case
    skill = case.make_skill
    return replace(case, make_skill=replace(skill, config=replace(skill.config, **overrides)))


CASES["dribble"] = _dribble("dribble", (-8.0, 0.0), 0.0, dribble_bench.STRAIGHT_M, dribble_bench.STRAIGHT_TARGET_M)
#: The dribble's first touches only (8 s): recorded with ``--replay-sim`` (our agent's commands on both servers) it
#: compares how far a walking foot pushes the ball, physics alone (``motion-studio calibrate``).
CASES["dribble_push"] = replace(CASES["dribble"], name="dribble_push", cycles=STAND_CYCLES + DRIBBLE_PUSH_CYCLES)
CASES["dribble_turn_left"] = _dribble("dribble_turn_left", (-6.0, -4.0), 90.0, dribble_bench.TURN_M,
                                      dribble_bench.TURN_TARGET_M)
CASES["dribble_turn_right"] = _dribble("dribble_turn_right", (-6.0, 4.0), -90.0, dribble_bench.TURN_M,
                                       dribble_bench.TURN_TARGET_M)
#: WalkToBall with the ball beside the right foot ((0.12, -0.16) m from the torso before the stand, which moves the
#: torso STAND_SHIFT_M forward), after a stand looking down at it: the line-up must not push the ball
#: (tests/scenarios/test_walk_transitions.py; ``motion-studio real skills walk_to_ball_beside``).
WALK_TO_BALL_BESIDE_M = (0.12, -0.16)
CASES["walk_to_ball_beside"] = Case(
    "walk_to_ball_beside",
    lambda: SkillSequence((PlayMotion("stand", repeat=True, head_deg=(0.0, -45.0)), STAND_CYCLES), (WalkToBall(), None),
                          (None, None)),
    STAND_CYCLES + 600, ball_m=(-8.0 + WALK_TO_BALL_BESIDE_M[0], WALK_TO_BALL_BESIDE_M[1]))
for _case in list(CASES.values()):
    if _case.motion is None and _case.name in ("stand", "turn_left", "turn_right", "walk_forward", "walk_fast",
                                               "walk_backward", "walk_left", "walk_right", "orbit_left",
                                               "orbit_right"):
        CASES[_case.name] = replace(_case, motion=_case.name)
CASES["standup_back"] = replace(CASES["standup_back"], motion="standup_back")
CASES["standup_front"] = replace(CASES["standup_front"], motion="standup_front")

#: Raw joint velocities [rad/s] by cycle of the skill phase that knock the robot over: both hips at 3 rad/s (as
#: tests/sim/fixtures/real_0.7.3_fall), hips at -1.5 and ankles at -3 rad/s. Measured on both servers, the first
#: tips the robot forward onto its front (the agent then plays standup_front) and the second onto its back
#: (standup_back plays), although they are the cases standup_back and standup_front (names kept: the fixtures
#: carry them; transfer.LIES_ON). The third, hip and ankle rolls at 3 rad/s, tips it onto its right side (the agent
#: rolls it onto its back with roll_to_back, then plays standup_back): 10 of 10 lying starts fell on the real server
#: (the hip rolls alone tipped 5 of 10 there).
FALL_SCRIPT = {
    "back": {0: {"lle3": 3.0, "rle3": 3.0}, 40: {"lle3": 0.0, "rle3": 0.0}},
    "front": {0: {"lle3": -1.5, "rle3": -1.5, "lle5": -3.0, "rle5": -3.0},
              30: {"lle3": 0.0, "rle3": 0.0, "lle5": 0.0, "rle5": 0.0}},
    "side": {0: {"lle2": 3.0, "rle2": 3.0, "lle6": 3.0, "rle6": 3.0},
             30: {"lle2": 0.0, "rle2": 0.0, "lle6": 0.0, "rle6": 0.0}},
}
FALL_SCRIPT_CYCLES = 100


def fall_steps(case: Case) -> dict[int, dict[str, float]]:
    """The case's fall script: FALL_SCRIPT[case.fall] with its velocities scaled and its stop step shifted
    (identical to FALL_SCRIPT for a shipped case)."""
    if case.fall is None:
        return {}
    script = FALL_SCRIPT[case.fall]
    stop = max(script)
    steps: dict[int, dict[str, float]] = {}
    for cycle, velocities in script.items():
        at = cycle + case.fall_stop_shift_cycles if cycle == stop else cycle
        steps[at] = {name: value * case.fall_speed_scale for name, value in velocities.items()}
    return steps


class FallThenSkill:
    """A ``Behavior``: from ``start_cycle`` on, FALL_SCRIPT_CYCLES cycles of the scripted fall, then ``inner``."""

    def __init__(self, inner: SkillBehavior, case: Case) -> None:
        self.inner = inner
        self.side = case.fall
        self.steps = fall_steps(case)
        self.cycle = -1
        self.start_cycle: int | None = None

    def __call__(self, world: WorldModel) -> list[Action]:
        self.cycle += 1
        if self.side is None or self.start_cycle is None or self.cycle - self.start_cycle >= FALL_SCRIPT_CYCLES:
            return self.inner(world)
        step = self.steps.get(self.cycle - self.start_cycle, {})
        return [JointVelocity(name, value) for name, value in step.items()]


# ---- motions -------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MotionSource:
    """Where the played motions come from: ``folder`` None = the working tree; else a folder with ``files/`` and
    ``params/dynamic_elements.toml`` exported from git ``revision``."""

    folder: Path | None = None
    revision: str = "worktree"

    def library(self, robot_type: int = 0, include_withheld: bool = False) -> MotionLibrary:
        """The motions a robot of ``robot_type`` plays (its own folder's files over the shared ones; with
        ``include_withheld`` also the shared ones it does not play, to measure them)."""
        return default_library(robot_type, self.folder / "files" if self.folder is not None else None,
                               include_withheld=include_withheld)

    def unplayed(self, case: Case, available: MotionLibrary) -> str | None:
        """Why a robot of ``case.robot_type`` does not play the case's motion (``available``: that type's library,
        ``library(case.robot_type)``, loaded once by the caller), or None when it does or the case has none."""
        if case.motion is None or case.motion in available:
            return None
        if case.motion in self.library(case.robot_type, include_withheld=True):
            return f"robot type {case.robot_type} does not play {case.motion!r}: motions/files/robot_types.toml"
        return f"no motion {case.motion!r} at {self.revision}"

    def controller(self, robot_type: int = 0) -> MotionController | None:
        """A motion controller on these motions (None: SkillBehavior's default, the working tree's)."""
        if self.folder is None:
            return None
        return MotionController(self.library(robot_type),
                                load_dynamic_params(self.folder / "params" / "dynamic_elements.toml"), robot_type)


def motion_source(revision: str, scratch: Path) -> MotionSource:
    """The motions of git ``revision`` exported under ``scratch`` ('worktree': the files as they are now).

    Raises:
        subprocess.CalledProcessError: an unknown revision.
    """
    if revision == "worktree":
        return MotionSource()
    short = short_revision(revision)
    return MotionSource(export_motions(short, scratch), short)


def behavior(case: Case, motions: MotionSource) -> tuple[SkillBehavior, FallThenSkill]:
    """The agent's behaviour for a case: the skill behaviour (skill set at the skill cycle) behind the fall."""
    inner = SkillBehavior(motions.controller(case.robot_type), None, case.robot_type, case.recover_falls)
    return inner, FallThenSkill(inner, case)


# ---- trainer commands ----------------------------------------------------------------------------------
def kick_ball_m(case: Case, motions: MotionSource) -> tuple[float, float]:
    """Field position of the ball for a kick case, from the motion's constants (robot frame)."""
    constants = motions.library(case.robot_type).get(case.motion).constants
    forward = float(constants["ball_forward_m"]) + STAND_SHIFT_M + case.ball_beyond_m
    left = float(constants["ball_left_m"])
    c, s = math.cos(math.radians(case.heading_deg)), math.sin(math.radians(case.heading_deg))
    return case.position_m[0] + c * forward - s * left, case.position_m[1] + s * forward + c * left


def trainer_commands(case: Case, motions: MotionSource) -> list[str]:
    """What the monitor sends at the move cycle (both servers): the move (trainer ``move`` angle = heading -
    90 deg for the left team, as beam adds -90), the ball, PlayOn."""
    x, y = case.position_m
    commands = [f"(agent (unum {UNUM})(team Left)(move {x} {y} 0.4 {case.heading_deg - 90.0}))"]
    ball = kick_ball_m(case, motions) if case.kick else case.ball_m
    if ball is not None:
        commands.append(f"(ball (pos {ball[0]:.4f} {ball[1]:.4f} 0.042)(vel 0 0 0))")
    commands.append("(playMode PlayOn)")
    return commands
