"""The agent's behaviour built from skills: each cycle the active skill asks for a motion, the motion
controller turns it into joint velocities. This is the ``Behavior`` that plugs into ``agent.Agent``.

Per-cycle order (why: the skill must see this cycle's world and what the controller did last cycle, and
the controller must get the skill's request before it computes the velocities):
1. fall watch (may replace the active skill with the stand-up);
2. the skill's ``step(world, motion)`` -> MotionRequest;
3. ``MotionController.update`` with this cycle's joint angles -> effector velocities.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from agent.motion import MotionController, MotionRequest, default_library, load_dynamic_params
from agent.protocol.effectors import Action, JointVelocity
from agent.skills.base import Skill
from agent.skills.standup import FallWatch, StandUp
from agent.world_model import WorldModel


class SkillBehavior:
    """A ``Behavior``: runs one skill at a time on a motion controller, with fall recovery.

    Args:
        controller: the motion controller (default: the shipped motions and dynamic elements for
            ``robot_type``).
        skill: the first skill (None: stand still).
        robot_type: 0-4.
        recover_falls: replace the active skill by the stand-up when a fall is confirmed, then resume it.
    """

    def __init__(self, controller: MotionController | None = None, skill: Skill | None = None, robot_type: int = 0,
                 recover_falls: bool = True) -> None:
        self.motion = controller or MotionController(default_library(robot_type), load_dynamic_params(),
                                                     robot_type)
        self.skill = skill
        self.recover_falls = recover_falls
        self.fall_watch = FallWatch()
        self.standup = StandUp()
        self.recovering = False
        self.on_cycle: Callable[[WorldModel, MotionRequest], None] | None = None
        """Called each cycle with the world and the request (for logs and benchmarks)."""

    def set_skill(self, skill: Skill | None) -> None:
        """Make ``skill`` the active skill (from the next cycle)."""
        self.skill = skill
        if skill is not None:
            skill.reset()

    def __call__(self, world: WorldModel) -> list[Action]:
        if not world.body.joints_rad:
            return []
        self.fall_watch.update(world)
        if self.recover_falls and not self.recovering and self.fall_watch.fallen:
            self.recovering = True
            self.standup.reset()
        if self.recovering:
            request = self.standup.step(world, self.motion)
            if self.standup.done:
                self.recovering = False
                self.fall_watch.reset()
                if self.skill is not None:
                    self.skill.reset()
        elif self.skill is not None:
            request = self.skill.step(world, self.motion)
        else:
            request = MotionRequest(None)
        if self.on_cycle is not None:
            self.on_cycle(world, request)
        self.motion.request(request)
        angles_deg = {name: math.degrees(value) for name, value in world.body.joints_rad.items()}
        velocities = self.motion.update(angles_deg, world.now_s, world.body.gyro_deg_s)
        return [JointVelocity(effector, value) for effector, value in velocities.items()]
