"""A tuning problem: named parameters with units and bounds, constraints, and an objective over rollouts.

Why one shape for every tuner: the optimizers (CMA-ES, the CasADi trust region), the rollout backends, the
checkpoint and the trace only ever see a :class:`Problem`; a tuner is a problem definition and nothing more.
The optimizers search the unit box [0, 1]^n; :class:`Parameter` maps it to each parameter's own unit.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from motion_studio.tuning.errors import TuningError

#: A candidate's figures as the evaluation returns them; ``loss`` (lower is better) is required.
Result = dict[str, Any]
#: Evaluates one candidate (parameter name -> value in its unit); must pickle (module-level) for processes.
Evaluate = Callable[[dict[str, float]], Result]


#: Name suffixes that say a parameter's unit (STYLE: units in names).
UNIT_SUFFIXES = {"_deg": "deg", "_rad": "rad", "_ms": "ms", "_s": "s", "_m": "m", "_m_s": "m/s", "_deg_m": "deg/m",
                 "_n": "N", "_kg": "kg"}


def unit_of(name: str) -> str:
    """The unit a parameter's name ends with (``strike_height_m`` -> "m"), "" if none."""
    for suffix, unit in sorted(UNIT_SUFFIXES.items(), key=lambda item: -len(item[0])):
        if name.lower().endswith(suffix):
            return unit
    return ""


@dataclass(frozen=True)
class Parameter:
    """One tuned parameter and its bounds, mapped to and from the optimizer's [0, 1] box.

    Args:
        name: the parameter (a dataclass field, or a dotted path the tuner resolves).
        low, high: bounds in the parameter's own unit (``unit``).
        step: values are rounded to a multiple of it and returned as int (0 = continuous): whole counts,
            durations in multiples of a 20 ms cycle.
        decimals: rounding of continuous values (keeps parameter files readable).
        unit: the unit of ``low``/``high``/values, for tables and plots ("deg", "m", "ms", "" = none; default
            from the name's suffix).
        log: searched on a log scale (bounds must then be positive): physical constants over decades.

    Raises:
        TuningError: a bound that is not finite, or ``low > high``.
    """

    name: str
    low: float
    high: float
    step: float = 0.0
    decimals: int = 4
    unit: str = ""
    log: bool = False

    def __post_init__(self) -> None:
        if not self.unit:
            object.__setattr__(self, "unit", unit_of(self.name))
        if not (math.isfinite(self.low) and math.isfinite(self.high)):
            raise TuningError(f"parameter {self.name!r}: bounds must be finite, got [{self.low}, {self.high}]")
        if self.low > self.high:
            raise TuningError(f"parameter {self.name!r}: lower bound {self.low} > upper bound {self.high}")
        if self.log and self.low <= 0.0:
            raise TuningError(f"parameter {self.name!r}: a log scale needs a positive lower bound, got {self.low}")

    def to_unit(self, value: float) -> float:
        """``value`` in the box (clipped into [0, 1]); a fixed parameter (low == high) sits at 0.5."""
        if self.high == self.low:
            return 0.5
        if self.log:
            unit = math.log(max(float(value), self.low) / self.low) / math.log(self.high / self.low)
        else:
            unit = (float(value) - self.low) / (self.high - self.low)
        return min(1.0, max(0.0, unit))

    def from_unit(self, unit: float) -> float:
        """The parameter's value for a box coordinate (clipped to the bounds, rounded by step/decimals)."""
        unit = min(1.0, max(0.0, float(unit)))
        value = self.low * (self.high / self.low) ** unit if self.log else self.low + unit * (self.high - self.low)
        if self.step:
            return int(round(value / self.step) * self.step)
        return round(value, self.decimals)


@dataclass(frozen=True)
class Constraint:
    """A named inequality on a candidate's figures: ``low <= value(result) <= high`` must hold.

    CMA-ES sees a violated constraint as ``penalty`` per unit of violation added to the loss; the CasADi
    trust region keeps it as a constraint of its subproblem (on the local model of ``figure``).
    """

    name: str
    figure: str
    """Key of the result holding the constrained value."""
    low: float = -math.inf
    high: float = math.inf
    penalty: float = 10.0

    def violation(self, result: Result) -> float:
        value = float(result.get(self.figure, math.nan))
        if not math.isfinite(value):
            return math.inf
        return max(0.0, self.low - value, value - self.high)


@dataclass(frozen=True)
class ModelSpec:
    """A problem's formulation for the CasADi trust region.

    ``figures`` are the measured outputs the trust region models locally (each a smooth function of the
    parameters near the centre); ``loss(figures, values)`` is the objective written once for numbers and
    CasADi symbols alike (only + - * / ** and ``casadi`` functions); ``constraints(values)`` returns the
    problem's constraints on the parameters as (expression, lower, upper) triples (smoothness,
    monotonicity, symmetry). The figure constraints of :class:`Constraint` are added by the trust region.
    """

    figures: tuple[str, ...]
    loss: Callable[[Mapping[str, Any], Mapping[str, Any]], Any]
    constraints: Callable[[Mapping[str, Any]], list[tuple[Any, float, float]]] = lambda values: []


@dataclass(frozen=True)
class Problem:
    """What a tuner tunes: parameters, the start, the objective over rollouts, and its constraints.

    Args:
        name: the problem's name (``lean``, ``turn``, ``kick:kick_strong``...): run folders and checkpoints
            carry it, and a checkpoint of another problem is refused.
        parameters: the tuned parameters (the box's axes, in this order).
        evaluate: one candidate -> its result (``loss`` plus figures). A rollout that raises is a failed
            candidate (``fail_loss``), never a crash; a NaN ``loss`` is a bug of the objective and stops the run.
        start: the start's values (default: the middle of each parameter's range).
        constraints: inequalities on the figures (see :class:`Constraint`).
        fail_loss: the loss of a failed candidate.
        rollouts_per_candidate: simulator runs one evaluation makes (rollout budgets count these).
        curve: how the run folder's curve plot shows a curve problem (None: objective plot only).
        model: the smooth formulation the CasADi trust region needs (None: CMA-ES only).

    Raises:
        TuningError: two parameters with one name, or a start value naming no parameter.
    """

    name: str
    parameters: tuple[Parameter, ...]
    evaluate: Evaluate
    start: Mapping[str, float] = field(default_factory=dict)
    constraints: tuple[Constraint, ...] = ()
    fail_loss: float = 1e3
    rollouts_per_candidate: int = 1
    curve: CurveView | None = None
    model: ModelSpec | None = None

    def __post_init__(self) -> None:
        names = [p.name for p in self.parameters]
        if not names:
            raise TuningError(f"problem {self.name!r} has no parameters")
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise TuningError(f"problem {self.name!r}: parameter {duplicates[0]!r} given twice")
        unknown = [k for k in self.start if k not in names]
        if unknown:
            raise TuningError(f"problem {self.name!r}: unknown parameter {unknown[0]!r} in the start; "
                              f"known: {', '.join(names)}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def parameter(self, name: str) -> Parameter:
        """The parameter called ``name``.

        Raises:
            TuningError: no such parameter (the message lists the known ones).
        """
        for parameter in self.parameters:
            if parameter.name == name:
                return parameter
        raise TuningError(f"problem {self.name!r}: unknown parameter {name!r}; known: {', '.join(self.names)}")

    def x0(self) -> np.ndarray:
        """The start in the unit box."""
        return np.array([p.to_unit(self.start.get(p.name, (p.low + p.high) / 2.0)) for p in self.parameters])

    def values(self, x: Sequence[float]) -> dict[str, float]:
        """Parameter values (their units) of a box point."""
        return {p.name: p.from_unit(u) for p, u in zip(self.parameters, x)}

    def penalised_loss(self, result: Result) -> float:
        """The loss plus each violated constraint's penalty (what CMA-ES ranks by)."""
        loss = float(result["loss"])
        for constraint in self.constraints:
            violation = constraint.violation(result)
            loss += constraint.penalty * (violation if math.isfinite(violation) else 1e3)
        return loss


def subset(parameters: Sequence[Parameter], names: Sequence[str], what: str = "--only") -> tuple[Parameter, ...]:
    """The parameters called ``names`` (in that order).

    Raises:
        TuningError: an unknown name (one line naming it and the known ones).
    """
    known = {p.name: p for p in parameters}
    for name in names:
        if name not in known:
            raise TuningError(f"{what}: unknown parameter {name!r}; known: {', '.join(known)}")
    return tuple(known[name] for name in names)




@dataclass(frozen=True)
class CurveView:
    """How a curve problem shows itself in the run folder's curve plot: the tuned curve and the measured
    points of the rollouts that shaped it, both drawn from the trace (``tuned(values, result)`` of the best
    candidate and ``measured(result)`` of each each return (x, y) sequences)."""

    xlabel: str
    ylabel: str
    tuned: Callable[[Mapping[str, float], Result], tuple[Sequence[float], Sequence[float]]]
    measured: Callable[[Result], tuple[Sequence[float], Sequence[float]]]
    target: Callable[[Sequence[float]], Sequence[float]] | None = None
    """The wanted y at x (e.g. curvature linear in the command), drawn dashed."""


__all__ = ["Constraint", "CurveView", "Evaluate", "ModelSpec", "Parameter", "Problem", "Result", "subset"]
