"""Skill scenarios on our simulator: one robot running our agent with a skill, observed through the world's
ground truth. Used by the scenario tests and the skill benchmarks.

The robot is a real ``agent.Agent`` hosted in-process by ``sim.inprocess.InProcessHost`` on a
``sim.engine.SimEngine`` (the bytes of a TCP match) with ``FrozenReferee`` (no rules: BeforeKickOff, beam
allowed); after connecting it is moved to the scenario's spot, so the scenario does not depend on the
formation. Truth per cycle: torso position, up-axis z, heading, ball position.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from agent.agent import Agent, AgentConfig
from agent.motion import MotionController
from agent.skills.base import Skill
from agent.skills.behavior import SkillBehavior
from sim.engine import FrozenReferee, SimEngine
from sim.inprocess import InProcessHost

#: Cycles for scene, init and beam before the robot is moved to its spot.
CONNECT_CYCLES = 6
#: REFERENCE §8.1: fallen when the torso's up axis z < 0.6 or the torso centre is below 0.25 m.
FALL_UP_Z = 0.6
FALL_TORSO_Z_M = 0.25


@dataclass
class Truth:
    """Ground truth of one cycle."""

    time_s: float
    torso_m: tuple[float, float, float]
    up_z: float
    heading_deg: float
    ball_m: tuple[float, float, float]
    feet_off_ground: bool

    @property
    def fallen(self) -> bool:
        return self.up_z < FALL_UP_Z or self.torso_m[2] < FALL_TORSO_Z_M


@dataclass
class Scenario:
    """One robot on the field with a skill.

    Args:
        skill: the skill to run (None: stand still).
        position_m: (x, y) of the torso in the field frame; heading_deg: 0 = facing +x (opponent goal).
        robot_type: 0-4; seed: the engine's random seed.
        controller: a motion controller (default: shipped motions and dynamic elements).
        recover_falls: whether the agent stands up by itself after a fall.
        ball_m: where to put the ball (None: leave it at the centre spot).
    """

    skill: Skill | None = None
    position_m: tuple[float, float] = (-5.0, 0.0)
    heading_deg: float = 0.0
    robot_type: int = 0
    seed: int = 0
    controller: MotionController | None = None
    recover_falls: bool = True
    ball_m: tuple[float, float] | None = None
    history: list[Truth] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.engine = SimEngine(seed=self.seed, referee=FrozenReferee())
        self.host = InProcessHost(self.engine)
        self.behavior = SkillBehavior(self.controller, self.skill, self.robot_type, self.recover_falls)
        self.agent = Agent(AgentConfig("Bench", 1, self.robot_type, say=False), self.behavior)
        self.key = self.host.add(self.agent)
        self.host.run(CONNECT_CYCLES)
        self.place(self.position_m, self.heading_deg)
        if self.ball_m is not None:
            self.place_ball(self.ball_m)

    @property
    def world(self):  # sim.world.World
        return self.engine.world

    def place(self, position_m: tuple[float, float], heading_deg: float) -> None:
        """Move the robot upright to a spot (as beam does; joints kept, velocities zeroed)."""
        self.world.place_robot(self.key, position_m[0], position_m[1], heading_deg)

    def place_ball(self, position_m: tuple[float, float]) -> None:
        self.world.set_ball((position_m[0], position_m[1], 0.042))

    def lay_down(self, side: str, yaw_deg: float = 0.0, twist_deg: float = 0.0) -> None:
        """Put the robot on its ``back`` or ``front`` on the ground (see ``lay_robot_down``)."""
        lay_robot_down(self.world, self.key, side, yaw_deg, twist_deg)

    def push(self, velocity_m_s: tuple[float, float, float], angular_rad_s: tuple[float, float, float] = (0, 0, 0)) -> None:
        """Add to the torso's velocity (field frame), e.g. to knock the robot over."""
        robot = self.world.by_key[self.key]
        dof = robot.root_dof
        self.world.data.qvel[dof:dof + 3] += velocity_m_s
        self.world.data.qvel[dof + 3:dof + 6] += angular_rad_s

    def truth(self) -> Truth:
        world = self.world
        rotation = world.torso_rotation(self.key)
        feet = world.foot_forces(self.key)
        off = all(float(np.linalg.norm(force)) < 0.01 for _, force in feet.values()) if feet else True
        return Truth(self.engine.time_s, tuple(world.torso_position(self.key).tolist()), float(rotation[2, 2]),
                     world.heading_deg(self.key), world.ball_position(), off)

    def run(self, cycles: int, stop: Callable[[Truth], bool] | None = None) -> list[Truth]:
        """Step ``cycles`` cycles (or until ``stop(truth)``); returns this run's truths (also in history)."""
        out = []
        for _ in range(cycles):
            self.host.run(1)
            truth = self.truth()
            out.append(truth)
            self.history.append(truth)
            if stop is not None and stop(truth):
                break
        return out

    def set_skill(self, skill: Skill | None) -> None:
        self.behavior.set_skill(skill)


def lay_robot_down(world, key, side: str, yaw_deg: float = 0.0, twist_deg: float = 0.0) -> None:  # noqa: ANN001
    """Put robot ``key`` of ``world`` (a ``sim.world.World``) on its ``back`` or ``front`` on the ground, joints
    as they are, at rest: the lying start of the stand-up scenarios, benchmarks and ``motion-studio play``.

    ``twist_deg`` turns it about its own long (up) axis first, so that it lies partly on a side
    (+ = its right side lower when lying on the back).

    Raises:
        ValueError: ``side`` is neither back nor front.
    """
    if side not in ("back", "front"):
        raise ValueError(f"side must be 'back' or 'front', got {side!r}")
    robot = world.by_key[key]
    position = world.torso_position(key)
    q = world.data.qpos
    a = robot.root_qadr
    # Body forward axis +y; lying on the back = rotated +90° about the body x axis (chest up).
    pitch = math.pi / 2 if side == "back" else -math.pi / 2
    yaw = math.radians(yaw_deg - 90.0)
    twist = math.radians(twist_deg)
    qyaw = np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
    qpitch = np.array([math.cos(pitch / 2), math.sin(pitch / 2), 0.0, 0.0])
    qtwist = np.array([math.cos(twist / 2), 0.0, 0.0, math.sin(twist / 2)])
    q[a:a + 3] = (position[0], position[1], 0.12)
    q[a + 3:a + 7] = _quat_mul(_quat_mul(qyaw, qpitch), qtwist)
    world.data.qvel[robot.root_dof:robot.root_dof + 6] = 0.0
    import mujoco
    mujoco.mj_kinematics(world.model, world.data)


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])
