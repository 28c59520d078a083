"""The tasks of the Nao3D environments: what an episode rewards and when it ends.

Rewards read the world's true torso state (privileged, as rewards in simulation usually are); the agent's
observation stays what its perceptors give. Every figure is per 20 ms cycle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: REFERENCE §4.5: a torso centre below 0.25 m counts as not standing; the episode ends there.
FALLEN_TORSO_Z_M = 0.25
#: Weight of the effort penalty: the mean of (velocity / speed limit)² over the joints, so flailing at full
#: speed costs 0.01 a cycle, a tenth of what standing earns.
EFFORT_WEIGHT = 0.01
#: Walk: the per-cycle bonus for still standing (small, so that standing still does not pay as well as
#: walking at 0.1 m/s).
WALK_ALIVE_BONUS = 0.05


@dataclass(frozen=True)
class StepState:
    """What a task sees after a cycle: torso centre before and after [m] (field frame), the z component of
    the torso's up axis (1 upright), the cycle length [s] and the clipped action [rad/s] over its limits."""

    torso_before_m: np.ndarray
    torso_after_m: np.ndarray
    torso_up_z: float
    cycle_s: float
    action_ratio: np.ndarray


def fallen(state: StepState) -> bool:
    """True when the torso centre is below `FALLEN_TORSO_Z_M` (the episode is over)."""
    return bool(state.torso_after_m[2] < FALLEN_TORSO_Z_M)


def effort(state: StepState) -> float:
    """Mean squared joint velocity as a fraction of each joint's speed limit (0..1)."""
    return float(np.mean(np.square(state.action_ratio)))


def stand_reward(state: StepState) -> float:
    """Nao3D-Stand: the torso's up-axis z (1 per cycle upright, less when leaning) minus the effort penalty."""
    return state.torso_up_z - EFFORT_WEIGHT * effort(state)


def walk_reward(state: StepState) -> float:
    """Nao3D-Walk: torso speed along +x [m/s] (the opponent goal of the left team) plus a small bonus for
    standing, minus the effort penalty and the sideways speed [m/s]."""
    velocity = (state.torso_after_m - state.torso_before_m) / state.cycle_s
    return float(velocity[0] - abs(velocity[1])) + WALK_ALIVE_BONUS - EFFORT_WEIGHT * effort(state)


#: Task name -> reward of one cycle.
TASKS = {"stand": stand_reward, "walk": walk_reward}
