"""The stand-up tuner's rollout backend on the real rcssserver3d (``motion-studio tune standup --backend real``),
optionally judged on our simulator as well (``--backend both``).

Each candidate (``StandUpParams``) is built into its motion once per real start (with the start's parameter
noise, as on the MuJoCo backend), and every (candidate, start) rollout of a generation goes to the worker pool
at once (``standup_pool.RolloutPool``: one real server per worker, each in its own loopback namespace, reset
between rollouts by trainer commands). With ``both``, our simulator judges the candidates meanwhile, in other
processes, from the MuJoCo tuner's own lying starts (``tune_standup.default_starts``: laid down from the walk
stance or a seeded pose near it, yawed, twisted and nudged, as the stand-up benchmark and the scenario tests
lay the robot down). A real rollout's loss is ``tune_standup.Rollout.loss`` of its figures (time to stand from
the motion's start, else how far from standing it stayed); a candidate's loss is the mean over the real
starts plus ``sim_weight`` x its MuJoCo loss (``tune_standup.evaluate``).
"""

from __future__ import annotations

from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from motion_studio.realserver.rollout_standup import RealStart, StandUpOutcome, real_starts, transfer_starts
from motion_studio.realserver.standup_pool import RolloutPool, RolloutRequest
from motions.authoring.standup import STANDUPS, SagittalSolver, StandUpParams, build_standup, stance_params
from kinematics.child_process import end_with_parent

#: Backends of the stand-up tuner besides the default in-process MuJoCo one.
BACKENDS = ("real", "both")


def rollout_loss(outcome: StandUpOutcome | None, target_s: float, time_weight: float) -> float:
    """``tune_standup.Rollout.loss`` of one outcome (a rollout the pool failed twice counts as the worst)."""
    from motion_studio.tune_standup import FAIL_LOSS, Rollout

    if outcome is None:
        return 2 * FAIL_LOSS + 6.0
    return Rollout(outcome.time_s, outcome.final_score, outcome.best_score, outcome.min_up_z,
                   outcome.self_collisions, 0, outcome.best_feet_load, target_s, time_weight).loss


def _mujoco_loss(packed: tuple) -> dict[str, object]:
    from motion_studio.tune_standup import evaluate

    return evaluate(*packed)


@dataclass
class RealEvaluator:
    """Judges candidates of one stand-up on the real server (and on ours).

    Args:
        section: ``standup_back`` or ``standup_front``.
        starts: the real lying starts (``real_starts``); a start's ``noise_seed`` puts noise on the candidate.
        pool: the worker pool.
        target_s, time_weight: the late-stand term of the loss (``tune_standup.Rollout``).
        mujoco_starts: ``tune_standup.Start``s judged on our simulator too (empty: the real server alone).
        sim_weight: weight of our simulator's loss.
        executor: where the MuJoCo rollouts run (default: the caller's process, after the real batch).
    """

    section: str
    starts: tuple[RealStart, ...]
    pool: RolloutPool
    target_s: float = 6.0
    time_weight: float = 0.0
    mujoco_starts: tuple = ()
    sim_weight: float = 1.0
    executor: Executor | None = None
    stance: object = field(default_factory=stance_params)
    use_skill: bool = False
    """The agent's StandUp skill plays the candidate (fall detection, rest, retries), as the transfer does."""
    sim_too: bool = False
    """The same starts on our simulator as well (the pool's ``sim`` world), weighted by ``sim_weight``."""
    robot_type: int = 0
    """The robot type playing the candidates (their crouch and rise solved with its kinematics)."""

    def evaluate(self, candidates: list[StandUpParams]) -> list[dict[str, object]]:
        """Loss and per-world figures of each candidate (a pose out of reach is a failed candidate)."""
        from motion_studio.tune_standup import FAIL_LOSS, noisy

        side = STANDUPS[self.section]
        # ours first, in other processes, so that it runs while the real server works
        packed = [(self.section, params, self.mujoco_starts, self.target_s, self.time_weight, self.robot_type)
                  for params in candidates]
        solver = SagittalSolver(self.robot_type)
        pending = ([self.executor.submit(_mujoco_loss, p) for p in packed]
                   if self.mujoco_starts and self.executor is not None else [])
        requests: list[RolloutRequest] = []
        owners: list[int] = []
        errors: dict[int, str] = {}
        for index, params in enumerate(candidates):
            try:
                motions = [build_standup(self.section, params if start.noise_seed is None else
                                         noisy(params, start.noise_seed), side, self.stance, solver=solver)
                           for start in self.starts]
            except ValueError as error:
                errors[index] = str(error)
                continue
            for world in ("real", "sim") if self.sim_too else ("real",):
                requests += [RolloutRequest({self.section: motion}, self.section, start, self.use_skill, world,
                                            robot_type=self.robot_type)
                             for start, motion in zip(self.starts, motions)]
                owners += [index] * len(motions)
        outcomes = self.pool.run(requests)
        ours = ([future.result() for future in pending] if pending else
                [_mujoco_loss(p) for p in packed] if self.mujoco_starts else [])
        per: dict[int, list[StandUpOutcome | None]] = {}
        per_sim: dict[int, list[StandUpOutcome | None]] = {}
        for owner, outcome, request in zip(owners, outcomes, requests):
            (per if request.world == "real" else per_sim).setdefault(owner, []).append(outcome)
        results = []
        for index in range(len(candidates)):
            if index in errors:
                results.append({"loss": 2 * FAIL_LOSS + 6.0, "error": errors[index]})
                continue
            runs = per[index]
            losses = [rollout_loss(run, self.target_s, self.time_weight) for run in runs]
            result: dict[str, object] = {
                "loss": float(np.mean(losses)), "times_s": [run.time_s if run else None for run in runs],
                "real": {"losses": [round(v, 3) for v in losses],
                         "self_collisions": [run.self_collisions if run else None for run in runs]}}
            if ours:
                result["loss"] = float(result["loss"]) + self.sim_weight * float(ours[index]["loss"])
                result["mujoco"] = ours[index]
            if index in per_sim:
                sims = per_sim[index]
                sim_losses = [rollout_loss(run, self.target_s, self.time_weight) for run in sims]
                result["loss"] = float(result["loss"]) + self.sim_weight * float(np.mean(sim_losses))
                result["sim"] = {"losses": [round(v, 3) for v in sim_losses],
                                 "times_s": [run.time_s if run else None for run in sims]}
            results.append(result)
        return results

    def close(self) -> None:
        self.pool.close()
        if self.executor is not None:
            self.executor.shutdown()


def make_evaluator(section: str, backend: str, count: int, seed: int, noise: bool, workers: int,
                   target_s: float, time_weight: float, sim_weight: float = 1.0,
                   mujoco_starts: tuple = (), transfer: bool = False, robot_type: int = 0) -> RealEvaluator:
    """The evaluator of ``backend`` ("real", or "both" with ``mujoco_starts``) with ``count`` real starts on the
    section's side (``transfer``: the lying starts of ``motion-studio transfer --seed seed``, no noise, the
    StandUp skill playing the candidate as there; with "both" ours plays them too) and
    ``workers`` real servers (and as many MuJoCo processes); ``robot_type``: the robot playing them."""
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; known: mujoco, {', '.join(BACKENDS)}")
    ours = tuple(mujoco_starts) if backend == "both" else ()
    sim_too = backend == "both" and transfer  # ours on the transfer's starts too (the pool's sim world)
    pool = ProcessPoolExecutor(workers, initializer=end_with_parent) if ours else None  # workers die with us
    starts = (transfer_starts(STANDUPS[section], count, seed) if transfer
              else real_starts(STANDUPS[section], count, seed, noise))
    return RealEvaluator(section, starts, RolloutPool(workers),
                         target_s, time_weight, ours, sim_weight, pool, use_skill=transfer, sim_too=sim_too,
                         robot_type=robot_type)
