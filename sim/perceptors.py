"""The body perceptors of REFERENCE §2.3/§3.4 for one robot, as `agent.protocol` values.

Values and frames: HJ in degrees (SimSpark sign); GYR = torso angular velocity in torso axes (x right,
y forward, z up) in deg/s; ACC = proper acceleration of the torso in torso axes, m/s² ((0, 0, 9.81) at
rest; sampled before the physics step, see `sim.world`); FRP per foot with contact: |f|-weighted mean
contact point relative to the foot box centre and the summed force, both in foot axes. Joints are listed
in the server's wire order (REFERENCE §3.3: hj1 hj2, right arm, left arm, right leg, left leg; the toe
joint of type 4 after each ankle roll, unverified); `agent.protocol.format_sense` places See and FRP.

`body_sense` is the typed path (tests compare against it); the engine writes the same bytes straight from the
world's arrays (`sim.world.World.perceptor_rows`) with `agent.protocol.sense_template`, because building a
`Sense` of dataclasses per robot and cycle cost more than the physics.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

import numpy as np

from agent.protocol.perceptors import (Accelerometer, ForceResistance, GameState, Gyro, Hear, See, Sense,
                                       TimePerceptor)
from kinematics.spec import robot_spec

_WIRE_GROUPS = ("hj", "raj", "laj", "rlj", "llj")


@lru_cache(maxsize=None)
def wire_joint_order(robot_type: int) -> tuple[tuple[str, ...], np.ndarray]:
    """(wire names in sense-message order, their indices in the spec's joint order) for a robot type."""
    names = [j.perceptor for j in robot_spec(robot_type).joints]
    ordered = [name for group in _WIRE_GROUPS for name in names if name.rstrip("0123456789") == group]
    return tuple(ordered), np.array([names.index(n) for n in ordered], dtype=np.intp)


def body_sense(now_s: float, game_state: GameState, hears: Sequence[Hear], gyro_deg_s: list[float],
               acc_m_s2: list[float], joint_names: tuple[str, ...], joint_deg: list[float],
               frp: dict[str, tuple[np.ndarray, np.ndarray]], see: See | None) -> Sense:
    """One robot's sense message content (format it with `agent.protocol.format_sense`).

    Args:
        now_s: server time [s]; game_state: the GS perceptor; hears: this cycle's hears in order;
        gyro_deg_s, acc_m_s2: torso rates and acceleration (x, y, z); joint_names / joint_deg: wire order;
        frp: sensor name -> (contact point [m], force [N]) for feet with contact; see: vision or None.
    """
    return Sense(TimePerceptor(now_s), game_state, Gyro("torso", tuple(gyro_deg_s)),  # type: ignore[arg-type]
                 Accelerometer("torso", tuple(acc_m_s2)), dict(zip(joint_names, joint_deg)),  # type: ignore[arg-type]
                 {name: ForceResistance(name, tuple(point.tolist()), tuple(force.tolist()))  # type: ignore[arg-type]
                  for name, (point, force) in frp.items()},
                 tuple(hears), see)
