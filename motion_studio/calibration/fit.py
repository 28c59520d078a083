"""Fit our simulator's contact parameters to the real recordings: CMA-ES over replay agreement, checkpointed.

The objective is the mean trace score of `motion_studio.calibration.agreement` over every trace, plus a
penalty per blow-up (a parameter set that makes the physics diverge is worse than any disagreement). The
fit is a problem of the tuning room (``motion_studio.tuning``): every candidate's scores go to the run
folder's ``trace.jsonl`` and the optimiser to ``checkpoint.pkl`` after every generation, so a killed run
resumes where it stopped and loses no finished replay.
"""

from __future__ import annotations

import math
from collections.abc import Callable
import dataclasses
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from motion_studio.calibration.agreement import Measure, Outcome, Replay, measures, outcomes, score
from motion_studio.calibration.errors import CalibrationError
from motion_studio.tuning import CMAES, Parameter, Problem, TuningError, run
from motion_studio.realserver.fixtures import Fixture
from motion_studio.realserver.replay import replay_states
from sim.physics_params import PhysicsParams

#: Objective added per blow-up of the physics during a replay.
BLOW_UP_PENALTY = 0.5


def FitParameter(name: str, low: float, high: float, log: bool = False) -> Parameter:  # noqa: N802 - a constructor
    """One fitted physical parameter: a `PhysicsParams` field (or ``field[index]`` of a tuple field), bounds in
    its unit, searched on a log scale when ``log``."""
    return Parameter(name, low, high, decimals=6, log=log)


#: The robot contact parameters (names as `PhysicsParams` fields).
CONTACT_PARAMETERS: tuple[Parameter, ...] = (
    FitParameter("friction", 0.5, 50.0, log=True),
    FitParameter("impratio", 0.1, 30.0, log=True),
    FitParameter("contact_solimp[0]", 0.05, 0.95),
    FitParameter("contact_solimp[1]", 0.05, 0.99),
    FitParameter("contact_solimp[2]", 0.0002, 0.02, log=True),
    FitParameter("contact_solref[0]", 0.02, 0.2, log=True),
    FitParameter("contact_solref[1]", 0.3, 3.0, log=True),
    FitParameter("noslip_iterations", 0, 20),
    FitParameter("surface_layer_m", 0.0, 0.002),
)
#: The ball's contact parameters (its contacts with feet and ground take the ball's values) and the restitution
#: of its rebound off robots (``sim.world``: MuJoCo's soft contact absorbs part of an impact before the rebound
#: is added, so SimSpark's 0.8 need not be ours). Not its drag: SimSpark's 0.01 N·s/m is a fact (REFERENCE §2.4).
BALL_PARAMETERS: tuple[Parameter, ...] = (
    FitParameter("ball_friction", 0.2, 200.0, log=True),
    FitParameter("ball_solref[0]", 0.005, 0.1, log=True),
    FitParameter("ball_solref[1]", 0.3, 3.0, log=True),
    FitParameter("ball_solimp[0]", 0.05, 0.95),
    FitParameter("ball_solimp[1]", 0.05, 0.99),
    FitParameter("ball_robot_restitution", 0.4, 1.0),
)
#: The feet's force-dependent slip (`sim.physics_params`, "Feet slip as ODE's") and the other body parts' Coulomb
#: friction that was fitted beside the feet's Coulomb mu; fitted from a physics file that sets the slip
#: (sim/physics_candidates/foot_slip.toml): 0.005 m/s per N is SimSpark's own value, the start of the search.
SLIP_PARAMETERS: tuple[Parameter, ...] = (
    FitParameter("foot_slip_m_s_per_n", 0.0005, 0.05, log=True),
    FitParameter("foot_slip_layer_m", 0.0, 0.002),
    FitParameter("body_friction", 0.3, 3.0, log=True),
)
PARAMETER_SETS: dict[str, tuple[Parameter, ...]] = {
    "contact": CONTACT_PARAMETERS, "ball": BALL_PARAMETERS, "slip": SLIP_PARAMETERS,
    "all": CONTACT_PARAMETERS + BALL_PARAMETERS}
DEFAULT_PARAMETERS = CONTACT_PARAMETERS


def _split(name: str) -> tuple[str, int | None]:
    if name.endswith("]") and "[" in name:
        field, index = name[:-1].split("[", 1)
        return field, int(index)
    return name, None


def read_value(params: PhysicsParams, name: str) -> float:
    field, index = _split(name)
    if field not in PhysicsParams.__dataclass_fields__:
        raise CalibrationError("<parameters>", 0, f"unknown physics parameter {field!r}")
    value = getattr(params, field)
    if value is None:
        raise CalibrationError("<parameters>", 0, f"{field} is off (None) in the physics in force: start from a "
                                                  f"physics file that sets it (NAO3D_PHYSICS_FILE=...)")
    return float(value[index] if index is not None else value)


def with_values(params: PhysicsParams, values: dict[str, float]) -> PhysicsParams:
    """``params`` with the named values set (tuple fields element-wise)."""
    changes: dict[str, object] = {}
    for name, value in values.items():
        field, index = _split(name)
        if field not in PhysicsParams.__dataclass_fields__:
            raise CalibrationError("<parameters>", 0, f"unknown physics parameter {field!r}")
        if index is None:
            current = getattr(params, field)
            changes[field] = float(value) if current is None else type(current)(value)
        else:
            current = list(changes.get(field, getattr(params, field)))  # type: ignore[arg-type]
            current[index] = value
            changes[field] = tuple(current)
    for name in ("contact_solimp", "ball_solimp"):   # MuJoCo wants dmin <= dmax < 1
        if name in changes:
            solimp = list(changes[name])  # type: ignore[arg-type]
            solimp[1] = max(solimp[0], solimp[1])
            changes[name] = tuple(solimp)
    return replace(params, **changes)


@dataclass
class Evaluation:
    """One parameter set's agreement: objective, per-trace scores and measures, blow-ups."""

    values: dict[str, float]
    objective: float
    scores: dict[str, float]
    details: dict[str, list[Measure]]
    blow_ups: int
    outcomes: dict[str, tuple[Outcome, Outcome]] = dataclasses.field(default_factory=dict)
    """Per skill trace: the real robot's and ours' outcome (fell or not, standing at the end or not)."""

    def same_outcomes(self) -> int:
        """Skill traces whose replay ends as the real run did."""
        return sum(real == ours for real, ours in self.outcomes.values())


def evaluate(traces: list[Fixture], params: PhysicsParams, values: dict[str, float] | None = None,
             ball_roll: bool = True) -> Evaluation:
    """Replay every trace with ``params`` and score the agreement (with the real ball-roll figures unless
    ``ball_roll`` is False)."""
    scores: dict[str, float] = {}
    details: dict[str, list[Measure]] = {}
    blow_ups = 0
    if ball_roll:
        from motion_studio.calibration.reference_figures import ball_roll_measures

        details["ball_roll"] = ball_roll_measures(params)
        scores["ball_roll"] = score(details["ball_roll"])
    ends: dict[str, tuple[Outcome, Outcome]] = {}
    for trace in traces:
        states = replay_states(trace, params)
        replay = Replay(trace, states)
        found = measures(replay)
        ended = outcomes(replay)
        if ended is not None:
            ends[trace.name] = ended
        details[trace.name] = found
        scores[trace.name] = score(found)
        blow_ups += states.blow_ups
    objective = float(np.mean(list(scores.values()))) + BLOW_UP_PENALTY * blow_ups
    if not math.isfinite(objective):
        objective = float("inf")
    return Evaluation(values or {}, objective, scores, details, blow_ups, ends)


def fit(traces: list[Fixture], base: PhysicsParams, parameters: tuple[Parameter, ...], run_dir: Path,
        generations: int, popsize: int | None = None, sigma: float = 0.25, seed: int = 0,
        on_evaluation: Callable[[int, Evaluation], None] | None = None, ball_roll: bool = True) -> Evaluation:
    """CMA-ES from ``base`` over ``parameters``; resumes from ``run_dir``'s checkpoint. Returns the best
    evaluation found (the starting point included)."""
    names = [p.name for p in parameters]
    generation = {"now": -1}

    def judge(values: dict[str, float]) -> dict[str, object]:
        result = evaluate(traces, with_values(base, values), values, ball_roll)
        if on_evaluation:
            on_evaluation(generation["now"], result)
        if not math.isfinite(result.objective):  # the physics diverged: a failed candidate
            return {"failed": "the physics diverged in a replay", "blow_ups": result.blow_ups}
        return {"loss": result.objective, "scores": result.scores, "blow_ups": result.blow_ups}

    def told(event) -> None:  # noqa: ANN001 - runner.Event
        if event.kind == "iteration":
            generation["now"] = event.iteration + 1
        elif event.iteration == -1:
            generation["now"] = 0  # the start is done; the first generation follows

    problem = Problem("calibrate", tuple(parameters), judge, start={n: read_value(base, n) for n in names},
                      fail_loss=1e6)
    try:
        result = run(problem, lambda p: CMAES(p.x0(), sigma, popsize, seed, max_iterations=generations), run_dir,
                     on_event=told)
    except TuningError as error:
        raise CalibrationError(run_dir / "checkpoint.pkl", 0, f"{error}; use another --out") from None
    best = result.best["values"]
    return evaluate(traces, with_values(base, best), best, ball_roll)
