"""CMA-ES from pycma (``cma``) on the unit box, for rough objectives (kicks, stand-ups, gaits).

Why a wrapper: the run loop speaks ``ask``/``tell`` on [0, 1]^n and checkpoints the optimizer by pickling
it (pycma's own way to save a run). pycma draws its samples from the ``randn`` option; ours is a seeded
generator that pickles with the strategy, so a run resumed from its checkpoint asks exactly the candidates
the killed run would have asked (the global NumPy generator, which other code may touch, plays no part).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import cma
import numpy as np

from motion_studio.tuning.errors import TuningError
from motion_studio.tuning.problem import Result


class SeededNormal:
    """pycma's ``randn`` option: standard normal samples of a given shape from our own generator."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def __call__(self, *shape: int) -> np.ndarray:
        return self.rng.standard_normal(shape)


class CMAES:
    """pycma's CMA-ES minimising in the box [0, 1]^n.

    Args:
        x0: start mean in [0, 1]^n.
        sigma0: initial step size [box units].
        popsize: candidates per iteration (default pycma's 4 + 3 ln n).
        seed: seed of the sampler.
        max_iterations: ``done`` after this many iterations.

    Raises:
        TuningError: an empty start or a step size that is not positive.
    """

    name = "cma-es"

    def __init__(self, x0: Sequence[float], sigma0: float = 0.2, popsize: int | None = None, seed: int = 0,
                 max_iterations: int = 100) -> None:
        x0 = np.clip(np.asarray(x0, dtype=float), 0.0, 1.0)
        if x0.size < 1 or not (sigma0 > 0.0 and math.isfinite(sigma0)):
            raise TuningError(f"CMA-ES needs at least one parameter and sigma0 > 0, got n={x0.size}, sigma0={sigma0}")
        options = {"bounds": [0.0, 1.0], "seed": seed + 1, "randn": SeededNormal(seed), "verbose": -9,
                   "verb_log": 0, "verb_disp": 0, "tolx": 1e-6, "tolfun": 0.0, "tolflatfitness": 10**9}
        if popsize:
            options["popsize"] = max(2, int(popsize))
        if x0.size == 1:
            # pycma refuses one dimension; a second, ignored axis keeps the same algorithm.
            x0 = np.append(x0, 0.5)
            self._pad = True
        else:
            self._pad = False
        self.es = cma.CMAEvolutionStrategy(x0, float(sigma0), options)
        self.max_iterations = max_iterations

    @property
    def iteration(self) -> int:
        return int(self.es.countiter)

    @property
    def popsize(self) -> int:
        return int(self.es.popsize)

    @property
    def sigma(self) -> float:
        return float(self.es.sigma)

    @property
    def mean(self) -> np.ndarray:
        mean = np.clip(np.asarray(self.es.mean, dtype=float), 0.0, 1.0)
        return mean[:-1] if self._pad else mean

    def done(self) -> bool:
        return self.iteration >= self.max_iterations

    def ask(self) -> list[np.ndarray]:
        """``popsize`` candidates in the box; the same ones again for the same (pickled) state."""
        self._asked = self.es.ask()
        return [np.clip(np.asarray(x[:-1] if self._pad else x, dtype=float), 0.0, 1.0) for x in self._asked]

    def tell(self, xs: Sequence[np.ndarray], results: Sequence[Result], losses: Sequence[float]) -> None:
        """Update from the losses of the last ``ask``'s candidates (same order; lower is better)."""
        if len(losses) != len(self._asked):
            raise TuningError(f"CMA-ES expected {len(self._asked)} losses, got {len(losses)}")
        self.es.tell(self._asked, [float(v) for v in losses])

    def summary(self) -> dict[str, float]:
        """What the trace records of the strategy after an iteration."""
        return {"sigma": round(self.sigma, 6)}


__all__ = ["CMAES", "SeededNormal"]
