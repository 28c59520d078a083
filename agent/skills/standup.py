"""Stand up after a fall (REFERENCE §7.7): a fall is suspected from the gyro or the tilt, confirmed when the
feet carry no weight and the accelerometer says the torso lies; the stand-up motion for the side the robot
lies on plays; the foot pressure then says whether it worked, else it tries again.

Thresholds (numbers, not tuned curves): the seed agent's 100 °/s gyro trigger; lying = gravity less than
half along the torso's up axis; feet "carrying the robot" = mean FRP f_z above a third of its weight
(4.6 kg · 9.81 / 3 ≈ 15 N, summed over both feet), measured over the confirmation windows below.
"""

from __future__ import annotations

import math

from agent.motion import MotionController, MotionRequest
from agent.skills.base import Skill
from agent.world_model import WorldModel

#: |gyro x| + |gyro y| above this suggests a fall [deg/s] (seed agent: |gyro_y| + |gyro_z| > 100 in its axes).
GYRO_TRIGGER_DEG_S = 100.0
#: Torso up-axis z below this suggests a fall (REFERENCE §8.1's fall criterion).
UP_Z_TRIGGER = 0.6
#: Gravity along the torso's own up axis below this fraction of g = lying.
LYING_ACC_FRACTION = 0.5
#: Feet carry the robot when their summed vertical force averages above this [N].
FEET_LOADED_N = 15.0
#: Cycles of evidence before a fall is confirmed / a recovery is accepted.
CONFIRM_CYCLES = 6
RECOVERY_CYCLES = 15
#: Torso up-axis z above this after the stand-up = upright.
UPRIGHT_UP_Z = 0.85
GRAVITY_M_S2 = 9.81
#: Motions by the side the robot lies on.
STANDUP_MOTIONS = {"back": "standup_back", "front": "standup_front"}
#: Motion that rolls a robot lying on its side onto its back (a torso twist with the arms).
SIDE_ROLL_MOTION = "roll_to_back"


def feet_force_n(world: WorldModel) -> float:
    """Summed vertical (foot-axis z) force of all foot sensors touching this cycle [N]."""
    return sum(max(0.0, contact.force_n[2]) for contact in world.body.feet.values())


def lying_side(world: WorldModel) -> str | None:
    """"back", "front", "side" or None (not lying), from the accelerometer (torso axes: x right, y forward).

    Lying on the back the forward axis points up, so the proper acceleration has +g along y.
    """
    ax, ay, az = world.body.acc_m_s2
    if abs(az) > LYING_ACC_FRACTION * GRAVITY_M_S2 or math.hypot(ax, ay, az) < 0.5 * GRAVITY_M_S2:
        return None
    if abs(ay) >= abs(ax):
        return "back" if ay > 0 else "front"
    return "side"


class FallWatch:
    """Possible fall (gyro or tilt), confirmed by no weight on the feet and a lying accelerometer."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.suspected = False
        self.fallen = False
        self.side: str | None = None
        self._evidence = 0

    def update(self, world: WorldModel) -> None:
        body = world.body
        gx, gy, _ = body.gyro_deg_s
        if abs(gx) + abs(gy) > GYRO_TRIGGER_DEG_S or body.up_z < UP_Z_TRIGGER:
            self.suspected = True
        if not self.suspected or self.fallen:
            return
        side = lying_side(world)
        if side is not None and feet_force_n(world) < FEET_LOADED_N:
            self._evidence += 1
        else:
            self._evidence = 0
            if body.up_z > UPRIGHT_UP_Z and feet_force_n(world) >= FEET_LOADED_N:
                self.suspected = False  # a bump, not a fall
        if self._evidence >= CONFIRM_CYCLES:
            self.fallen, self.side = True, side


class StandUp(Skill):
    """Play the stand-up for the side the robot lies on until the feet carry it upright.

    ``done`` once the robot stands (FRP loaded and upright for RECOVERY_CYCLES after the motion);
    ``attempts`` counts the motions started.
    """

    name = "stand up"

    def __init__(self) -> None:
        super().__init__()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.attempts = 0
        self._playing: str | None = None
        self._completed_before = 0
        self._upright_cycles = 0
        self.state = "choose"

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        if self.state == "choose":
            side = lying_side(world)
            if side is None:
                if world.body.up_z > UPRIGHT_UP_Z:
                    self.state = "check"
                    return MotionRequest(None)
                side = "back" if world.body.acc_m_s2[1] > 0 else "front"
            name = SIDE_ROLL_MOTION if side == "side" and SIDE_ROLL_MOTION in motion.library else \
                STANDUP_MOTIONS["back" if side == "side" else side]
            self._playing = name
            self._completed_before = motion.completed[name]
            self.attempts += 1 if name != SIDE_ROLL_MOTION else 0
            self.state = "play"
            return MotionRequest(name, interrupt=True)
        if self.state == "play":
            assert self._playing is not None
            if motion.completed[self._playing] > self._completed_before:
                self.state = "choose" if self._playing == SIDE_ROLL_MOTION else "check"
                self._upright_cycles = 0
                return MotionRequest(None)
            return MotionRequest(self._playing)
        # check: the feet must carry an upright robot for a while, else try again
        if world.body.up_z > UPRIGHT_UP_Z and feet_force_n(world) >= FEET_LOADED_N:
            self._upright_cycles += 1
            if self._upright_cycles >= RECOVERY_CYCLES:
                self.done = True
        else:
            self._upright_cycles = 0
            if lying_side(world) is not None:
                self.state = "choose"
        return MotionRequest(None)
