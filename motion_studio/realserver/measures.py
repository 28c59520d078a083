"""Measurements on a run's ground truth (a list of ``Truth`` per cycle, None where unknown), the same on both
servers: falls, standing up, turning, displacement, ball travel."""

from __future__ import annotations

import math
from collections.abc import Sequence

from agent.world.frames import Pose2D
from motion_studio.realserver.cases import CYCLE_S
from motion_studio.scenarios import FALL_TORSO_Z_M, FALL_UP_Z, Truth

#: Stood up: the torso centre above this height [m] ...
STOOD_TORSO_Z_M = 0.30
#: ... for this long without a break [s] (tilt alone does not count: a robot sitting upright on the ground
#: holds its torso below 0.30 m).
STOOD_HOLD_S = 1.0
#: A fall ends (the robot counts as standing again) above this torso height [m] (sim.match's hysteresis).
STANDING_AGAIN_Z_M = 0.30

Truths = Sequence[Truth | None]


def fallen(truth: Truth) -> bool:
    """REFERENCE §8.1: the torso's up axis z below 0.6 or its centre below 0.25 m."""
    return truth.up_z < FALL_UP_Z or truth.torso_m[2] < FALL_TORSO_Z_M


def wrap_deg(angle_deg: float) -> float:
    return (angle_deg + 180.0) % 360.0 - 180.0


def first_fall(truths: Truths, start: int = 0) -> int | None:
    """Index of the first fallen cycle from ``start`` (None: no fall)."""
    return next((i for i in range(start, len(truths)) if truths[i] is not None and fallen(truths[i])), None)


def stood_index(truths: Truths, start: int = 0, hold_s: float = STOOD_HOLD_S) -> int | None:
    """First index >= ``start`` from which the torso centre stays above STOOD_TORSO_Z_M for ``hold_s`` (every
    cycle of the window known); None if it never does within the run."""
    hold = round(hold_s / CYCLE_S)
    run = 0
    for i in range(start, len(truths)):
        truth = truths[i]
        run = run + 1 if truth is not None and truth.torso_m[2] > STOOD_TORSO_Z_M else 0
        if run >= hold:
            return i - hold + 1
    return None


def count_falls(truths: Truths, until: int | None = None) -> list[int]:
    """Cycles at which the robot fell (torso centre below 0.25 m; it must rise above 0.30 m before another fall
    counts, as sim.match counts them)."""
    falls, down = [], False
    for i, truth in enumerate(truths[:until]):
        if truth is None:
            continue
        z = truth.torso_m[2]
        if not down and z < FALL_TORSO_Z_M:
            falls.append(i)
            down = True
        elif down and z > STANDING_AGAIN_Z_M:
            down = False
    return falls


def known(truths: Truths, index: int, backwards: bool = True) -> Truth | None:
    """The truth at ``index``, else the nearest known one before it (or after it with ``backwards`` False)."""
    index = min(max(index, 0), len(truths) - 1)
    steps = range(index, -1, -1) if backwards else range(index, len(truths))
    return next((truths[i] for i in steps if truths[i] is not None), None)


def turned_deg(truths: Truths, start: int = 0, end: int | None = None) -> float:
    """Heading change summed cycle by cycle (unwrapped) over known truths in [start, end] [deg]."""
    headings = [t.heading_deg for t in truths[start:None if end is None else end + 1] if t is not None]
    return float(sum(wrap_deg(b - a) for a, b in zip(headings, headings[1:])))


def pose_of(truth: Truth) -> Pose2D:
    """The torso's ground pose of a truth (field frame)."""
    return Pose2D(truth.torso_m[0], truth.torso_m[1], math.radians(truth.heading_deg))


def displacement_m(first: Truth, last: Truth) -> tuple[float, float]:
    """(forward, left) of ``last``'s torso in the frame of ``first`` [m]."""
    return pose_of(first).to_ego(last.torso_m[0], last.torso_m[1])


def ball_travel_m(first: Truth, last: Truth) -> float:
    """How far the ball moved on the ground between two truths [m] (NaN if the ball is unknown)."""
    if math.isnan(first.ball_m[0]) or math.isnan(last.ball_m[0]):
        return math.nan
    return math.dist(first.ball_m[:2], last.ball_m[:2])
