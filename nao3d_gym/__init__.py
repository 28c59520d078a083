"""Gymnasium environments over the in-process SimSpark world: one Nao, 20 ms steps, no real server needed.

Importing this package registers the environments (``gymnasium.make("Nao3D-Stand-v0")``);
``gymnasium.make("nao3d_gym:Nao3D-Walk-v0")`` imports it on the way. Ids, tasks and episode lengths:

* ``Nao3D-Stand-v0``: keep standing for 10 s (500 steps); reward `nao3d_gym.tasks.stand_reward`.
* ``Nao3D-Walk-v0``: walk toward +x for 20 s (1000 steps); reward `nao3d_gym.tasks.walk_reward`.

Both end early when the robot falls (torso centre below 0.25 m). Keyword arguments of `Nao3DEnv`
(``robot_type``, ``settle_cycles``, ``init_noise_rad``) pass through ``gymnasium.make``.
"""

from __future__ import annotations

import gymnasium

from nao3d_gym.env import Nao3DEnv

#: id -> (task, steps per episode).
ENVIRONMENTS = {"Nao3D-Stand-v0": ("stand", 500), "Nao3D-Walk-v0": ("walk", 1000)}


def register_environments() -> None:
    """Register every id of `ENVIRONMENTS` once (importing the package calls it)."""
    for env_id, (task, steps) in ENVIRONMENTS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(env_id, entry_point="nao3d_gym.env:Nao3DEnv", max_episode_steps=steps,
                               kwargs={"task": task})


register_environments()

__all__ = ["ENVIRONMENTS", "Nao3DEnv", "register_environments"]
