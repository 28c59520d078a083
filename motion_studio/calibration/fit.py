"""Fit our simulator's contact parameters to the real recordings: CMA-ES over replay agreement, checkpointed.

The objective is the mean trace score of `motion_studio.calibration.agreement` over every trace, plus a
penalty per blow-up (a parameter set that makes the physics diverge is worse than any disagreement). Each
generation's candidates and scores go to ``evaluations.jsonl`` and the optimiser's state to
``checkpoint.json`` in the run folder, so a killed run resumes where it stopped and loses no finished replay.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from motion_studio.calibration.agreement import Measure, Replay, measures, score
from motion_studio.calibration.errors import CalibrationError
from motion_studio.cmaes import CMAES
from motion_studio.realserver.fixtures import Fixture
from motion_studio.realserver.replay import replay_states
from sim.physics_params import PhysicsParams

#: Objective added per blow-up of the physics during a replay.
BLOW_UP_PENALTY = 0.5


@dataclass(frozen=True)
class FitParameter:
    """One fitted physical parameter: a `PhysicsParams` field (or ``field[index]`` of a tuple field), bounds in
    its unit, searched on a log scale when ``log``."""

    name: str
    low: float
    high: float
    log: bool = False

    def to_unit(self, value: float) -> float:
        if self.log:
            return float(np.clip((math.log(value) - math.log(self.low)) / math.log(self.high / self.low), 0, 1))
        return float(np.clip((value - self.low) / (self.high - self.low), 0, 1))

    def from_unit(self, unit: float) -> float:
        unit = float(np.clip(unit, 0.0, 1.0))
        if self.log:
            return round(self.low * (self.high / self.low) ** unit, 6)
        return round(self.low + unit * (self.high - self.low), 6)


#: The robot contact parameters (names as `PhysicsParams` fields).
CONTACT_PARAMETERS: tuple[FitParameter, ...] = (
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
#: The ball's contact parameters (its contacts with feet and ground take the ball's values).
BALL_PARAMETERS: tuple[FitParameter, ...] = (
    FitParameter("ball_friction", 0.5, 200.0, log=True),
    FitParameter("ball_solref[0]", 0.005, 0.1, log=True),
    FitParameter("ball_solref[1]", 0.3, 3.0, log=True),
    FitParameter("ball_solimp[0]", 0.05, 0.95),
    FitParameter("ball_solimp[1]", 0.05, 0.99),
    FitParameter("ball_linear_drag_n_s_m", 0.005, 0.02, log=True),
)
PARAMETER_SETS: dict[str, tuple[FitParameter, ...]] = {
    "contact": CONTACT_PARAMETERS, "ball": BALL_PARAMETERS, "all": CONTACT_PARAMETERS + BALL_PARAMETERS}
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
    return float(value[index] if index is not None else value)


def with_values(params: PhysicsParams, values: dict[str, float]) -> PhysicsParams:
    """``params`` with the named values set (tuple fields element-wise)."""
    changes: dict[str, object] = {}
    for name, value in values.items():
        field, index = _split(name)
        if field not in PhysicsParams.__dataclass_fields__:
            raise CalibrationError("<parameters>", 0, f"unknown physics parameter {field!r}")
        if index is None:
            changes[field] = type(getattr(params, field))(value)
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
    for trace in traces:
        states = replay_states(trace, params)
        found = measures(Replay(trace, states))
        details[trace.name] = found
        scores[trace.name] = score(found)
        blow_ups += states.blow_ups
    objective = float(np.mean(list(scores.values()))) + BLOW_UP_PENALTY * blow_ups
    if not math.isfinite(objective):
        objective = float("inf")
    return Evaluation(values or {}, objective, scores, details, blow_ups)


def fit(traces: list[Fixture], base: PhysicsParams, parameters: tuple[FitParameter, ...], run_dir: Path,
        generations: int, popsize: int | None = None, sigma: float = 0.25, seed: int = 0,
        on_evaluation: Callable[[int, Evaluation], None] | None = None, ball_roll: bool = True) -> Evaluation:
    """CMA-ES from ``base`` over ``parameters``; resumes from ``run_dir``'s checkpoint. Returns the best
    evaluation found (the starting point included)."""
    run_dir.mkdir(parents=True, exist_ok=True)
    checkpoint = run_dir / "checkpoint.json"
    log = run_dir / "evaluations.jsonl"
    names = [p.name for p in parameters]
    if checkpoint.exists():
        state = json.loads(checkpoint.read_text())
        if state.get("parameters") != names:
            raise CalibrationError(checkpoint, 0, f"checkpoint fits {state.get('parameters')}, not {names}; "
                                                  "use another --out")
        optimiser = CMAES.from_state(state["cmaes"])
        best = state["best"]
    else:
        x0 = np.array([p.to_unit(read_value(base, p.name)) for p in parameters])
        optimiser = CMAES.create(x0, sigma, popsize, seed)
        start = {p.name: read_value(base, p.name) for p in parameters}
        first = evaluate(traces, base, start, ball_roll)
        _log(log, -1, first)
        if on_evaluation:
            on_evaluation(-1, first)
        best = {"values": start, "objective": first.objective}
    count = 0
    while optimiser.generation < generations:
        candidates = optimiser.ask()
        losses = []
        for unit in candidates:
            values = {p.name: p.from_unit(u) for p, u in zip(parameters, unit)}
            result = evaluate(traces, with_values(base, values), values, ball_roll)
            _log(log, optimiser.generation, result)
            if on_evaluation:
                on_evaluation(optimiser.generation, result)
            losses.append(result.objective)
            count += 1
            if result.objective < best["objective"]:
                best = {"values": values, "objective": result.objective}
        optimiser.tell(losses)
        checkpoint.write_text(json.dumps({"parameters": names, "cmaes": optimiser.state(), "best": best}))
    return evaluate(traces, with_values(base, best["values"]), best["values"], ball_roll)


def _log(path: Path, generation: int, result: Evaluation) -> None:
    with open(path, "a") as stream:
        stream.write(json.dumps({"generation": generation, "values": result.values, "objective": result.objective,
                                 "scores": result.scores, "blow_ups": result.blow_ups}) + "\n")
