"""Speed of the Nao3D environments: environment steps per second for one env and for vectorised envs.

Figures only (printed by ``motion-studio bench gym``), never assertions. One step is one 20 ms cycle. The
policy is seeded random joint velocities at a fifth of the speed limit (the robot sways, sometimes falls,
and the episode then resets as a learner's would); reset cycles are not counted as steps. Wall time is
what a user waits; CPU time is the same figure on an idle core (the two differ on a shared machine).
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import gymnasium
import numpy as np

import nao3d_gym  # noqa: F401  (registers the ids)

#: Issue 16's goal for one robot [env steps per wall second].
TARGET_STEPS_PER_S = 2000.0
ACTION_SCALE = 0.2


@dataclass(frozen=True)
class GymBenchResult:
    """One run: env id, vectorisation ("none", "sync", "async"), envs, env steps timed, wall and CPU seconds
    of this process (worker processes of async envs are not in ``cpu_s``), steps per wall second, steps
    per CPU second (None for async), episodes ended."""

    env_id: str
    mode: str
    num_envs: int
    steps: int
    wall_s: float
    cpu_s: float
    steps_per_s: float
    steps_per_cpu_s: float | None
    episodes_ended: int

    def as_dict(self) -> dict:
        return asdict(self)


def run_single(env_id: str = "Nao3D-Stand-v0", steps: int = 2000, seed: int = 0) -> GymBenchResult:
    """Time ``steps`` steps of one environment (resets after falls not counted)."""
    env = gymnasium.make(env_id)
    rng = np.random.default_rng(seed)
    high = env.action_space.high * ACTION_SCALE
    env.reset(seed=seed)
    actions = rng.uniform(-high, high, (steps, high.size)).astype(np.float32)
    ended = 0
    wall, cpu = 0.0, 0.0
    for action in actions:
        wall_start, cpu_start = time.perf_counter(), time.process_time()
        _, _, terminated, truncated, _ = env.step(action)
        wall += time.perf_counter() - wall_start
        cpu += time.process_time() - cpu_start
        if terminated or truncated:
            ended += 1
            env.reset()
    env.close()
    return GymBenchResult(env_id, "none", 1, steps, wall, cpu, steps / wall, steps / max(cpu, 1e-9), ended)


def run_vector(env_id: str = "Nao3D-Stand-v0", num_envs: int = 8, steps: int = 250, mode: str = "async",
               seed: int = 0) -> GymBenchResult:
    """Time ``steps`` vector steps of ``num_envs`` environments (gymnasium's Sync/AsyncVectorEnv, which reset
    ended episodes themselves: those resets are inside the timed steps)."""
    envs = gymnasium.make_vec(env_id, num_envs=num_envs, vectorization_mode=mode)
    rng = np.random.default_rng(seed)
    high = envs.single_action_space.high * ACTION_SCALE
    envs.reset(seed=seed)
    actions = rng.uniform(-high, high, (steps, num_envs, high.size)).astype(np.float32)
    ended = 0
    wall_start, cpu_start = time.perf_counter(), time.process_time()
    for action in actions:
        _, _, terminated, truncated, _ = envs.step(action)
        ended += int(np.count_nonzero(terminated | truncated))
    wall, cpu = time.perf_counter() - wall_start, time.process_time() - cpu_start
    envs.close()
    total = steps * num_envs
    per_cpu = total / max(cpu, 1e-9) if mode == "sync" else None
    return GymBenchResult(env_id, mode, num_envs, total, wall, cpu, total / wall, per_cpu, ended)
