"""The walk-leaning curve as a tuning problem: lean request c in [-1, 1] -> swing-leg joint offsets, so that
the walk's curvature is linear in the request over the whole range, with no fall and at most 10 % speed loss.

The curve (``agent.motion.dynamic.WalkLean``): offset of joint kind j = ``joint_offsets_deg[j]`` x s(|c|)
on the side c leans to, per walk phase as its phase scale says; s is the command curve through (0, 0),
the tuned shares at ``COMMANDS`` and (1, 1): odd-symmetric by construction (each side mirrors the other),
bounded by the full-lean offsets, smooth (second differences of s bounded) and monotone (constraints).
Parameters: the full-lean offsets of the hip yaw-pitch (le1) and hip pitch (le3), and s at the inner
commands. A candidate walks ``walk_forward`` at +-each command on our simulator; its figures are the
curvature [deg/m] and speed ratio (to the straight walk's) at each. Loss: the mean squared curvature error
against ``target x c`` [deg^2/m^2]; a fall costs 100, the speed ratio must stay >= 0.9 (a constraint).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from functools import partial
from typing import Any

import casadi
import numpy as np

from agent.motion.dynamic import DynamicParams, WalkLean
from motion_studio.tuning import Constraint, CurveView, ModelSpec, Parameter, Problem

#: Request magnitudes walked (each left and right); the command curve's inner points are all but the last.
COMMANDS = (0.25, 0.5, 0.75, 1.0)
QUICK_COMMANDS = (0.5, 1.0)
#: Wanted curvature at a full lean [deg/m] (the shipped curve gives about 27).
TARGET_DEG_M = 24.0
#: Walk per rollout [s] (from x = -8 m, as the lean trials of tune_gait).
WALK_S, QUICK_WALK_S = 8.0, 6.0
MIN_SPEED_RATIO = 0.9
FALL_LOSS = 100.0
#: Bound on the command curve's second differences (smoothness).
MAX_BEND = 0.3
OFFSET_BOUNDS_DEG = {"le1": (-6.0, 0.0), "le3": (-3.0, 3.0)}


def tag(command: float) -> str:
    """Figure suffix of a signed command (+0.5 -> ``p050``, -1 -> ``m100``)."""
    return f"{'p' if command > 0 else 'm'}{round(abs(command) * 100):03d}"


def shape_name(command: float) -> str:
    return f"share_at_{round(command * 100):03d}"


def lean_curve(base: WalkLean, values: Mapping[str, float], commands: Sequence[float], provenance: str = "") -> WalkLean:
    """``base`` with the tuned full-lean offsets and command curve."""
    offsets = dict(base.joint_offsets_deg)
    offsets.update({kind: round(float(values[f"{kind}_deg"]), 3) for kind in OFFSET_BOUNDS_DEG})
    inner = [c for c in commands if c < 1.0]
    return replace(base, joint_offsets_deg=offsets, command_points=(0.0, *inner, 1.0),
                   command_scale=(0.0, *(round(float(values[shape_name(c)]), 4) for c in inner), 1.0),
                   provenance=provenance or base.provenance)


def walk(dynamic: DynamicParams, lean: float, duration_s: float) -> tuple[float, float, bool]:
    """Curvature [deg/m], steady speed [m/s] and fall of one walk_forward run at ``lean``."""
    from agent.motion import default_library
    from motion_studio.walk_rollout import run_walk

    run = run_walk(default_library(0), "walk_forward", duration_s, position_m=(-8.0, 0.0), lean=lean, x_limit_m=None,
                   dynamic=dynamic)
    return run.curvature_deg_m, math.hypot(*run.steady_velocity_m_s()), bool(run.fell or run.fell_stopping)


def measure(dynamic: DynamicParams, commands: Sequence[float], duration_s: float, straight: tuple[float, float],
            target_deg_m: float, values: Mapping[str, float]) -> dict[str, Any]:
    """Figures and loss of one candidate (module-level: worker processes run it)."""
    tuned = replace(dynamic, walk_lean=lean_curve(dynamic.walk_lean, values, commands))
    straight_curvature, straight_speed = straight
    out: dict[str, Any] = {"falls": 0}
    errors = []
    for magnitude in commands:
        for command in (magnitude, -magnitude):
            curvature, speed, fell = walk(tuned, command, duration_s)
            out[f"curvature_{tag(command)}"] = curvature
            out[f"speed_ratio_{tag(command)}"] = speed / straight_speed if straight_speed > 0 else 0.0
            out["falls"] += int(fell)
            errors.append(curvature - straight_curvature - target_deg_m * command)
    out["curvature_error_max_deg_m"] = float(np.max(np.abs(errors)))
    out["loss"] = float(np.mean(np.square(errors))) + FALL_LOSS * out["falls"]
    return out


def lean_problem(dynamic: DynamicParams, commands: Sequence[float] = COMMANDS, duration_s: float = WALK_S,
                 target_deg_m: float = TARGET_DEG_M, straight: tuple[float, float] | None = None) -> Problem:
    """The problem, started from ``dynamic``'s lean curve (its offsets, a linear command curve). The straight
    walk (curvature and speed at c = 0 do not depend on the curve) is measured here once unless given."""
    if straight is None:
        curvature, speed, _ = walk(dynamic, 0.0, duration_s)
        straight = (curvature, speed)
    base = dynamic.walk_lean
    inner = [c for c in commands if c < 1.0]
    parameters = tuple(Parameter(f"{kind}_deg", *bounds) for kind, bounds in OFFSET_BOUNDS_DEG.items()) + tuple(
        Parameter(shape_name(c), 0.0, 1.0) for c in inner)
    start = {f"{kind}_deg": min(max(base.joint_offsets_deg.get(kind, 0.0), low), high)
             for kind, (low, high) in OFFSET_BOUNDS_DEG.items()}
    start.update({shape_name(c): c for c in inner})
    signed = [s * c for c in commands for s in (1.0, -1.0)]
    straight_curvature = straight[0]

    def loss(figures: Mapping[str, Any], values: Mapping[str, Any]) -> Any:
        return sum((figures[f"curvature_{tag(c)}"] - straight_curvature - target_deg_m * c) ** 2
                   for c in signed) / len(signed)

    def shape(values: Mapping[str, Any]) -> list[tuple[Any, float, float]]:
        shares = [0.0] + [values[shape_name(c)] for c in inner] + [1.0]
        points = [0.0, *inner, 1.0]
        slopes = [(b - a) / (q - p) for a, b, p, q in zip(shares, shares[1:], points, points[1:])]
        rows = [(slope, 0.0, casadi.inf) for slope in slopes]  # monotone
        rows += [(b - a, -MAX_BEND / 0.25, MAX_BEND / 0.25) for a, b in zip(slopes, slopes[1:])]  # smooth
        return rows

    figures = tuple(f"curvature_{tag(c)}" for c in signed) + tuple(f"speed_ratio_{tag(c)}" for c in signed)
    constraints = tuple(Constraint(f"speed at {c:+g}", f"speed_ratio_{tag(c)}", low=MIN_SPEED_RATIO, penalty=100.0)
                        for c in signed)
    def measured(result: Mapping[str, Any]) -> tuple[list[float], list[float]]:
        xs = signed_sorted(commands)
        return xs, [result[f"curvature_{tag(c)}"] - straight_curvature if c else 0.0 for c in xs]

    view = CurveView("lean request", "curvature less the straight walk's [deg/m]",
                     tuned=lambda values, result: measured(result), measured=measured,
                     target=lambda xs: [target_deg_m * x for x in xs])
    return Problem("walk_lean", parameters,
                   partial(measure, dynamic, tuple(commands), duration_s, straight, target_deg_m),
                   start=start, constraints=constraints, fail_loss=1e4, rollouts_per_candidate=len(signed), curve=view,
                   model=ModelSpec(figures, loss, shape))


def signed_sorted(commands: Sequence[float]) -> list[float]:
    """-1 ... 0 ... +1: the requests walked and the straight walk, in order (for plots)."""
    return sorted([-c for c in commands] + [0.0] + list(commands))


__all__ = ["COMMANDS", "QUICK_COMMANDS", "QUICK_WALK_S", "TARGET_DEG_M", "WALK_S", "lean_curve", "lean_problem",
           "measure", "signed_sorted", "tag"]
