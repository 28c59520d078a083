"""Kick the ball toward a field point: line up behind the ball, choose the foot, play the kick.

``KickToward`` reads only the world model (the ball estimate, the self pose from localization) and the
motion library. Each kick motion says where it wants the ball (its constants ``ball_forward_m`` and
``ball_left_m``: the ball centre in the ego frame of the robot standing in the walk stance), so the skill
knows the spot to stand on for either foot. Lining up, with the motions the library has:

1. far from the spot (more than ``approach_m``): walk to a point behind it on the kick line
   (``agent.skills.walk.WalkTo``);
2. near it, standing still and with a fresh ball sighting: turn toward the aim (``turn_left`` /
   ``turn_right``, one turn motion per correction), then correct sideways and along the kick line, with a
   walk (``walk_left`` / ``walk_right`` / ``walk_forward`` / ``walk_backward``) while the error exceeds half
   of what one short walk moves (the walks are cyclic gaits: a single request walks a whole start and stop
   ramp, 0.12 m sideways and 0.35 m forward on our simulator), then with the kick steps
   (``kick_step_left`` ... of ``motions.authoring.kick_steps``: 2 cm each);
3. kick once the ball lies within the kick's tolerance of its spot, or once the corrections are used up and
   it lies within the loose tolerance; else give up (``done`` with ``kicked`` False).

Without walk or turn motions in the library the corresponding corrections are skipped (place-and-kick:
someone else put the robot behind the ball). The foot is the one whose spot is nearer to where the ball
lies; it is chosen anew before each correction.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from agent.motion import MotionController, MotionRequest
from agent.skills.base import Skill
from agent.skills.walk import WalkTo, report_walk_odometry
from agent.world.frames import wrap_angle_rad
from agent.world_model import WorldModel

logger = logging.getLogger(__name__)

CYCLE_S = 0.02
KICK, STRONG = "kick", "kick_strong"
LEFT_SUFFIX = "_left"
TURN_LEFT, TURN_RIGHT = "turn_left", "turn_right"
FORWARD, BACKWARD, SIDE_LEFT, SIDE_RIGHT = "walk_forward", "walk_backward", "walk_left", "walk_right"
STEP_FORWARD, STEP_BACKWARD = "kick_step_forward", "kick_step_backward"
STEP_LEFT, STEP_RIGHT = "kick_step_left", "kick_step_right"


def _step_size(motion: MotionController, name: str, key: str) -> float:
    """Size of a kick step from its motion constant [m] (0 when the library lacks it)."""
    if name not in motion.library:
        return 0.0
    return abs(float(motion.library.get(name).constants.get(key, 0.0)))


@dataclass(frozen=True)
class KickConfig:
    """Tolerances and moves of the kick skill (numbers chosen on our simulator; see the kick benchmark)."""

    heading_tol_deg: float = 6.0
    """Aim error corrected with a turn motion when larger [deg]."""
    forward_tol_m: float = 0.01
    """Ball along the kick line off its spot: kick when within [m]."""
    lateral_tol_m: float = 0.015
    """Ball across the kick line off its spot: kick when within [m]."""
    loose_forward_m: float = 0.025
    """After the corrections are used up, kick if the ball is this close along the line [m]..."""
    loose_lateral_m: float = 0.03
    """... and this close across it [m]."""
    side_step_m: float = 0.12
    """Sideways displacement of one short sideways walk [m] (measured: walk_left/right, one request)."""
    forward_step_m: float = 0.35
    """Forward displacement of one short forward walk [m] (measured: walk_forward, one request)."""
    backward_step_m: float = 0.30
    """Backward displacement of one short backward walk [m]."""
    approach_m: float = 0.45
    """Beyond this distance from the kick spot the robot walks to a point behind it first [m]."""
    approach_back_m: float = 0.30
    """That point lies this far behind the kick spot on the kick line [m]."""
    max_corrections: int = 12
    """Corrections near the ball before kicking within the loose tolerance or giving up."""
    max_approaches: int = 2
    """Walks to the point behind the spot before the skill corrects with short walks only."""
    settle_s: float = 0.25
    """Wait after a move for a ball sighting taken standing still [s]."""
    max_ball_age_s: float = 3.0
    """A ball sighting older than this counts as lost [s]."""
    lost_timeout_s: float = 8.0
    """Give up after the ball has been lost this long [s]."""
    head_pitch_deg: float = -45.0
    """Head pitch while lining up close to the ball [deg] (down: the ball lies at the feet)."""


@dataclass(frozen=True)
class Spot:
    """Where a kick motion wants the ball: ego (forward, left) [m]."""

    motion: str
    forward_m: float
    left_m: float


def kick_spots(motion: MotionController, strong: bool) -> list[Spot]:
    """The kick motions of the library for this strength (right and left foot) and their ball spots.

    Raises:
        KeyError: the library has none of them.
    """
    base = STRONG if strong and STRONG in motion.library else KICK
    spots = []
    for name in (base, base + LEFT_SUFFIX):
        if name in motion.library:
            constants = motion.library.get(name).constants
            if "ball_forward_m" in constants and "ball_left_m" in constants:
                spots.append(Spot(name, float(constants["ball_forward_m"]), float(constants["ball_left_m"])))
    if not spots:
        raise KeyError(f"no kick motion ({base}, {base + LEFT_SUFFIX}) with ball_forward_m/ball_left_m constants "
                       f"in the library; known: {', '.join(motion.library.names)}")
    return spots


class KickToward(Skill):
    """Kick the ball toward a team-frame point (x, y) [m]; see the module docstring.

    Args:
        target_x_m, target_y_m: where the ball should go, team frame (own goal at -x).
        strong: use ``kick_strong`` (falls back to ``kick`` if the library lacks it).
        config: tolerances and moves.

    After ``done``: ``kicked`` says whether a kick was played, ``foot`` which motion, ``reason`` why it
    stopped without kicking, ``kick_started_s`` the server time the kick motion was first requested.
    """

    def __init__(self, target_x_m: float, target_y_m: float, strong: bool = False,
                 config: KickConfig | None = None) -> None:
        super().__init__()
        if not (math.isfinite(target_x_m) and math.isfinite(target_y_m)):
            raise ValueError(f"KickToward target must be finite, got ({target_x_m!r}, {target_y_m!r})")
        self.target = (float(target_x_m), float(target_y_m))
        self.strong = strong
        self.config = config or KickConfig()
        self.name = f"kick{' strong' if strong else ''} toward ({target_x_m:.1f}, {target_y_m:.1f})"
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.kicked = False
        self.foot: str | None = None
        self.reason = ""
        self.kick_started_s: float | None = None
        self.corrections = 0
        self._kick_motion: str | None = None
        self._kicks_before = 0
        self._move: str | None = None
        self._move_started = False
        self._move_turn_deg: float | None = None
        self._still_since_s: float | None = None
        self._walk_to: WalkTo | None = None
        self._approaches = 0
        self._lost_since_s: float | None = None
        self._unlocalized_since_s: float | None = None

    # ---- perception -----------------------------------------------------------------------------------
    def _ball_ego(self, world: WorldModel) -> tuple[float, float] | None:
        """The ball in the ego frame: the sighting itself when taken while standing still, else through
        the current pose (the robot may have moved since)."""
        ball = world.ball
        if ball is None or ball.age_s(world.now_s) > self.config.max_ball_age_s:
            return None
        still = self._still_since_s
        if ball.forward_m is not None and still is not None and ball.seen_s >= still:
            return ball.forward_m, ball.left_m  # type: ignore[return-value]
        pose = world.pose
        if pose is not None and ball.position is not None:
            return pose.to_ego(*ball.position)
        if ball.forward_m is not None:
            return ball.forward_m, ball.left_m  # type: ignore[return-value]
        return None

    def _aim_error_rad(self, world: WorldModel, ball: tuple[float, float]) -> float:
        """Heading change that points the robot along ball -> target (0 when not localized)."""
        pose = world.pose
        if pose is None:
            return 0.0
        bx, by = pose.to_team(*ball)
        aim = math.atan2(self.target[1] - by, self.target[0] - bx)
        return wrap_angle_rad(aim - pose.heading_rad)

    def _request(self, name: str | None, ball: tuple[float, float] | None = None, **fields: object) -> MotionRequest:
        pitch = self.config.head_pitch_deg if ball is None or math.hypot(*ball) < 0.6 else -25.0
        yaw = 0.0 if ball is None or math.hypot(*ball) < 0.6 else max(-60.0, min(60.0, math.degrees(math.atan2(ball[1], ball[0]))))
        return MotionRequest(name, head_deg=(yaw, pitch), **fields)  # type: ignore[arg-type]

    # ---- the cycle ------------------------------------------------------------------------------------
    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        if self.done:
            return self._request(None)
        if self._kick_motion is not None:
            return self._kicking(world, motion)
        moving = self._moving(world, motion)
        if moving is not None:
            return moving
        if not motion.idle:
            self._still_since_s = None
            return self._request(None)
        if self._still_since_s is None:
            self._still_since_s = world.now_s
        ball = self._ball_ego(world)
        if ball is None:
            return self._search(world)
        self._lost_since_s = None
        if world.now_s - self._still_since_s < self.config.settle_s:
            return self._request(None, ball)
        return self._decide(world, motion, ball)

    def _search(self, world: WorldModel) -> MotionRequest:
        if self._lost_since_s is None:
            self._lost_since_s = world.now_s
        if world.now_s - self._lost_since_s > self.config.lost_timeout_s:
            self.done, self.reason = True, "ball lost"
        sweep = 60.0 * math.sin((world.now_s - self._lost_since_s) * 1.5)
        return MotionRequest(None, head_deg=(sweep, -30.0))

    def _decide(self, world: WorldModel, motion: MotionController, ball: tuple[float, float]) -> MotionRequest:
        config = self.config
        spots = kick_spots(motion, self.strong)
        spot = min(spots, key=lambda s: math.hypot(ball[0] - s.forward_m, ball[1] - s.left_m))
        self.foot = spot.motion
        error_f, error_l = ball[0] - spot.forward_m, ball[1] - spot.left_m
        aim_rad = self._aim_error_rad(world, ball)
        logger.debug("t=%.2f ball (%.3f, %.3f) spot %s error (%+.3f, %+.3f) aim %+.1f deg corrections %d",
                     world.now_s, ball[0], ball[1], spot.motion, error_f, error_l, math.degrees(aim_rad),
                     self.corrections)
        if math.hypot(error_f, error_l) > config.approach_m and self._approaches < config.max_approaches \
                and FORWARD in motion.library:
            return self._approach(world, ball, spot, aim_rad)
        can_correct = self.corrections < config.max_corrections
        if can_correct and abs(math.degrees(aim_rad)) > config.heading_tol_deg and TURN_LEFT in motion.library \
                and TURN_RIGHT in motion.library:
            return self._start_move(TURN_LEFT if aim_rad > 0 else TURN_RIGHT, ball, abs(math.degrees(aim_rad)))
        within = abs(error_f) <= config.forward_tol_m and abs(error_l) <= config.lateral_tol_m
        if not within and can_correct:
            move = self._correction(motion, error_f, error_l)
            if move is not None:
                return self._start_move(move, ball)
        loose = abs(error_f) <= config.loose_forward_m and abs(error_l) <= config.loose_lateral_m
        if within or loose:
            self._kick_motion = spot.motion
            self._kicks_before = motion.completed[spot.motion]
            self.kick_started_s = world.now_s
            return self._request(spot.motion, ball)
        self.done = True
        self.reason = (f"ball off the kick spot by ({error_f:+.2f}, {error_l:+.2f}) m and no motion left to "
                       f"correct it")
        return self._request(None, ball)

    def _correction(self, motion: MotionController, error_f: float, error_l: float) -> str | None:
        """The move that best reduces the ball's offset from its spot: a walk for an error above half of
        what the walk moves, else a kick step for an error above the tolerance (sideways first: a sideways
        miss costs more than one along the line)."""
        config, library = self.config, motion.library
        lateral = [(SIDE_LEFT if error_l > 0 else SIDE_RIGHT, config.side_step_m)]
        lateral.append((STEP_LEFT if error_l > 0 else STEP_RIGHT, _step_size(motion, STEP_LEFT, "step_left_m")))
        along = [(FORWARD, config.forward_step_m) if error_f > 0 else (BACKWARD, config.backward_step_m)]
        along.append((STEP_FORWARD, _step_size(motion, STEP_FORWARD, "step_forward_m")) if error_f > 0
                     else (STEP_BACKWARD, _step_size(motion, STEP_BACKWARD, "step_forward_m")))
        for error, tolerance, moves in ((abs(error_l), config.lateral_tol_m, lateral),
                                        (abs(error_f), config.forward_tol_m, along)):
            if error <= tolerance:
                continue
            for name, size in moves:
                if name in library and size > 0 and error > size / 2:
                    return name
        return None

    def _approach(self, world: WorldModel, ball: tuple[float, float], spot: Spot, aim_rad: float) -> MotionRequest:
        """Walk to a point behind the kick spot on the kick line (team frame through the pose)."""
        pose = world.pose
        if pose is None:  # not localized yet: look up at the landmarks for a while
            if self._unlocalized_since_s is None:
                self._unlocalized_since_s = world.now_s
            if world.now_s - self._unlocalized_since_s > self.config.lost_timeout_s:
                self.done, self.reason = True, "not localized: cannot walk to the ball"
            sweep = 60.0 * math.sin((world.now_s - self._unlocalized_since_s) * 1.5)
            return MotionRequest(None, head_deg=(sweep, 0.0))
        c, s = math.cos(aim_rad), math.sin(aim_rad)
        back = spot.forward_m + self.config.approach_back_m
        # The ego point from which, facing the aim, the ball lies at (back, spot.left_m).
        fx, fy = ball[0] - (c * back - s * spot.left_m), ball[1] - (s * back + c * spot.left_m)
        self._approaches += 1
        self._walk_to = WalkTo(*pose.to_team(fx, fy))
        self._move = "approach"
        self._still_since_s = None
        return self._request(None, ball)

    # ---- moves ----------------------------------------------------------------------------------------
    def _start_move(self, name: str, ball: tuple[float, float], turn_deg: float | None = None) -> MotionRequest:
        self.corrections += 1
        self._move, self._move_started, self._move_turn_deg = name, False, turn_deg
        self._still_since_s = None
        return self._request(name, ball, turn_deg=turn_deg)

    def _moving(self, world: WorldModel, motion: MotionController) -> MotionRequest | None:
        """The request while a correction is under way (None when there is none or it has ended)."""
        if self._move is None:
            return None
        head = (0.0, self.config.head_pitch_deg)
        if self._move == "approach":
            walk_to = self._walk_to
            assert walk_to is not None
            if not walk_to.done:
                return walk_to.step(world, motion)
            if not motion.idle:
                return MotionRequest(None, head_deg=head)
        elif not self._move_started:
            if motion.motion_name != self._move:
                return MotionRequest(self._move, turn_deg=self._move_turn_deg, head_deg=head)
            self._move_started = True
        if self._move in (TURN_LEFT, TURN_RIGHT) and motion.motion_name == self._move:
            return MotionRequest(self._move, turn_deg=self._move_turn_deg, head_deg=head)
        if motion.motion_name is not None:  # a walk: asked to stop at once (one short walk), let it finish
            return MotionRequest(None, head_deg=head)
        self._move, self._walk_to = None, None
        self._still_since_s = None
        return None

    def _kicking(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        name = self._kick_motion
        assert name is not None
        if motion.completed[name] > self._kicks_before:
            self.done, self.kicked = True, True
            return self._request(None)
        return MotionRequest(name, head_deg=(0.0, self.config.head_pitch_deg))


__all__ = ["KickConfig", "KickToward", "Spot", "kick_spots"]
