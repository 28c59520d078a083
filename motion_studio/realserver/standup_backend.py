"""The stand-up tuner's rollout backend on the real rcssserver3d (``motion-studio tune standup --backend real``),
optionally judged on our simulator too from the same lying starts (``--backend both``).

Each candidate (``StandUpParams``) is built into its motion once per start (with the start's parameter noise,
as on the MuJoCo backend), and every (candidate, start) rollout of a generation goes to the worker pool at
once (``standup_pool.RolloutPool``: one real server per worker, each in its own loopback namespace, reset
between rollouts by trainer commands). A rollout's loss is ``motion_studio.tune_standup.Rollout.loss`` of its
figures (time to stand from the motion's start, else how far from standing it stayed); a candidate's loss is
the mean over the starts, summed over the worlds (``both``: real + ``sim_weight`` x ours).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from motion_studio.realserver.rollout_standup import RealStart, StandUpOutcome, real_starts
from motion_studio.realserver.standup_pool import RolloutPool, RolloutRequest
from motions.authoring.standup import STANDUPS, StandUpParams, build_standup, stance_params

#: Backends of the stand-up tuner besides the default in-process MuJoCo one: worlds judged.
WORLDS = {"real": ("real",), "both": ("real", "sim")}


def rollout_loss(outcome: StandUpOutcome | None, target_s: float, time_weight: float) -> float:
    """``tune_standup.Rollout.loss`` of one outcome (a rollout the pool failed twice counts as the worst)."""
    from motion_studio.tune_standup import FAIL_LOSS, Rollout

    if outcome is None:
        return 2 * FAIL_LOSS + 6.0
    return Rollout(outcome.time_s, outcome.final_score, outcome.best_score, outcome.min_up_z,
                   outcome.self_collisions, 0, outcome.best_feet_load, target_s, time_weight).loss


@dataclass
class RealEvaluator:
    """Judges candidates of one stand-up on the real server (and ours).

    Args:
        section: ``standup_back`` or ``standup_front``.
        starts: the lying starts (``real_starts``); a start's ``noise_seed`` puts noise on the candidate.
        pool: the worker pool.
        worlds: ("real",) or ("real", "sim").
        target_s, time_weight: the late-stand term of the loss (``tune_standup.Rollout``).
        sim_weight: weight of our simulator's mean loss when both are judged.
        sim_starts: how many of the starts our simulator plays (None: all).
    """

    section: str
    starts: tuple[RealStart, ...]
    pool: RolloutPool
    worlds: tuple[str, ...] = ("real",)
    target_s: float = 6.0
    time_weight: float = 0.0
    sim_weight: float = 1.0
    sim_starts: int | None = None
    stance: object = field(default_factory=stance_params)

    def evaluate(self, candidates: list[StandUpParams]) -> list[dict[str, object]]:
        """Loss and per-world figures of each candidate (a pose out of reach is a failed candidate)."""
        from motion_studio.tune_standup import FAIL_LOSS, noisy

        side = STANDUPS[self.section]
        requests: list[RolloutRequest] = []
        owners: list[tuple[int, str]] = []
        errors: dict[int, str] = {}
        for index, params in enumerate(candidates):
            motions = []
            try:
                for start in self.starts:
                    candidate = params if start.noise_seed is None else noisy(params, start.noise_seed)
                    motions.append(build_standup(self.section, candidate, side, self.stance))
            except ValueError as error:
                errors[index] = str(error)
                continue
            for world in self.worlds:
                count = self.sim_starts if world == "sim" and self.sim_starts is not None else len(self.starts)
                for start, motion in list(zip(self.starts, motions))[:count]:
                    requests.append(RolloutRequest({self.section: motion}, self.section, start, world=world))
                    owners.append((index, world))
        outcomes = self.pool.run(requests)
        per: dict[tuple[int, str], list[StandUpOutcome | None]] = {}
        for owner, outcome in zip(owners, outcomes):
            per.setdefault(owner, []).append(outcome)
        results = []
        for index in range(len(candidates)):
            if index in errors:
                results.append({"loss": 2 * FAIL_LOSS + 6.0, "error": errors[index]})
                continue
            result: dict[str, object] = {"loss": 0.0}
            for world in self.worlds:
                runs = per[(index, world)]
                losses = [rollout_loss(run, self.target_s, self.time_weight) for run in runs]
                weight = self.sim_weight if world == "sim" else 1.0
                result["loss"] = float(result["loss"]) + weight * float(np.mean(losses))
                result[world] = {"losses": [round(v, 3) for v in losses],
                                 "times_s": [run.time_s if run else None for run in runs],
                                 "self_collisions": [run.self_collisions if run else None for run in runs]}
            result["times_s"] = result["real"]["times_s"]
            results.append(result)
        return results


def make_evaluator(section: str, backend: str, count: int, seed: int, noise: bool, workers: int,
                   target_s: float, time_weight: float, sim_weight: float = 1.0,
                   sim_starts: int | None = None) -> RealEvaluator:
    """The evaluator of ``backend`` ("real" or "both") with ``count`` starts on the section's side."""
    if backend not in WORLDS:
        raise ValueError(f"unknown backend {backend!r}; known: mujoco, {', '.join(WORLDS)}")
    pool = RolloutPool(workers)
    return RealEvaluator(section, real_starts(STANDUPS[section], count, seed, noise), pool, WORLDS[backend],
                         target_s, time_weight, sim_weight, sim_starts)
