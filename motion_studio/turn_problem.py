"""The turn-gain curve as a tuning problem: requested turn of one motion [deg] -> gain, monotone and bounded,
so that the turn a motion makes is the turn requested (dead reckoning predicts it) in the least time.

Parameters: the gain at each request point (``REQUEST_POINTS_DEG``). A candidate plays one turn motion from
the stance at each point's gain, left and right, on our simulator (``skill_bench.turn.run_motions``, truth
heading), as ``agent.skills.turn.TurnBy`` plays a request up to the last point. Loss: the mean squared
error of the turn made against the turn requested [deg^2] plus ``TIME_WEIGHT`` x the mean motion time [s].
The curve between the points is linear in the request, beyond the last point TurnBy splits the request
into equal parts (``agent.skills.turn.split_turn``), so requests of 3-60 deg all use it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from functools import partial
from typing import Any

import casadi
import numpy as np

from agent.motion.dynamic import DynamicParams, TurnGain
from motion_studio.tuning import CurveView, ModelSpec, Parameter, Problem

#: Requested turns of one motion [deg] at which the gain is tuned; the last is the largest one motion is asked.
REQUEST_POINTS_DEG = (2.0, 10.0, 20.0, 30.0, 38.0)
QUICK_POINTS_DEG = (5.0, 20.0, 38.0)
#: Loss per second of motion time [deg^2/s]: time per turn counts, but an exact turn counts more.
TIME_WEIGHT = 0.1
#: Smallest gain step between neighbouring points (strictly monotone, so the curve inverts).
MIN_GAIN_STEP = 0.01
GAIN_BOUNDS = (0.02, 1.0)
#: Requested turns of the prediction check [deg] (each left and right), as the turn benchmark's.
CHECK_DEG = (3.0, 6.0, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0)
CHECK_QUICK_DEG = (3.0, 10.0, 25.0, 45.0, 60.0)


def gain_name(point_deg: float) -> str:
    return f"gain_at_{point_deg:g}_deg".replace(".", "_")


def turn_name(point_deg: float) -> str:
    return f"turn_at_{point_deg:g}_deg".replace(".", "_")


def measure(points_deg: Sequence[float], sides: Sequence[str], seed: int, values: Mapping[str, float]) -> dict[str, Any]:
    """Turn per motion [deg] and motion time [s] at each point's gain (mean of ``sides``) and the loss.
    Module-level: worker processes run it."""
    from motion_studio.skill_bench.turn import run_motions

    out: dict[str, Any] = {}
    errors, times, falls = [], [], 0
    for point in points_deg:
        turns = []
        for side in sides:
            run = run_motions(side, float(values[gain_name(point)]), 1, seed)
            turns.append(abs(run.turn_deg) / max(run.motions, 1))
            times.append(run.duration_s / max(run.motions, 1))
            falls += run.fell
        out[turn_name(point)] = float(np.mean(turns))
        errors.append(out[turn_name(point)] - point)
    out["time_per_motion_s"] = float(np.mean(times))
    out["falls"] = falls
    out["max_error_deg"] = float(np.max(np.abs(errors)))
    out["loss"] = float(np.mean(np.square(errors))) + TIME_WEIGHT * out["time_per_motion_s"] + 100.0 * falls
    return out


def turn_curve(values: Mapping[str, float], points_deg: Sequence[float], provenance: str = "") -> TurnGain:
    """The ``[turn_gain]`` curve of tuned values (the legacy line fields describe the same range)."""
    gains = tuple(round(float(values[gain_name(p)]), 4) for p in points_deg)
    return TurnGain(min_gain=gains[0], offset_deg=points_deg[0], span_deg=points_deg[-1] - points_deg[0],
                    predicted_base_deg=points_deg[0], predicted_slope_deg=points_deg[-1] - points_deg[0],
                    provenance=provenance, request_points_deg=tuple(points_deg), curve_gains=gains)


def turn_problem(start: TurnGain, points_deg: Sequence[float] = REQUEST_POINTS_DEG,
                 sides: Sequence[str] = ("left", "right"), seed: int = 0) -> Problem:
    """The problem (start: ``start``'s gains at the points, made strictly increasing)."""
    points = tuple(float(p) for p in points_deg)
    start_gains = np.maximum.accumulate([min(GAIN_BOUNDS[1], max(GAIN_BOUNDS[0], start.gain(p))) for p in points])
    parameters = tuple(Parameter(gain_name(p), *GAIN_BOUNDS, unit="") for p in points)

    def loss(figures: Mapping[str, Any], values: Mapping[str, Any]) -> Any:
        error = sum((figures[turn_name(p)] - p) ** 2 for p in points) / len(points)
        return error + TIME_WEIGHT * figures["time_per_motion_s"]

    def monotone(values: Mapping[str, Any]) -> list[tuple[Any, float, float]]:
        return [(values[gain_name(b)] - values[gain_name(a)], MIN_GAIN_STEP, casadi.inf)
                for a, b in zip(points, points[1:])]

    view = CurveView("gain", "turn of one motion [deg]",
                     tuned=lambda v, result: ([v[gain_name(p)] for p in points], list(points)),
                     measured=lambda r: (r.get("_gains", []), [r[turn_name(p)] for p in points] if "_gains" in r else []))
    return Problem("turn_gain", parameters, partial(_measure_with_gains, points, tuple(sides), seed),
                   start={gain_name(p): round(float(g), 4) for p, g in zip(points, start_gains)},
                   fail_loss=1e4, rollouts_per_candidate=len(points) * len(sides), curve=view,
                   model=ModelSpec(tuple(turn_name(p) for p in points) + ("time_per_motion_s",), loss, monotone))


def _measure_with_gains(points: Sequence[float], sides: Sequence[str], seed: int,
                        values: Mapping[str, float]) -> dict[str, Any]:
    """:func:`measure`, with the candidate's gains kept in the result for the curve plot."""
    out = measure(points, sides, seed, values)
    out["_gains"] = [float(values[gain_name(p)]) for p in points]
    return out


def prediction_error(curve: TurnGain, dynamic: DynamicParams, requested_deg: Sequence[float] = CHECK_DEG,
                     seed: int = 0) -> dict[str, float]:
    """TurnBy by dead reckoning with ``curve``, each request left and right: |measured - predicted| mean and
    max [deg], |measured - requested| mean [deg], time per turn [s], falls."""
    from motion_studio.skill_bench.turn import run_turn_by

    tuned = replace(dynamic, turn_gain=curve)
    predicted_errors, requested_errors, times, falls = [], [], [], 0
    for angle in requested_deg:
        for sign in (1.0, -1.0):
            run, predicted = run_turn_by(sign * angle, seed, tuned)
            predicted_errors.append(abs(run.turn_deg - predicted))
            requested_errors.append(abs(run.turn_deg - sign * angle))
            times.append(run.duration_s)
            falls += run.fell
    return {"prediction_error_mean_deg": round(float(np.mean(predicted_errors)), 3),
            "prediction_error_max_deg": round(float(np.max(predicted_errors)), 3),
            "request_error_mean_deg": round(float(np.mean(requested_errors)), 3),
            "time_per_turn_s": round(float(np.mean(times)), 3), "falls": falls,
            "requests": len(predicted_errors)}


__all__ = ["CHECK_DEG", "CHECK_QUICK_DEG", "QUICK_POINTS_DEG", "REQUEST_POINTS_DEG", "gain_name", "measure",
           "prediction_error", "turn_curve", "turn_name", "turn_problem"]
