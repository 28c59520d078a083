"""A model-based trust region on rollouts: local models fitted in CasADi, subproblems solved by IPOPT.

Why not CMA-ES for the curves: the lean and turn curves are smooth in their parameters, with constraints
(monotone, bounded, odd-symmetric, at most 10 % speed loss) that a penalty only approximates. Each
iteration here evaluates a small batch around the current point, fits every modelled figure (curvature
per command, turn per motion...) with a weighted least-squares model (linear, plus a diagonal quadratic
once there are enough points), and hands the problem's own objective and constraints on those models to
IPOPT inside the trust region. The step is accepted or not by the ratio of actual to predicted decrease
(Conn, Gould & Toint, "Trust-Region Methods", ch. 6 and 9); design points are added only in the directions
the points near the centre do not span yet, so most iterations cost one or two rollouts.

The state is plain arrays (pickled by the run loop's checkpoint); the problem is attached again on resume.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from typing import Any

import casadi
import numpy as np

from motion_studio.tuning.errors import TuningError
from motion_studio.tuning.problem import Problem, Result

logger = logging.getLogger(__name__)

#: Acceptance and radius-update thresholds of the ratio test.
ACCEPT_RATIO = 0.1
SHRINK_RATIO = 0.25
EXPAND_RATIO = 0.7
#: Smallest singular value of the (radius-scaled) displacements near the centre for a well-poised model.
POISED = 0.35
#: Ridge regularisation of the fits (in units of the scaled displacement).
RIDGE = 1e-6


class TrustRegion:
    """CasADi/IPOPT trust region over ``problem`` (which must carry a ``model``, see ``ModelSpec``).

    Args:
        problem: the problem (its ``model`` gives the figures to model, the objective and constraints).
        x0: start in the unit box.
        radius: initial trust-region radius [box units, infinity norm].
        min_radius: ``done`` once the radius falls below it.
        max_radius: the radius never grows beyond it.
        max_iterations: ``done`` after this many iterations.
        tolerance: ``done`` once the model's predicted decrease is below ``tolerance`` x max(1, |loss|) and the
            last step was accepted (converged: more rollouts would only measure the noise floor).

    Raises:
        TuningError: the problem has no model.
    """

    name = "casadi-ipopt-trust-region"

    def __init__(self, problem: Problem, x0: Sequence[float], radius: float = 0.2, min_radius: float = 0.01,
                 max_radius: float = 0.5, max_iterations: int = 30, tolerance: float = 1e-4) -> None:
        if problem.model is None:
            raise TuningError(f"problem {problem.name!r} has no CasADi model (ModelSpec); use CMA-ES")
        self.center = np.clip(np.asarray(x0, dtype=float), 0.0, 1.0)
        self.radius, self.min_radius, self.max_radius = float(radius), float(min_radius), float(max_radius)
        self.max_iterations = max_iterations
        self.iteration = 0
        self.center_loss = math.inf
        self.proposal: np.ndarray | None = None
        self.predicted: tuple[float, float] | None = None
        """Model loss at the centre and at the proposal when it was made."""
        self.points: list[np.ndarray] = []
        self.figures: list[dict[str, float] | None] = []
        self.losses: list[float] = []
        self.last_status = "start"
        self.last_ratio = math.nan
        self.tolerance = tolerance
        self.converged = False
        self._proposal_in_batch = False
        self.attach(problem)

    # ---- pickling: the problem holds functions; it is attached again by the run loop -------------------
    def attach(self, problem: Problem) -> None:
        self._problem = problem

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state.pop("_problem", None)
        return state

    # ---- the loop ------------------------------------------------------------------------------------
    def done(self) -> bool:
        return self.iteration >= self.max_iterations or self.radius < self.min_radius or self.converged

    def ask(self) -> list[np.ndarray]:
        """The proposal (or, first, the centre) and the design points the model still lacks around it."""
        if self.proposal is None:
            first = [self.center]
        elif np.array_equal(self.proposal, self.center):
            first = []  # no step to try: only the missing design points (the centre is measured already)
        else:
            first = [self.proposal]
        self._proposal_in_batch = bool(first) and self.proposal is not None
        design = self._design(first[0] if first else self.center)
        if not first and not design:
            design = [np.clip(self.center + 0.5 * self.radius * axis, 0.0, 1.0) for axis in np.eye(self.center.size)]
        return first + design

    def tell(self, xs: Sequence[np.ndarray], results: Sequence[Result], losses: Sequence[float]) -> None:
        """Take the batch's results, run the ratio test on the proposal, refit and solve the next step."""
        model = self._problem.model
        assert model is not None
        for x, result, loss in zip(xs, results, losses):
            self.points.append(np.asarray(x, dtype=float))
            usable = "failed" not in result and not result.get("falls", 0)
            self.figures.append({k: float(result[k]) for k in model.figures} if usable else None)
            self.losses.append(float(loss))
        first_loss = float(losses[0])
        if self.proposal is None:
            self.center_loss = first_loss
        elif self._proposal_in_batch:
            actual = self.center_loss - first_loss
            predicted = self.predicted[0] - self.predicted[1] if self.predicted else 0.0
            self.last_ratio = actual / predicted if predicted > 1e-12 else (1.0 if actual > 0 else -1.0)
            step = float(np.max(np.abs(self.proposal - self.center)))
            if self.last_ratio >= ACCEPT_RATIO and actual > 0:
                self.center, self.center_loss = self.proposal, first_loss
            if self.last_ratio < SHRINK_RATIO:
                self.radius *= 0.5
            elif self.last_ratio > EXPAND_RATIO and step >= 0.9 * self.radius:
                self.radius = min(self.max_radius, 2.0 * self.radius)
        # A design point may beat the centre outright: move there (the model is refitted around it).
        best = int(np.argmin(self.losses))
        if self.losses[best] < self.center_loss:
            self.center, self.center_loss = self.points[best], self.losses[best]
        self.iteration += 1
        while not self.done():
            self._propose()
            if self.last_status == "too few points":
                break  # the next batch adds the missing design points
            if self.predicted is not None and self.last_ratio >= ACCEPT_RATIO and (
                    self.predicted[0] - self.predicted[1] < self.tolerance * max(1.0, abs(self.center_loss))):
                self.converged = True
                break
            if self.proposal is not None and np.max(np.abs(self.proposal - self.center)) > 1e-3 * self.radius:
                break
            self.radius *= 0.5  # the model sees no better point here: look closer

    def summary(self) -> dict[str, float | str]:
        return {"radius": round(self.radius, 6), "ratio": round(self.last_ratio, 4) if math.isfinite(
            self.last_ratio) else "nan", "solver": self.last_status}

    # ---- model and subproblem -------------------------------------------------------------------------
    def _near(self, around: np.ndarray, factor: float = 2.0) -> list[int]:
        return [i for i, x in enumerate(self.points)
                if self.figures[i] is not None and np.max(np.abs(x - around)) <= factor * self.radius + 1e-12]

    def _design(self, around: np.ndarray) -> list[np.ndarray]:
        """Points at half the radius along the directions the nearby points (and ``around``) leave unspanned."""
        n = around.size
        near = [self.points[i] for i in self._near(around)]
        displacement = np.array([(x - around) / self.radius for x in near]).reshape(-1, n)
        if displacement.shape[0]:
            _, singular, vt = np.linalg.svd(displacement, full_matrices=True)
            singular = np.concatenate([singular, np.zeros(n - singular.size)]) if singular.size < n else singular
        else:
            singular, vt = np.zeros(n), np.eye(n)
        points = []
        for k in range(n):
            if singular[k] >= POISED:
                continue
            direction = vt[k] / np.max(np.abs(vt[k]))
            step = 0.5 * self.radius * direction
            candidate = around + step
            if np.any(candidate > 1.0) or np.any(candidate < 0.0):
                candidate = around - step
            points.append(np.clip(candidate, 0.0, 1.0))
        return points

    def _fit(self, names: Sequence[str]) -> tuple[dict[str, np.ndarray], bool]:
        """Per figure, coefficients of a + g.d (+ 0.5 h.d^2) in d = (x - centre) / radius, fitted in CasADi
        (weighted ridge least squares: nearer points weigh more)."""
        indices = self._near(self.center)
        n = self.center.size
        d = np.array([(self.points[i] - self.center) / self.radius for i in indices]).reshape(-1, n)
        quadratic = len(indices) >= 2 * n + 1
        basis = np.hstack([np.ones((len(indices), 1)), d] + ([0.5 * d ** 2] if quadratic else []))
        weights = np.exp(-np.sum(d ** 2, axis=1) / 4.0)
        a = casadi.DM(basis)
        w = casadi.diag(casadi.DM(weights))
        normal = a.T @ w @ a + RIDGE * casadi.DM.eye(basis.shape[1])
        coefficients = {}
        for name in names:
            y = casadi.DM([self.figures[i][name] for i in indices])  # type: ignore[index]
            coefficients[name] = np.array(casadi.solve(normal, a.T @ w @ y)).ravel()
        return coefficients, quadratic

    def _propose(self) -> None:
        """Solve the subproblem on the models with IPOPT; its solution is the next proposal."""
        problem, model = self._problem, self._problem.model
        assert model is not None
        if len(self._near(self.center)) < self.center.size + 1:
            self.proposal, self.predicted, self.last_status = self.center, None, "too few points"
            return
        coefficients, quadratic = self._fit(model.figures)
        n = self.center.size
        x = casadi.SX.sym("x", n)
        d = (x - self.center) / self.radius
        figures = {}
        for name, c in coefficients.items():
            value = c[0] + casadi.dot(casadi.DM(c[1:n + 1]), d)
            if quadratic:
                value += 0.5 * casadi.dot(casadi.DM(c[n + 1:]), d ** 2)
            figures[name] = value
        values = {p.name: p.low + x[i] * (p.high - p.low) for i, p in enumerate(problem.parameters)}
        objective = model.loss(figures, values)
        constraints, lower, upper = [], [], []
        for expression, low, high in model.constraints(values):
            constraints.append(expression), lower.append(low), upper.append(high)
        for constraint in problem.constraints:
            if constraint.figure in figures:
                constraints.append(figures[constraint.figure])
                lower.append(constraint.low), upper.append(constraint.high)
        nlp = {"x": x, "f": objective, "g": casadi.vertcat(*constraints) if constraints else casadi.SX(0, 1)}
        solver = casadi.nlpsol("trust_region_step", "ipopt", nlp,
                               {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes",
                                "ipopt.max_iter": 200})
        lbx = np.maximum(0.0, self.center - self.radius)
        ubx = np.minimum(1.0, self.center + self.radius)
        solution = solver(x0=self.center, lbx=lbx, ubx=ubx, lbg=lower, ubg=upper)
        self.last_status = solver.stats()["return_status"]
        if not solver.stats()["success"]:
            logger.warning("IPOPT: %s at iteration %d (radius %.4f)", self.last_status, self.iteration, self.radius)
        proposal = np.clip(np.array(solution["x"]).ravel(), lbx, ubx)
        model_loss = casadi.Function("model_loss", [x], [objective], ["x"], ["loss"])
        self.predicted = (float(model_loss(self.center)), float(model_loss(proposal)))
        self.proposal = proposal


__all__ = ["TrustRegion"]
