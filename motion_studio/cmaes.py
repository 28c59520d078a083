"""A small CMA-ES (covariance matrix adaptation evolution strategy) for rough, noisy rollout objectives.

Written from Hansen's tutorial ("The CMA Evolution Strategy: A Tutorial", 2016, the (mu/mu_w, lambda)
algorithm with rank-one and rank-mu updates). It *minimises*; the search runs in a box normalised to
[0, 1]^n (the caller maps to its parameters), candidates are clipped into the box and pay a quadratic
penalty for the distance clipped away, so the mean does not drift outside. The whole state is plain data
(:meth:`CMAES.state` / :meth:`CMAES.from_state`), so a tuner can checkpoint it to JSON after every
generation and resume after a crash.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class CMAES:
    """CMA-ES state in the unit box.

    Args (of :meth:`create`): x0 start mean in [0, 1]^n; sigma0 initial step size (box units); popsize
    lambda (default 4 + 3 ln n); seed for the sampler.
    """

    mean: np.ndarray
    sigma: float
    cov: np.ndarray
    p_sigma: np.ndarray
    p_c: np.ndarray
    generation: int
    popsize: int
    seed: int

    @classmethod
    def create(cls, x0: np.ndarray, sigma0: float = 0.2, popsize: int | None = None, seed: int = 0) -> CMAES:
        x0 = np.clip(np.asarray(x0, dtype=float), 0.0, 1.0)
        n = x0.size
        if n < 1 or not 0.0 < sigma0:
            raise ValueError(f"CMA-ES needs n >= 1 and sigma0 > 0, got n={n}, sigma0={sigma0}")
        lam = popsize or 4 + int(3 * math.log(n))
        return cls(x0, float(sigma0), np.eye(n), np.zeros(n), np.zeros(n), 0, max(4, lam), seed)

    # ---- constants of the strategy (Hansen's defaults) -------------------------------------------------
    @property
    def _weights(self) -> np.ndarray:
        mu = self.popsize // 2
        w = np.log(mu + 0.5) - np.log(np.arange(1, mu + 1))
        return w / w.sum()

    def ask(self) -> list[np.ndarray]:
        """``popsize`` candidates in the box (clipped), drawn from this generation's distribution.

        Deterministic for a given state: the generator is seeded with (seed, generation), so a resumed run
        asks the same candidates.
        """
        rng = np.random.default_rng([self.seed, self.generation])
        eigenvalues, eigenvectors = np.linalg.eigh(self.cov)
        scale = eigenvectors * np.sqrt(np.maximum(eigenvalues, 1e-20))
        self._raw = [self.mean + self.sigma * scale @ rng.standard_normal(self.mean.size)
                     for _ in range(self.popsize)]
        return [np.clip(x, 0.0, 1.0) for x in self._raw]

    def tell(self, losses: list[float]) -> None:
        """Update from the losses of the last ``ask``'s candidates (same order; lower is better).

        A box penalty (squared distance clipped away, x 10) is added here, so callers pass the raw loss.
        """
        if len(losses) != self.popsize:
            raise ValueError(f"expected {self.popsize} losses, got {len(losses)}")
        raw = np.array(self._raw)
        penalty = 10.0 * np.sum((raw - np.clip(raw, 0.0, 1.0)) ** 2, axis=1)
        order = np.argsort(np.asarray(losses, dtype=float) + penalty)
        n = self.mean.size
        weights = self._weights
        mu = weights.size
        mu_eff = 1.0 / np.sum(weights ** 2)
        c_sigma = (mu_eff + 2) / (n + mu_eff + 5)
        d_sigma = 1 + 2 * max(0.0, math.sqrt((mu_eff - 1) / (n + 1)) - 1) + c_sigma
        c_c = (4 + mu_eff / n) / (n + 4 + 2 * mu_eff / n)
        c_1 = 2 / ((n + 1.3) ** 2 + mu_eff)
        c_mu = min(1 - c_1, 2 * (mu_eff - 2 + 1 / mu_eff) / ((n + 2) ** 2 + mu_eff))
        chi_n = math.sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n * n))

        selected = raw[order[:mu]]
        old_mean = self.mean
        self.mean = weights @ selected
        step = (self.mean - old_mean) / self.sigma
        eigenvalues, eigenvectors = np.linalg.eigh(self.cov)
        inv_sqrt = eigenvectors @ np.diag(1 / np.sqrt(np.maximum(eigenvalues, 1e-20))) @ eigenvectors.T
        self.p_sigma = (1 - c_sigma) * self.p_sigma + math.sqrt(c_sigma * (2 - c_sigma) * mu_eff) * inv_sqrt @ step
        norm = np.linalg.norm(self.p_sigma)
        h_sigma = norm / math.sqrt(1 - (1 - c_sigma) ** (2 * (self.generation + 1))) < (1.4 + 2 / (n + 1)) * chi_n
        self.p_c = (1 - c_c) * self.p_c + (h_sigma * math.sqrt(c_c * (2 - c_c) * mu_eff)) * step
        deviations = (selected - old_mean) / self.sigma
        rank_mu = (deviations.T * weights) @ deviations
        self.cov = ((1 - c_1 - c_mu) * self.cov + c_1 * (np.outer(self.p_c, self.p_c)
                    + (1 - h_sigma) * c_c * (2 - c_c) * self.cov) + c_mu * rank_mu)
        self.cov = (self.cov + self.cov.T) / 2
        self.sigma *= math.exp((c_sigma / d_sigma) * (norm / chi_n - 1))
        self.sigma = min(self.sigma, 1.0)
        self.mean = np.clip(self.mean, 0.0, 1.0)
        self.generation += 1

    def state(self) -> dict:
        """JSON-serialisable state."""
        return {"mean": self.mean.tolist(), "sigma": self.sigma, "cov": self.cov.tolist(),
                "p_sigma": self.p_sigma.tolist(), "p_c": self.p_c.tolist(), "generation": self.generation,
                "popsize": self.popsize, "seed": self.seed}

    @classmethod
    def from_state(cls, state: dict) -> CMAES:
        return cls(np.array(state["mean"], dtype=float), float(state["sigma"]), np.array(state["cov"], dtype=float),
                   np.array(state["p_sigma"], dtype=float), np.array(state["p_c"], dtype=float),
                   int(state["generation"]), int(state["popsize"]), int(state["seed"]))


__all__ = ["Dimension", "CMAES"]


@dataclass(frozen=True)
class Dimension:
    """One tuned parameter and its search bounds, mapped to and from the optimiser's [0, 1] box.

    Why shared: every tuner (gait, kick, stand-up) searches a box of named parameters, some of which only
    take whole numbers or multiples of a cycle (``step``: 1 for counts, 20 for millisecond durations).

    Args:
        name: the parameter (a dataclass field, or a dotted path the tuner resolves).
        low, high: bounds in the parameter's own unit.
        step: values are rounded to a multiple of it and returned as int (0 = continuous).
        decimals: rounding of continuous values (keeps parameter files readable).
    """

    name: str
    low: float
    high: float
    step: float = 0.0
    decimals: int = 4

    def to_unit(self, value: float) -> float:
        return min(1.0, max(0.0, (value - self.low) / (self.high - self.low)))

    def from_unit(self, unit: float) -> float:
        value = self.low + min(1.0, max(0.0, float(unit))) * (self.high - self.low)
        if self.step:
            return int(round(value / self.step) * self.step)
        return round(value, self.decimals)
