"""Kick the ball toward a field point: line up behind the ball, choose the foot, play the kick.

``KickToward`` reads only the world model (the ball estimate, the self pose from localization) and the
motion library. Each kick motion says where it wants the ball (its constants ``ball_forward_m`` and
``ball_left_m``: the ball centre in the ego frame of the robot standing in the walk stance), so the skill
knows the spot to stand on for either foot. Standing still with a fresh ball sighting, it asks
``agent.skills.kick_lineup.plan`` for the next move and plays it:

1. far from the kick pose (or on the wrong side of the ball): walk to a point behind the ball on the kick
   line (``agent.skills.walk.WalkTo`` from afar, then a turn toward the point and a counted number of
   strides steered with the walk lean), then turn to the aim; with the ball at the feet and the aim far off,
   back off first;
2. facing the aim: one walk-in along the kick line, its strides chosen so the ball ends just beyond its spot
   (a walk covers a fixed distance per stride, whenever it is asked to stop);
3. kick within the window; kick steps (2 cm), sideways or backward walks only for what the walk-in cannot
   fix, and the loose window when such a slow correction would be needed (after the first 4 s, or once the
   corrections are used up); else give up (``done`` with ``kicked`` False).

While the robot moves the ball estimate goes through the localized pose (a ball out of view is remembered
10 s once seen during the skill) and the head follows it; decisions wait for a sighting taken standing still.

Without walk or turn motions in the library the corresponding moves are skipped (place-and-kick: someone
else put the robot behind the ball; without turns the kick goes where the robot faces). Not localized,
the robot kicks a near ball along its heading and waits (head sweeping) for a pose before walking to a
farther one, giving up after ``lost_timeout_s``. The foot is the one
whose spot suits the ball best (the lateral tolerance is tighter outward), chosen anew before each move.
"""

from __future__ import annotations

import logging
import math
from dataclasses import replace

from agent.motion import MotionController, MotionRequest
from agent.skills.base import Skill
from agent.skills.kick_lineup import (LEFT_SUFFIX, STEP_FORWARD, KickConfig, Move, Spot, foot_side, plan,
                                     plan_with_fallback)
from agent.skills.walk import FORWARD, TURN_LEFT, TURN_RIGHT, WalkConfig, WalkTo, report_walk_odometry
from agent.world.frames import wrap_angle_rad
from agent.world_model import WorldModel
from agent.protocol.constants import CYCLE_S

logger = logging.getLogger(__name__)

KICK, STRONG = "kick", "kick_strong"
TURNS = (TURN_LEFT, TURN_RIGHT)
#: Lean rate limit of the walks this skill steers [1/s]: the walk skills' (a sudden lean can topple).
LEAN_RATE_PER_S = WalkConfig.lean_rate_per_s


def _step_size(motion: MotionController, name: str, key: str) -> float:
    """Size of a kick step from its motion constant [m] (0 when the library lacks it)."""
    if name not in motion.library:
        return 0.0
    return abs(float(motion.library.get(name).constants.get(key, 0.0)))


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
                spots.append(Spot(name, float(constants["ball_forward_m"]), float(constants["ball_left_m"]),
                                  float(constants.get("ball_direction_deg", 0.0))))
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
        distance_m: the ball distance wanted [m] (the distance-controlled kick: the kick's strike is slowed by
            the controller's kick-distance table, ``agent.motion.dynamic.KickDistance``); None = as far as the
            kick goes. Implies the normal kick, whose table it is, and a loose window no farther than
            ``KickConfig.controlled_loose_forward_max_m``.

    After ``done``: ``kicked`` says whether a kick was played, ``foot`` which motion, ``reason`` why it
    stopped without kicking, ``kick_started_s`` the server time the kick motion was first requested.
    """

    def __init__(self, target_x_m: float, target_y_m: float, strong: bool = False,
                 config: KickConfig | None = None, distance_m: float | None = None) -> None:
        super().__init__()
        if not (math.isfinite(target_x_m) and math.isfinite(target_y_m)):
            raise ValueError(f"KickToward target must be finite, got ({target_x_m!r}, {target_y_m!r})")
        if distance_m is not None and not (math.isfinite(distance_m) and distance_m > 0.0):
            raise ValueError(f"KickToward distance_m must be a positive number of metres, got {distance_m!r}")
        self.target = (float(target_x_m), float(target_y_m))
        self.distance_m = distance_m
        self.strong = strong and distance_m is None
        self._base_config = config or KickConfig()
        self._robot_type: int | None = None
        self._configure(0)  # sets config and _fallback_config; the first step configures the world's robot type
        reach = f" {distance_m:.1f} m" if distance_m is not None else ""
        self.name = f"kick{' strong' if self.strong else ''}{reach} toward ({target_x_m:.1f}, {target_y_m:.1f})"
        self.reset()

    def _configure(self, robot_type: int) -> None:
        """The tolerances this kick plays with for a robot of ``robot_type`` (its own where it has them,
        ``KickConfig.for_robot_type``), narrowed for a distance-controlled or a long kick."""
        self._robot_type = robot_type
        config = self._base_config.for_robot_type(robot_type)
        if self.distance_m is not None:  # an accurate kick waits for a placement its table was measured on
            config = replace(config, loose_forward_max_m=min(config.loose_forward_max_m,
                                                             config.controlled_loose_forward_max_m))
        self._fallback_config = config
        """The normal kick's tolerances: a long kick whose narrow window the ball misses kicks the normal kick
        where that one would kick now (a short kick now beats a long one after more corrections)."""
        self.config = config.for_strong_kick() if self.strong else config  # the long kick: its spot to 2 cm on

    def reset(self) -> None:
        super().reset()
        self.kicked = False
        self.foot: str | None = None
        self.reason = ""
        self.kick_started_s: float | None = None
        self.corrections = 0
        self.approaches = 0
        self.fine_steps = 0
        self._started_s: float | None = None
        self.moves: list[str] = []
        """Kinds and motions of the moves played, in order (for benchmarks and logs)."""
        self._kick_motion: str | None = None
        self._kicks_before = 0
        self._move: Move | None = None
        self._move_started = False
        self._cycles = 0
        self._last_phase: str | None = None
        self._goal_team: tuple[float, float] | None = None
        self._heading_team_rad: float | None = None
        self._lean = 0.0
        self._walk_to: WalkTo | None = None
        self._still_since_s: float | None = None
        self._lost_since_s: float | None = None
        self._unlocalized_since_s: float | None = None

    # ---- perception -----------------------------------------------------------------------------------
    def _ball_ego(self, world: WorldModel) -> tuple[float, float] | None:
        """The ball in the ego frame: the sighting itself when taken while standing still, else through
        the current pose (the robot may have moved since; a ball out of view is remembered a while)."""
        ball = world.ball
        if ball is None:
            return None
        age = ball.age_s(world.now_s)
        still = self._still_since_s
        if ball.forward_m is not None and still is not None and ball.seen_s >= still:
            return ball.forward_m, ball.left_m  # type: ignore[return-value]
        pose = world.pose
        seen_here = self._started_s is not None and ball.seen_s >= self._started_s
        limit = self.config.remembered_ball_s if seen_here else self.config.max_ball_age_s
        if pose is not None and ball.position is not None and age <= limit:
            return pose.to_ego(*ball.position)
        if ball.forward_m is not None and age <= self.config.max_ball_age_s:
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
        return MotionRequest(name, head_deg=self._head(ball), **fields)  # type: ignore[arg-type]

    def _head(self, ball: tuple[float, float] | None) -> tuple[float, float]:
        """Head (yaw, pitch) [deg]: toward the ball, down at the feet when it is near."""
        if ball is None or math.hypot(*ball) < 0.6:
            return 0.0, self.config.head_pitch_deg
        return max(-60.0, min(60.0, math.degrees(math.atan2(ball[1], ball[0])))), -25.0

    # ---- the cycle ------------------------------------------------------------------------------------
    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        if self._robot_type != world.robot_type:
            self._configure(world.robot_type)
        if self._started_s is None:
            self._started_s = world.now_s
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
        pose = world.pose
        if self.strong and STRONG not in motion.library:
            # A robot type without the long kick (agent.motion.library: withheld) plays the kick with its own
            # windows, not the long kick's narrow ones.
            self.strong, self.config = False, self._fallback_config
        if pose is None and math.hypot(*ball) > self.config.approach_far_m:
            return self._wait_for_pose(world)  # not localized: no aim to walk round for; look at the landmarks
        spots = kick_spots(motion, self.strong)
        aim_rad = self._aim_error_rad(world, ball)
        library = set(motion.library.names)
        step_m = _step_size(motion, STEP_FORWARD, "step_forward_m")
        fine_steps = self.fine_steps
        if self._started_s is not None and world.now_s - self._started_s > self.config.fine_steps_within_s:
            fine_steps = self.config.max_fine_steps  # too late for precision
        keep_side = None if self.foot is None else foot_side(self.foot)
        if self.strong:
            alignment, move = plan_with_fallback(self.config, self._fallback_config, ball, aim_rad, spots,
                                                 kick_spots(motion, False), library, self.corrections,
                                                 self.approaches, fine_steps, pose is not None, step_m, keep_side)
        else:
            alignment, move = plan(self.config, ball, aim_rad, spots, library, self.corrections, self.approaches,
                                   fine_steps, pose is not None, step_m, keep_side)
        self.foot = alignment.spot.motion
        logger.debug("t=%.2f ball (%.3f, %.3f) spot %s error (%+.3f, %+.3f) aim %+.1f deg -> %s %s (%s)",
                     world.now_s, ball[0], ball[1], alignment.spot.motion, alignment.error_f, alignment.error_l,
                     alignment.aim_deg, move.kind, move.motion, move.why)
        self._unlocalized_since_s = None
        if move.kind == "give_up":
            self.done, self.reason = True, move.why
            return self._request(None, ball)
        self.moves.append(f"{move.kind}:{move.motion}" + (f"x{move.strides}" if move.strides
                                                            else ""))
        if move.kind == "kick":
            assert move.motion is not None
            self._kick_motion = move.motion
            self._kicks_before = motion.completed[move.motion]
            self.kick_started_s = world.now_s
            return self._request(move.motion, ball)
        if move.fine:
            self.fine_steps += 1
        if move.kind in ("approach", "walk_to"):
            self.approaches += 1
            assert pose is not None and move.goal_ego is not None
            self._goal_team = pose.to_team(*move.goal_ego)
            self._heading_team_rad = None
            if move.kind == "walk_to":
                self._walk_to = WalkTo(*self._goal_team, WalkConfig(arrive_m=self.config.walk_to_m - 0.5))
        else:
            self.corrections += 1
            self._goal_team = None
            self._heading_team_rad = None if pose is None else pose.heading_rad + aim_rad - alignment.turned_back_rad
        self._move, self._move_started, self._cycles, self._last_phase = move, False, 0, None
        self._lean = 0.0
        self._still_since_s = None
        return self._moving(world, motion) or self._request(None, ball)

    def _wait_for_pose(self, world: WorldModel) -> MotionRequest:
        if self._unlocalized_since_s is None:
            self._unlocalized_since_s = world.now_s
        if world.now_s - self._unlocalized_since_s > self.config.lost_timeout_s:
            self.done, self.reason = True, "not localized: cannot walk to the ball"
        sweep = 60.0 * math.sin((world.now_s - self._unlocalized_since_s) * 1.5)
        return MotionRequest(None, head_deg=(sweep, 0.0))

    # ---- moves ----------------------------------------------------------------------------------------
    def _moving(self, world: WorldModel, motion: MotionController) -> MotionRequest | None:
        """The request while a move is under way (None when there is none or it has ended)."""
        move = self._move
        if move is None:
            return None
        head = self._head(self._ball_ego(world))
        if move.kind == "walk_to":
            walk_to = self._walk_to
            assert walk_to is not None
            if not walk_to.done:
                return walk_to.step(world, motion)
            if not motion.idle:
                return MotionRequest(None, head_deg=head)
            self._move, self._walk_to, self._still_since_s = None, None, None
            return None
        if not self._move_started:
            if motion.motion_name != move.motion:
                return MotionRequest(move.motion, turn_deg=move.turn_deg, head_deg=head)
            self._move_started = True
        if motion.motion_name == move.motion:
            if move.motion in TURNS:
                return MotionRequest(move.motion, turn_deg=move.turn_deg, head_deg=head)
            if move.strides and not motion.stopping:
                return self._striding(world, motion, move, head)
            # any other walk: asked to stop at once (one short walk); a kick step: let it finish
            return MotionRequest(None, head_deg=head)
        if motion.motion_name is not None:
            return MotionRequest(None, head_deg=head)
        self._move = None
        self._still_since_s = None
        return None

    def _striding(self, world: WorldModel, motion: MotionController, move: Move,
                  head: tuple[float, float]) -> MotionRequest:
        """A forward walk of ``move.strides`` cycles: walk on, steered by the lean toward the goal point (an
        approach) or the aim heading (a walk-in), until that many cycles have begun, then stop."""
        phase = motion.phase_name or ""
        last = self._last_phase or ""
        if phase.startswith("cycle") and (not last.startswith("cycle") or phase < last):
            self._cycles += 1
        self._last_phase = phase
        if self._cycles >= move.strides:
            return MotionRequest(None, head_deg=head)
        error_deg = 0.0
        pose = world.pose
        if pose is not None and self._goal_team is not None:
            forward, left = pose.to_ego(*self._goal_team)
            if forward > 0.1:
                error_deg = math.degrees(math.atan2(left, forward))
        elif pose is not None and self._heading_team_rad is not None:
            error_deg = math.degrees(wrap_angle_rad(self._heading_team_rad - pose.heading_rad))
        config = self.config
        wanted = max(-config.max_lean, min(config.max_lean, error_deg / config.lean_full_deg * config.max_lean))
        if not phase.startswith("cycle") or move.motion != FORWARD:
            wanted = 0.0  # the lean acts in the cycle phases only; start from 0 there
        step = LEAN_RATE_PER_S * CYCLE_S
        self._lean += max(-step, min(step, wanted - self._lean))
        return MotionRequest(move.motion, lean=self._lean, head_deg=head)

    def _kicking(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        name = self._kick_motion
        assert name is not None
        if motion.completed[name] > self._kicks_before:
            self.done, self.kicked = True, True
            return self._request(None)
        return MotionRequest(name, head_deg=(0.0, self.config.head_pitch_deg), distance_m=self.distance_m)


__all__ = ["KickConfig", "KickToward", "Spot", "kick_spots"]
