"""Walk skills: to a field point (WalkTo), in a body-relative direction (WalkDirection), to the ball
(WalkToBall). They read only the world model (self pose from localization, the ball estimate) and ask for
the walk motions of the contract (``walk_forward``, ``walk_backward``, ``walk_left``, ``walk_right``,
``turn_left``/``turn_right`` when the library has them, ``stand``).

Steering (REFERENCE §7.2): a heading error within the lean band is walked out with the walk lean; larger
errors turn in place with the turn motions (their gain from the turn-gain curve) or, in a library without
turn motions, with a full lean. Near the target the walk is stopped early by the distance it still covers
while it stops (the walk file's ``measured_stop_m`` constant), and the last few decimetres are corrected
with the backward and sideways walks.

The skills also report the walk's odometry to the world model (the walk files' measured speeds), so the
localizer's prediction follows the walk between vision frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.motion import MotionController, MotionRequest
from agent.skills.avoid import AvoidConfig, Avoider
from agent.skills.base import Skill
from agent.world.frames import Pose2D
from agent.world_model import WorldModel

CYCLE_S = 0.02
FORWARD, BACKWARD, LEFT, RIGHT = "walk_forward", "walk_backward", "walk_left", "walk_right"
WALKS = (FORWARD, BACKWARD, LEFT, RIGHT)
TURN_LEFT, TURN_RIGHT = "turn_left", "turn_right"
STAND = "stand"
#: Stopping distance used when a walk file has no ``measured_stop_m`` constant [m].
DEFAULT_STOP_M = 0.12


@dataclass(frozen=True)
class WalkConfig:
    """Thresholds of the walk skills (numbers chosen on our simulator; see the walk benchmark)."""

    lean_band_deg: float = 7.0
    """Heading error steered with the walk lean alone (REFERENCE §7.2: 7°); a standing robot turns first
    when its error is larger and turn motions exist."""
    lean_full_deg: float = 15.0
    """Heading error that asks for a full lean (smaller errors lean proportionally)."""
    turn_band_deg: float = 45.0
    """A walking robot stops to turn in place once its error exceeds this (with turn motions)."""
    arrive_m: float = 0.15
    """Target reached within this distance [m]."""
    near_m: float = 0.5
    """Within this distance the robot corrects with the short walks (backward, sideways) instead of turning
    toward the target [m]."""
    head_deg: tuple[float, float] = (0.0, 0.0)
    """Head (yaw, pitch) while walking [deg, SimSpark signs] (level: landmarks in view for localization)."""
    max_corrections: int = 6
    """Short correcting walks near the target before WalkTo gives up (``done`` with ``reached`` False)."""
    lean_rate_per_s: float = 2.5
    """Largest change of the lean request per second (a sudden full lean can topple the walk); the lean
    starts from 0 whenever the walk is not in its cycle phases."""
    settle_after_turn_s: float = 0.3
    """Standing still after a turn motion before walking on [s]."""
    lean_release: float = 0.15
    """A walk leaning more than this is straightened at ``lean_rate_per_s`` before it is stopped or left
    for another motion: dropped at once (a full lean to 0 mid-stride, then the stop), it toppled a
    type-1 robot in a match."""
    avoid: AvoidConfig | None = AvoidConfig()
    """Obstacle avoidance while walking toward a far target (``agent.skills.avoid``); None = walk straight."""


def constant(motion: MotionController, name: str, key: str, default: float) -> float:
    """A constant of motion ``name`` from the library (``default`` if the motion or the key is missing)."""
    if name not in motion.library:
        return default
    return float(motion.library.get(name).constants.get(key, default))


def walk_velocity_m_s(motion: MotionController, name: str) -> tuple[float, float]:
    """(forward, left) steady velocity of a walk [m/s]: measured on the simulator if the file says, else
    the nominal ``speed_m_s`` / ``side_speed_m_s``."""
    forward = constant(motion, name, "measured_forward_m_s", constant(motion, name, "speed_m_s", 0.0))
    left = constant(motion, name, "measured_left_m_s", constant(motion, name, "side_speed_m_s", 0.0))
    return forward, left


def report_walk_odometry(world: WorldModel, motion: MotionController) -> None:
    """Tell the localizer how far the walk moved the torso in the last cycle: the walk's steady velocity
    in its cycle phases, half of it in its start and stop ramps, nothing otherwise."""
    name, phase = motion.motion_name, motion.phase_name
    if name not in WALKS or phase is None:
        return
    share = 1.0 if phase.startswith("cycle") else 0.5 if phase.startswith(("start", "stop_0", "stop_1")) else 0.0
    if share:
        forward, left = walk_velocity_m_s(motion, name)
        world.report_odometry(forward * share * CYCLE_S, left * share * CYCLE_S)


def stop_distance_m(motion: MotionController, name: str) -> float:
    """Distance a walk still covers after a stop request [m] (file constant ``measured_stop_m``)."""
    return constant(motion, name, "measured_stop_m", DEFAULT_STOP_M)


def _lean(bearing_deg: float, config: WalkConfig) -> float:
    return max(-1.0, min(1.0, bearing_deg / config.lean_full_deg))


def _walking(motion: MotionController) -> bool:
    return motion.motion_name in WALKS and not motion.stopping


class _Steer:
    """Shared mechanics: turn motions played to their end, odometry, head, the last choice (hysteresis)."""

    def __init__(self, config: WalkConfig) -> None:
        self.config = config
        self.turning: str | None = None
        self.lean: float | None = None
        """The lean request sent last (slew-rate limited); None until this skill first steers a walk."""
        self._settle_cycles = 0
        self._stands_before = 0
        self.just_turned = False
        """A turn has ended and no walk has started since: the lean, not another turn, takes the rest
        (a turn motion's smallest turn may exceed the lean band, so turning again could oscillate)."""
        self._turn_deg = 0.0
        self._turns_before = 0

    def request(self, name: str | None, **fields: object) -> MotionRequest:
        return MotionRequest(name, head_deg=fields.pop("head_deg", self.config.head_deg), **fields)  # type: ignore[arg-type]

    def turn(self, motion: MotionController, bearing_deg: float) -> MotionRequest:
        """Start a turn toward ``bearing_deg`` (one turn motion, gain from the turn-gain curve)."""
        self.turning = TURN_LEFT if bearing_deg > 0 else TURN_RIGHT
        self._turn_deg = abs(bearing_deg)
        self._turns_before = motion.completed[self.turning]
        return self.request(self.turning, turn_deg=self._turn_deg)

    def turn_step(self, motion: MotionController) -> MotionRequest | None:
        """The request while a turn and the return to the stance after it are under way, else None."""
        if self.turning is None and not self._settle_cycles:
            return None
        if motion.completed[self.turning] > self._turns_before:
            self.turning = None
            self.just_turned = True
            self._settle_cycles = round(self.config.settle_after_turn_s / CYCLE_S)
            self._stands_before = motion.completed[STAND]
        if self.turning is None:
            # Back into the walk stance (the turn may end in another pose, and the walk skips its own
            # stance phase while the stance flag is still set), then stand still a moment.
            if STAND in motion.library and motion.completed[STAND] <= self._stands_before:
                return self.request(STAND)
            if self._settle_cycles > 0:
                self._settle_cycles -= 1
                return self.request(None)
            return None
        return self.request(self.turning, turn_deg=self._turn_deg)

    def smooth_lean(self, motion: MotionController, wanted: float) -> float:
        """``wanted`` lean, approached at ``lean_rate_per_s`` once the walk cycles, from the lean the walk
        plays with now (another skill may have started it)."""
        cycling = motion.motion_name == FORWARD and (motion.phase_name or "").startswith("cycle")
        if not cycling:
            self.lean = 0.0
            return 0.0
        if self.lean is None:
            self.lean = motion.last_request.lean if motion.last_request.motion == FORWARD else 0.0
        step = self.config.lean_rate_per_s * CYCLE_S
        self.lean += max(-step, min(step, wanted - self.lean))
        return self.lean

    def guard(self, motion: MotionController, request: MotionRequest) -> MotionRequest:
        """``request``, unless it leaves a forward walk that still leans more than ``lean_release``: then
        the walk goes on straightening first (the turn or stop follows a few cycles later)."""
        leaving = request.motion != FORWARD and motion.motion_name == FORWARD and not motion.stopping
        if leaving:
            lean = self.smooth_lean(motion, 0.0)
            if abs(lean) > self.config.lean_release:
                return MotionRequest(FORWARD, lean=lean, head_deg=request.head_deg)
        return request

    def can_turn(self, motion: MotionController) -> bool:
        return TURN_LEFT in motion.library and TURN_RIGHT in motion.library

    def heading(self, motion: MotionController, bearing_deg: float) -> MotionRequest:
        """Walk forward toward ``bearing_deg``: lean within the bands, else turn (or a full lean)."""
        error = abs(bearing_deg)
        walking = _walking(motion)
        band = self.config.turn_band_deg if walking or self.just_turned else self.config.lean_band_deg
        if error > band and self.can_turn(motion):
            return self.turn(motion, bearing_deg)
        if walking:
            self.just_turned = False
        return self.request(FORWARD, lean=self.smooth_lean(motion, _lean(bearing_deg, self.config)))


class WalkTo(Skill):
    """Walk to a team-frame point (x, y) [m]; ``done`` when within ``arrive_m`` (``reached``) or after
    ``max_corrections`` short corrections near it (``reached`` False).

    Args:
        x_m, y_m: the target in the team frame (own goal at -x).
        config: thresholds.
    """

    def __init__(self, x_m: float, y_m: float, config: WalkConfig | None = None) -> None:
        super().__init__()
        self.target = (float(x_m), float(y_m))
        self.config = config or WalkConfig()
        self.name = f"walk to ({x_m:.2f}, {y_m:.2f})"
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.reached = False
        self.corrections = 0
        self._steer = _Steer(self.config)
        self._avoider = Avoider(self.config.avoid) if self.config.avoid else None
        self._correction: str | None = None

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        return self._steer.guard(motion, self._step(world, motion))

    def _step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        steer = self._steer
        pose = world.pose
        if self.done or pose is None or not world.localized:
            return steer.request(None)  # no trusted pose yet (e.g. just after a beam): stand and look
        under_way = steer.turn_step(motion)
        if under_way is not None:
            return under_way
        forward, left = pose.to_ego(*self.target)
        distance = math.hypot(forward, left)
        bearing_deg = math.degrees(math.atan2(left, forward))
        if distance <= self.config.arrive_m:
            return self._arrive(motion, reached=True)
        if self._correction is not None:
            return self._correct(motion, forward, left)
        if distance <= self.config.near_m:
            if motion.motion_name == FORWARD and not motion.stopping and forward > 0:
                # Still walking in: stop once the remaining distance is what the stop covers.
                if forward > stop_distance_m(motion, FORWARD) + self.config.arrive_m / 2 and abs(bearing_deg) < 45:
                    return steer.request(FORWARD, lean=steer.smooth_lean(motion, _lean(bearing_deg, self.config)))
            return self._correct(motion, forward, left)
        if self._avoider is not None:
            escape = self._avoider.bearing_deg(world, (forward, left))
            if escape is None:
                return steer.request(None)  # surrounded: let the others pass
            bearing_deg = escape
        return steer.heading(motion, bearing_deg)

    def _arrive(self, motion: MotionController, reached: bool) -> MotionRequest:
        if motion.idle or motion.motion_name not in WALKS:
            self.done, self.reached = True, reached
        return self._steer.request(None)

    def _correct(self, motion: MotionController, forward: float, left: float) -> MotionRequest:
        """Near the target: one short walk along the larger error component (a walk already stopping is let
        finish first); each finished correction counts."""
        if self._correction is not None:
            if motion.motion_name == self._correction and not motion.stopping:
                if self._correction_left(motion, forward, left) > stop_distance_m(motion, self._correction):
                    return self._steer.request(self._correction)
                return self._steer.request(None)
            if not motion.idle:
                return self._steer.request(None)
            self._correction = None
            self.corrections += 1
            if self.corrections >= self.config.max_corrections:
                return self._arrive(motion, reached=False)
        if not motion.idle and motion.motion_name in WALKS:
            return self._steer.request(None)
        if abs(forward) >= abs(left):
            name = FORWARD if forward > 0 else BACKWARD
        else:
            name = LEFT if left > 0 else RIGHT
        if name not in motion.library:
            name = FORWARD
        self._correction = name
        return self._steer.request(name)

    @staticmethod
    def _correction_left(motion: MotionController, forward: float, left: float) -> float:
        """Remaining error along the correcting walk's direction [m]."""
        return {FORWARD: forward, BACKWARD: -forward, LEFT: left, RIGHT: -left}.get(motion.motion_name or "", 0.0)


class WalkDirection(Skill):
    """Walk in a direction relative to the body, without turning: 0° = forward, 90° = left, ±180° =
    backward, -90° = right; the nearest of the four walks (sectors of ±45°) plays until the skill is
    replaced (``done`` stays False).

    Args:
        angle_deg: the direction [deg], counter-clockwise from forward.
    """

    def __init__(self, angle_deg: float, config: WalkConfig | None = None) -> None:
        super().__init__()
        if not math.isfinite(angle_deg):
            raise ValueError(f"WalkDirection angle_deg must be finite, got {angle_deg!r}")
        self.angle_deg = (angle_deg + 180.0) % 360.0 - 180.0
        self.config = config or WalkConfig()
        self.name = f"walk direction {self.angle_deg:.0f}°"
        self.motion_name = self.walk_for(self.angle_deg)

    @staticmethod
    def walk_for(angle_deg: float) -> str:
        """The walk motion for a body-relative direction [deg]."""
        angle = (angle_deg + 180.0) % 360.0 - 180.0
        if -45.0 <= angle <= 45.0:
            return FORWARD
        if 45.0 < angle < 135.0:
            return LEFT
        if -135.0 < angle < -45.0:
            return RIGHT
        return BACKWARD

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        return MotionRequest(self.motion_name, head_deg=self.config.head_deg)


@dataclass(frozen=True)
class BallApproach:
    """Where the ball should end up for WalkToBall, in the robot's ego frame [m]."""

    forward_min_m: float = 0.08
    """Closest the ball may be in front (torso centre to ball centre)."""
    forward_max_m: float = 0.38
    """Farthest the ball may be in front and still count as close [m] (a forward walk, however short the
    request, moves about 0.35 m with its start and stop ramps: a nearer limit made the correction walk
    through the ball)."""
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
            if forward <= stop_distance_m(motion, FORWARD) + a.standoff_m and motion.motion_name == FORWARD:
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
            remaining = {FORWARD: to_forward, BACKWARD: a.back_to_m - forward, LEFT: left, RIGHT: -left}[name]
            # Walk on while the error exceeds what the walk still covers once stopped (a side walk's stop
            # alone covers about the lateral tolerance, so stopping at a fixed small error overshot and the
            # corrections swung from side to side).
            if remaining > stop_distance_m(motion, name):
                return steer.request(name, head_deg=head, lean=steer.smooth_lean(motion, _lean(bearing_deg, self.config))
                                     if name == FORWARD else 0.0)
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


__all__ = ["BallApproach", "WalkConfig", "WalkDirection", "WalkTo", "WalkToBall", "report_walk_odometry",
           "stop_distance_m", "walk_velocity_m_s"]
