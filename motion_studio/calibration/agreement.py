"""How far a replay on our simulator is from the real recording: named measures, each scaled to an error.

Each measure compares one figure of the real run with ours (the distance walked, the turn, the torso height,
when the robot fell, how far the ball went, how the leg joints followed) and divides the difference by a
scale: the difference that matters for a skill (10 cm of a walk, 5 degrees of a turn, 1 cm of height, a
fall 10 cycles early). An error of 1 is "just noticeable for a skill"; errors are capped at `ERROR_CAP` so one
broken trace cannot hide the others. The score of a trace is the mean of its errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from agent.protocol.constants import CYCLE_S
from agent.protocol.perceptors import Sense
from agent.protocol.sense import parse_sense
from motion_studio.realserver.fixtures import Fixture
from motion_studio.realserver.measures import STOOD_HOLD_S, displacement_m, fallen, stood_index, turned_deg
from motion_studio.realserver.replay import ReplayStates
from motion_studio.scenarios import Truth

ERROR_CAP = 5.0
LEG_JOINTS = tuple(f"{side}lj{n}" for side in "lr" for n in range(1, 7))
#: Cycles of the skill phase over which leg joints are compared (open loop, errors add up after that).
JOINT_WINDOW_CYCLES = 150


@dataclass(frozen=True)
class Measure:
    """One compared figure: name, real value, our value, unit, and the error (difference / scale, capped)."""

    name: str
    real: float
    ours: float
    unit: str
    error: float


def _measure(name: str, real: float, ours: float, scale: float, unit: str) -> Measure:
    error = abs(ours - real) / scale if math.isfinite(ours) and math.isfinite(real) else ERROR_CAP
    return Measure(name, real, ours, unit, min(error, ERROR_CAP))


@dataclass
class Replay:
    """Both sides of one recorded session: the real recording and our replay of its commands."""

    fixture: Fixture
    states: ReplayStates
    _parsed: dict[tuple[str, int], Sense] = field(default_factory=dict, repr=False)

    @property
    def real(self) -> dict[int, Truth]:
        return self.fixture.truth

    @property
    def ours(self) -> dict[int, Truth]:
        return self.states.ours

    def sense(self, side: str, index: int) -> Sense:
        """Sense message ``index`` of ``side`` ("real" or "ours"), parsed once."""
        key = (side, index)
        if key not in self._parsed:
            messages = self.fixture.received if side == "real" else self.states.messages
            self._parsed[key] = parse_sense(messages[index])
        return self._parsed[key]


def _first_fall(poses: dict[int, Truth], cycles: list[int]) -> int | None:
    """Index in ``cycles`` of the first fallen pose, None if the robot stayed up."""
    return next((k for k, i in enumerate(cycles) if fallen(poses[i])), None)


@dataclass(frozen=True)
class Outcome:
    """How a skill trace ended for one robot (the transfer issue's "same fall/no-fall outcome")."""

    fell: bool
    """Fallen (`fallen`) at some cycle of the skill phase."""
    standing: bool
    """Standing at the end: `stood_index`'s window (the torso centre above 0.30 m for 1 s) is the last one."""


def _skill_cycles(replay: Replay) -> list[int]:
    """The skill phase's cycles that both sides have a pose for."""
    return [i for i in sorted(replay.real) if i >= replay.fixture.skill_cycle and i in replay.ours]


def outcomes(replay: Replay) -> tuple[Outcome, Outcome] | None:
    """The real robot's and ours' outcome of a skill trace; None for a scripted trace (no truth)."""
    cycles = _skill_cycles(replay)
    if len(cycles) < 2:
        return None
    last_second = max(0, len(cycles) - round(STOOD_HOLD_S / CYCLE_S))

    def outcome(poses: dict[int, Truth]) -> Outcome:
        return Outcome(_first_fall(poses, cycles) is not None,
                       stood_index([poses[i] for i in cycles], last_second) is not None)

    return outcome(replay.real), outcome(replay.ours)


def measures(replay: Replay) -> list[Measure]:
    """The measures that apply to ``replay``'s trace (skill traces by their truth, scripted ones by sensors)."""
    if replay.real:
        return _pose_measures(replay) + _joint_measures(replay, LEG_JOINTS, 2.0)
    return _joint_measures(replay, None, 1.0) + _force_measures(replay)


def _pose_measures(replay: Replay) -> list[Measure]:
    real, ours = replay.real, replay.ours
    cycles = _skill_cycles(replay)
    if len(cycles) < 2:
        return []
    out: list[Measure] = []
    real_move = displacement_m(real[cycles[0]], real[cycles[-1]])
    our_move = displacement_m(ours[cycles[0]], ours[cycles[-1]])
    walked = math.hypot(*real_move)
    out.append(Measure("displacement_m", walked, math.hypot(*our_move), "m",
                       min(math.dist(real_move, our_move) / (0.1 + 0.1 * walked), ERROR_CAP)))
    # A lying torso's heading is meaningless (its forward axis points up or down): turns count while both stand.
    falls = [k for k in (_first_fall(real, cycles), _first_fall(ours, cycles)) if k is not None]
    upright = cycles[:min(falls)] if falls else cycles
    if len(upright) > 1:
        real_turn = turned_deg([real[i] for i in upright])
        our_turn = turned_deg([ours[i] for i in upright])
        out.append(_measure("turn_deg", real_turn, our_turn, 5.0 + 0.05 * abs(real_turn), "deg"))
    heights = np.array([[real[i].torso_m[2], ours[i].torso_m[2]] for i in cycles])
    out.append(Measure("height_m", float(heights[:, 0].mean()), float(heights[:, 1].mean()), "m",
                       min(float(np.abs(heights[:, 0] - heights[:, 1]).mean()) / 0.01, ERROR_CAP)))
    real_fall, our_fall = _first_fall(real, cycles), _first_fall(ours, cycles)
    nan = float("nan")
    if (real_fall is None) != (our_fall is None):
        out.append(Measure("fall_cycle", nan if real_fall is None else real_fall,
                           nan if our_fall is None else our_fall, "cycle", 3.0))
    elif real_fall is not None and our_fall is not None:
        out.append(_measure("fall_cycle", real_fall, our_fall, 10.0, "cycle"))
        after = slice(real_fall, None)
        out.append(_measure("peak_height_after_fall_m", max(h for h in heights[after, 0]),
                            max(h for h in heights[after, 1]), 0.03, "m"))
        # the transfer issue's outcome: stood up (torso centre above 0.30 m for 1 s) after the fall, or not
        low = min(real_fall, our_fall)
        lying = next((k for k in range(low, len(cycles)) if heights[k].max() < 0.30), None)
        if lying is not None:
            real_stood = stood_index([real[i] for i in cycles], lying)
            our_stood = stood_index([ours[i] for i in cycles], lying)
            if (real_stood is None) != (our_stood is None):
                out.append(Measure("stood_up_cycle", nan if real_stood is None else real_stood,
                                   nan if our_stood is None else our_stood, "cycle", 3.0))
            elif real_stood is not None and our_stood is not None:
                out.append(_measure("stood_up_cycle", real_stood, our_stood, 15.0, "cycle"))  # 0.3 s
    ball_real = math.dist(real[cycles[0]].ball_m[:2], real[cycles[-1]].ball_m[:2])
    ball_ours = math.dist(ours[cycles[0]].ball_m[:2], ours[cycles[-1]].ball_m[:2])
    if max(ball_real, ball_ours) > 0.05:
        scale = 0.1 + 0.2 * ball_real
        out.append(_measure("ball_travel_m", ball_real, ball_ours, scale, "m"))
        # where it stopped, not only how far: a kick that flies 30 degrees off is not the real kick
        out.append(Measure("ball_end_apart_m", 0.0, math.dist(real[cycles[-1]].ball_m[:2], ours[cycles[-1]].ball_m[:2]),
                           "m", min(math.dist(real[cycles[-1]].ball_m[:2], ours[cycles[-1]].ball_m[:2]) / scale,
                                    ERROR_CAP)))
        # how deep the resting ball sits decides where the foot meets it (real: 2 mm into the ground)
        out.append(_measure("ball_rest_height_m", real[cycles[0]].ball_m[2], ours[cycles[0]].ball_m[2], 0.002, "m"))
    return out


def _joint_measures(replay: Replay, joints: tuple[str, ...] | None, scale_deg: float) -> list[Measure]:
    start = replay.fixture.skill_cycle
    stop = min(len(replay.fixture.received), len(replay.states.messages), start + JOINT_WINDOW_CYCLES)
    errors = []
    for i in range(start, stop):
        real, ours = replay.sense("real", i).joints, replay.sense("ours", i).joints
        names = joints or tuple(real)
        errors.extend(ours[n] - real[n] for n in names if n in ours and n in real)
    if not errors:
        return []
    rms = float(np.sqrt(np.mean(np.square(errors))))
    return [Measure("joint_rms_deg", 0.0, rms, "deg", min(rms / scale_deg, ERROR_CAP))]


def _force_measures(replay: Replay) -> list[Measure]:
    stop = min(len(replay.fixture.received), len(replay.states.messages))
    real, ours = [], []
    for i in range(stop):
        real.append(sum(f.force_n[2] for f in replay.sense("real", i).frp.values()))
        ours.append(sum(f.force_n[2] for f in replay.sense("ours", i).frp.values()))
    rms = float(np.sqrt(np.mean(np.square(np.array(ours) - np.array(real)))))
    return [Measure("foot_force_rms_n", 0.0, rms, "N", min(rms / 10.0, ERROR_CAP))]


def score(found: list[Measure]) -> float:
    """A trace's error: the mean of its measures' errors (0 = agrees)."""
    return float(np.mean([m.error for m in found])) if found else 0.0
