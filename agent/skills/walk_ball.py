"""WalkToBall: walk until the ball is close and in front, from the world model's ball estimate, with the
steering of ``agent.skills.walk`` (lean, turns, obstacle avoidance) far from the ball and short corrections
near it. Why a module of its own: the lining-up near the ball (what a short walk can and cannot correct,
the ball beside the feet) is its own problem."""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.motion import MotionController, MotionRequest
from agent.skills.avoid import Avoider
from agent.skills.base import Skill
from agent.skills.walk import (BACKWARD, CYCLE_S, FAST, FORWARD, FORWARD_WALKS, LEFT, RIGHT, WALKS, WalkConfig,
                               _lean, _Steer, report_walk_odometry, stop_distance_m)
from agent.world.frames import Pose2D
from agent.world_model import WorldModel


@dataclass(frozen=True)
class BallApproach:
    """Where the ball should end up for WalkToBall, in the robot's ego frame [m]."""

    forward_min_m: float = 0.08
    """Closest the ball may be in front (torso centre to ball centre)."""
    forward_max_m: float = 0.43
    """Farthest the ball may be in front and still count as close [m]: ``forward_min_m`` plus the least a forward
    walk moves (about 0.35 m with its start and stop ramps, however short the request), so a ball beyond it can be
    walked to without walking through it. (0.38 left a ball 0.39-0.40 m ahead after a step back and a turn; the
    forward walk then pushed it 1.55 m: tests/scenarios/test_walk_transitions.py.)"""
    lateral_m: float = 0.1
    """Largest sideways offset of the ball."""
    standoff_m: float = 0.18
    """Point walked to: this far short of the ball along the line from the robot."""
    max_age_s: float = 4.0
    """A ball sighting older than this is not trusted; the robot stands and looks around."""
    side_clear_m: float = 0.16
    """A side step only with the ball at least this far in front [m] (the toes reach ~0.09 m ahead of the
    torso, the ball's radius is 0.042 m): nearer, a side step pushed the ball along beside the feet for
    seconds and then stepped on it (seen in matches); the robot steps back first."""
    back_to_m: float = 0.24
    """A backward correction aims to put the ball this far in front [m]."""
    min_side_m: float = 0.25
    """Lateral errors below this are turned out, not side-stepped [m]: a side walk, however short the
    request, plays its start and stop ramps and moves about 0.25 m (measured), so smaller corrections
    overshot and swung from side to side."""
    search_turn_s: float = 4.2
    """Searching, the robot turns a quarter by a turn motion after each full head sweep [s] (2 periods of
    the sweep): a ball behind the robot is out of the head's reach, and a lone robot stood for ever."""


class WalkToBall(Skill):
    """Walk until the ball is close and in front (``done``), from the world model's ball estimate (its
    position is projected with the camera height from the kinematics).

    The head pitches down as the ball comes closer so the ball stays in view; a lost ball (older than
    ``max_age_s``) stops the robot, which sweeps its head until it sees the ball again.
    """

    name = "walk to ball"

    def __init__(self, approach: BallApproach | None = None, config: WalkConfig | None = None) -> None:
        super().__init__()
        self.approach = approach or BallApproach()
        self.config = config or WalkConfig()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self._steer = _Steer(self.config)
        self._avoider = Avoider(self.config.avoid) if self.config.avoid else None
        self._search_cycles = 0

    def ball_ego(self, world: WorldModel) -> tuple[float, float] | None:
        """The ball in the ego frame now [m]: through the current pose when both are known (the robot may
        have moved since the sighting), else the sighting's own ego position."""
        ball = world.ball
        if ball is None or ball.age_s(world.now_s) > self.approach.max_age_s:
            return None
        pose: Pose2D | None = world.pose
        if ball.position is not None and pose is not None and world.localized and ball.age_s(world.now_s) > 0.1:
            return pose.to_ego(*ball.position)
        if ball.forward_m is None:
            return None if pose is None or ball.position is None else pose.to_ego(*ball.position)
        return ball.forward_m, ball.left_m  # type: ignore[return-value]

    def head_for(self, world: WorldModel, ball: tuple[float, float]) -> tuple[float, float]:
        """Head (yaw, pitch) [deg] that keeps the ball near the image centre's lower part."""
        distance = math.hypot(*ball)
        yaw = max(-60.0, min(60.0, math.degrees(math.atan2(ball[1], ball[0]))))
        depression = math.degrees(math.atan2(world.body.camera_height_m, max(distance, 0.05)))
        return yaw, -max(0.0, min(45.0, depression - 25.0))

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        return self._steer.guard(motion, self._step(world, motion))

    def _step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        steer = self._steer
        ball = self.ball_ego(world)
        if ball is None:
            self._search_cycles += 1
            under_way = steer.turn_step(motion)
            if under_way is not None:
                return under_way
            if self._search_cycles % round(self.approach.search_turn_s / CYCLE_S) == 0 and steer.can_turn(motion):
                return steer.turn(motion, 90.0)
            phase = self._search_cycles * CYCLE_S * 1.5
            sweep = 60.0 * math.sin(phase)
            # Every other sweep looks down at the feet too (a ball right in front is below a -20° view).
            pitch = -20.0 if int(phase / math.pi) % 2 == 0 else -45.0
            return steer.request(None, head_deg=(sweep, pitch))
        self._search_cycles = 0
        head = self.head_for(world, ball)
        under_way = steer.turn_step(motion)
        if under_way is not None:
            return under_way
        forward, left = ball
        a = self.approach
        close = a.forward_min_m <= forward <= a.forward_max_m and abs(left) <= a.lateral_m
        if close:
            if motion.idle or motion.motion_name not in WALKS:
                self.done = True
            return steer.request(None, head_deg=head)
        self.done = False
        distance = math.hypot(forward, left)
        bearing_deg = math.degrees(math.atan2(left, forward))
        # Target: the standoff point on the line robot -> ball.
        scale = max(0.0, distance - a.standoff_m) / distance if distance > 1e-6 else 0.0
        to_forward, to_left = forward * scale, left * scale
        if distance > 0.6:
            walk = motion.motion_name
            if walk in FORWARD_WALKS and forward <= stop_distance_m(motion, walk) + a.standoff_m:
                return steer.request(None, head_deg=head)
            if self._avoider is not None:
                escape = self._avoider.bearing_deg(world, (to_forward, to_left))
                if escape is None:
                    return steer.request(None, head_deg=head)
                bearing_deg = escape
            request = steer.heading(motion, bearing_deg)
            return MotionRequest(request.motion, request.lean, request.turn_deg, request.gain, head)
        # Close: line up with short walks along the larger error (forward only if it does not overshoot; a
        # side step only with the ball clear of the toes, else a step back first).
        if motion.motion_name in WALKS and not motion.stopping:
            name = motion.motion_name
            if name in (LEFT, RIGHT) and forward < a.side_clear_m - 0.03:
                return steer.request(None, head_deg=head)  # the ball came to the feet: stop before stepping on it
            remaining = {FORWARD: to_forward, FAST: to_forward, BACKWARD: a.back_to_m - forward, LEFT: left,
                         RIGHT: -left}[name]
            # Walk on while the error exceeds what the walk still covers once stopped (a side walk's stop
            # alone covers about the lateral tolerance, so stopping at a fixed small error overshot and the
            # corrections swung from side to side).
            if remaining > stop_distance_m(motion, name):
                return steer.request(name, head_deg=head, lean=steer.smooth_lean(motion, _lean(bearing_deg, self.config))
                                     if name in FORWARD_WALKS else 0.0)
            return steer.request(None, head_deg=head)
        if not motion.idle and motion.motion_name in WALKS:
            return steer.request(None, head_deg=head)
        if abs(left) > a.lateral_m and abs(left) >= abs(to_forward) / 2:
            if forward < a.side_clear_m:
                name = BACKWARD  # room first: a side step or a turn would kick the ball beside the feet
            elif abs(left) < a.min_side_m and steer.can_turn(motion):
                return steer.turn(motion, bearing_deg)
            else:
                name = LEFT if left > 0 else RIGHT
        elif forward < a.forward_min_m:
            name = BACKWARD
        elif abs(bearing_deg) > 25 and steer.can_turn(motion):
            return steer.turn(motion, bearing_deg)
        else:
            name = FORWARD
        return steer.request(name, head_deg=head)


__all__ = ["BallApproach", "WalkToBall"]
