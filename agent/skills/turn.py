"""Turning in place: turn by an angle or until facing a field point, with the turn motions and the turn gain.

One turn motion (``turn_left`` / ``turn_right``) makes one turn whose size the gain sets (REFERENCE §7.3);
the controller maps a requested per-motion turn [deg] to a gain with the turn-gain curve
(``motions/params/dynamic_elements.toml`` ``[turn_gain]``), whose inverse predicts the turn a motion makes.
A request beyond one motion's range is split into equal parts, one motion each. Between two motions the
skill looks at its beliefs again, so each new motion turns by what is still missing.

Beliefs only (never the simulator's truth): :class:`TurnToFace` takes the bearing of its point from the
localized pose (and waits while there is none); :class:`TurnBy` plans by the curve's predictions and
measures the turn made with the localizer's heading, the gyro's yaw filling its gaps.
"""

from __future__ import annotations

import math

from agent.motion import MotionController, MotionRequest
from agent.motion.dynamic import TurnGain
from agent.skills.base import Skill
from agent.world.frames import wrap_angle_rad
from agent.world_model import WorldModel

#: The turn motions by direction (+ = left).
TURN_MOTIONS = {"left": "turn_left", "right": "turn_right"}
#: Default tolerance on the final heading [deg].
TOLERANCE_DEG = 5.0
#: Correction motions allowed after the planned ones (a guard against endless corrections).
MAX_CORRECTIONS = 4


def split_turn(turn_deg: float, curve: TurnGain) -> list[float]:
    """Per-motion turns [deg] (signed like ``turn_deg``) for a requested turn: the fewest equal parts that
    one motion each can make at a gain <= 1 (the curve's turn at gain 1)."""
    largest = curve.predicted_turn_deg(1.0)
    if largest <= 0.0:
        raise ValueError(f"the turn-gain curve predicts no turn at gain 1 ({largest} deg)")
    parts = max(1, math.ceil(abs(turn_deg) / largest - 1e-9))
    return [turn_deg / parts] * parts


def predicted_turn_deg(turn_deg: float, curve: TurnGain) -> float:
    """Turn [deg] that one motion requested with ``turn_deg`` makes by the curve (signed like the request)."""
    return math.copysign(curve.predicted_turn_deg(curve.gain(turn_deg)), turn_deg)


class _TurnSkill(Skill):
    """Shared part: one turn motion at a time; between motions ``_remaining_deg`` says what is missing."""

    def __init__(self, tolerance_deg: float, max_motions: int | None) -> None:
        super().__init__()
        if tolerance_deg <= 0.0:
            raise ValueError(f"tolerance_deg must be > 0, got {tolerance_deg}")
        self.tolerance_deg = tolerance_deg
        self.max_motions = max_motions
        self.motions_played = 0
        """Turn motions started since the reset."""
        self.predicted_deg = 0.0
        """Sum of the turns the curve predicts for the motions started (+ = left) [deg]."""
        self._playing: MotionRequest | None = None
        self._seen_playing = False

    def reset(self) -> None:
        super().reset()
        self.motions_played = 0
        self.predicted_deg = 0.0
        self._playing = None
        self._seen_playing = False

    def _remaining_deg(self, world: WorldModel, curve: TurnGain) -> float | None:
        """Turn still missing (+ = left) [deg]; None = cannot tell yet (wait)."""
        raise NotImplementedError

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        self._observe(world)
        if self._playing is not None:
            if motion.motion_name == self._playing.motion:
                self._seen_playing = True
                return self._playing  # a Webots motion runs to its end; keep asking for it
            if not self._seen_playing:
                return self._playing  # the controller is still leaving another motion (e.g. a walk's stop)
            self._playing = None
        if self.done:
            return MotionRequest(None)
        curve = motion.dynamic.turn_gain
        remaining = self._remaining_deg(world, curve)
        if remaining is None:
            return MotionRequest(None)
        smallest = curve.predicted_turn_deg(curve.min_gain)
        limit = self.max_motions
        if (abs(remaining) <= max(self.tolerance_deg, smallest / 2.0)
                or (limit is not None and self.motions_played >= limit)):
            self.done = True
            return MotionRequest(None)
        part = split_turn(remaining, curve)[0]
        self._playing = MotionRequest(TURN_MOTIONS["left" if part > 0 else "right"], turn_deg=abs(part))
        self._seen_playing = False
        self.motions_played += 1
        self.predicted_deg += predicted_turn_deg(part, curve)
        return self._playing

    def _observe(self, world: WorldModel) -> None:
        """Per-cycle bookkeeping before the decision (heading tracking)."""


class TurnBy(_TurnSkill):
    """Turn in place by ``angle_deg`` (+ = left).

    Planned by dead reckoning: the request is split into the fewest motions the gain curve can make, each
    asking for what is still missing. Corrected by the beliefs: the turn made so far is summed cycle by
    cycle from the localizer's heading change; a cycle without a pose, or whose heading change disagrees
    with the gyro's yaw change by more than ``JUMP_DEG`` (a restart or a teleport of the localizer, not a
    turn), counts the gyro's yaw change instead. With ``use_localization=False`` the turn made is the sum of
    the curve's predictions alone (the turn benchmark measures the curve this way). Done when the missing
    turn is within ``tolerance_deg`` (or below half the smallest motion's turn), or after the planned motions
    (plus ``MAX_CORRECTIONS`` corrections when measuring).

    Args:
        angle_deg: turn to make [deg], + = left.
        tolerance_deg: acceptable final error [deg].
        use_localization: False = dead reckoning only.
    """

    #: A localizer heading change this far from the gyro's in one cycle is a jump, not a turn [deg].
    JUMP_DEG = 5.0

    def __init__(self, angle_deg: float, tolerance_deg: float = TOLERANCE_DEG, use_localization: bool = True) -> None:
        if not math.isfinite(angle_deg):
            raise ValueError(f"angle_deg must be finite, got {angle_deg!r}")
        super().__init__(tolerance_deg, None)
        self.name = f"turn by {angle_deg:g} deg"
        self.angle_deg = angle_deg
        self.use_localization = use_localization
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.max_motions = None
        self.measured_deg: float | None = 0.0 if self.use_localization else None
        """Turn the beliefs saw since the reset (+ = left) [deg]; None in dead reckoning."""
        self._last_yaw_rad: float | None = None
        self._last_heading_rad: float | None = None

    def _observe(self, world: WorldModel) -> None:
        if self.measured_deg is None:
            return
        yaw = world.orientation.yaw_rad
        pose = world.pose
        heading = pose.heading_rad if pose is not None else None
        if self._last_yaw_rad is not None:
            delta = wrap_angle_rad(yaw - self._last_yaw_rad)
            if heading is not None and self._last_heading_rad is not None:
                located = wrap_angle_rad(heading - self._last_heading_rad)
                if abs(located - delta) <= math.radians(self.JUMP_DEG):
                    delta = located
            self.measured_deg += math.degrees(delta)
        self._last_yaw_rad, self._last_heading_rad = yaw, heading

    def turned_deg(self) -> float:
        """The turn made so far by the skill's reckoning (+ = left) [deg]."""
        return self.predicted_deg if self.measured_deg is None else self.measured_deg

    def _remaining_deg(self, world: WorldModel, curve: TurnGain) -> float | None:
        if self.max_motions is None:
            self.max_motions = len(split_turn(self.angle_deg, curve)) + (
                MAX_CORRECTIONS if self.measured_deg is not None else 0)
        return self.angle_deg - self.turned_deg()


class TurnToFace(_TurnSkill):
    """Turn in place until facing the field point (x, y) of the team frame within ``tolerance_deg``.

    The bearing comes from the localized pose at the end of each motion; the next motion's turn (hence its
    gain) is that bearing, split if it exceeds one motion's range. Without a pose the robot stands and waits.

    Args:
        x_m, y_m: the point in the team frame [m].
        tolerance_deg: acceptable final bearing [deg].
        max_motions: give up after this many motions (None: no limit).
    """

    def __init__(self, x_m: float, y_m: float, tolerance_deg: float = TOLERANCE_DEG,
                 max_motions: int | None = 20) -> None:
        super().__init__(tolerance_deg, max_motions)
        self.name = f"turn to face ({x_m:g}, {y_m:g})"
        self.target_m = (x_m, y_m)

    def bearing_deg(self, world: WorldModel) -> float | None:
        """Bearing of the point from the believed pose (+ = left) [deg]; None without a pose."""
        pose = world.pose
        if pose is None:
            return None
        forward, left = pose.to_ego(*self.target_m)
        if math.hypot(forward, left) < 1e-6:
            return 0.0  # standing on the point: every heading faces it
        return math.degrees(math.atan2(left, forward))

    def _remaining_deg(self, world: WorldModel, curve: TurnGain) -> float | None:
        return self.bearing_deg(world)


__all__ = ["MAX_CORRECTIONS", "TOLERANCE_DEG", "TURN_MOTIONS", "TurnBy", "TurnToFace", "predicted_turn_deg",
           "split_turn"]
