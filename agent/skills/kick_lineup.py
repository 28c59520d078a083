"""Lining up for a kick: where the ball lies against the kick spot, and the one move that brings it there
fastest (pure: values in, a move out; ``agent.skills.kick.KickToward`` plays the moves).

Measured on our simulator (the walk benchmark's gait, the kick benchmark's kicks), the moves are coarse:

* a forward walk covers a fixed distance per cycle begun: stopped in (or before) its first cycle it still
  walks 0.33 m (start ramp, one cycle, stop ramp), 0.44 m in its second, and each further cycle adds
  0.118 m, whatever the moment of the stop request within the cycle; so a walk-in is planned as a count of
  cycles ("strides"): the one that leaves the ball nearest to ``walk_in_target_m`` beyond its spot without
  the last swing reaching the ball;
* a sideways walk moves at least 0.27 m, a backward walk at least 0.30 m (2.1-2.4 s each), then 9-10 cm
  per further cycle;
* a kick step moves 2 cm in 2.5 s; a turn motion turns up to about 40° in 0.7 s;
* the kick itself is forgiving along its line (the ball 1.5 cm nearer to 9 cm farther than its spot
  still flies 1.9-3.5 m within about 11°, farthest from the spot itself) and less so across it (outward)
  and in heading (the ball follows the robot's heading error almost one to one).

Hence the order: far from the kick pose, walk to a point behind the ball on the kick line (with the walk
skill from beyond 2.5 m, then turning toward the point and walking counted strides); with the ball at the
feet and the aim far off, back off first (a turn there would swing the feet into the ball); face the aim;
one walk-in of counted strides along the kick line; kick. Kick steps and sideways or backward walks only
for what the walk-in cannot fix, and the loose window when such a correction would cost more than it gains.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from agent.skills.walk import BACKWARD, FORWARD, TURN_LEFT, TURN_RIGHT
from agent.skills.walk import LEFT as SIDE_LEFT
from agent.skills.walk import RIGHT as SIDE_RIGHT

#: The name of a kick motion's left-foot mirror is its right-foot name plus this.
LEFT_SUFFIX = "_left"
STEP_FORWARD, STEP_BACKWARD = "kick_step_forward", "kick_step_backward"
STEP_LEFT, STEP_RIGHT = "kick_step_left", "kick_step_right"
#: What a kick step moves (``motions.authoring.kick_steps``) [m]; planning only needs it roughly.
KICK_STEP_M = 0.02

#: ``KickConfig`` fields a robot type plays with instead of the defaults (type 0's), where its walk or its kick
#: differs by more than the line-up forgives. Measured 2026-11-30:
#:
#: * the forward walk from a stand stopped as ``KickToward`` stops it, in its 1st / 2nd / 3rd cycle (torso, ground
#:   truth; real rcssserver3d 0.7.3 / ours) [m]: type 0 0.320 / 0.331, 0.429 / 0.438, 0.540 / 0.558; type 1 0.342 /
#:   0.353, 0.447 / 0.484, 0.560 / 0.612; type 3 0.293 / 0.319, 0.393 / 0.428, 0.487 / 0.529; type 4 0.311 / 0.332,
#:   0.424 / 0.443, 0.535 / 0.559. The other types lie within 2.4 cm of the defaults (their line-ups kick 3.3-4.9 m
#:   on both servers); type 3's own walk (type3/walk_forward.xml, shorter steps) walks in 3-7 cm less, and planned
#:   with the defaults its walk-ins ended 5.7-5.9 cm beyond the plan on the real server, where its kick grazes the
#:   ball: its line-up kicked 0.09 m from 45 and 55 cm there.
#: * type 3's kick window along the line (``kick_check kick --type 3 --offsets-cm=-4,...,3``, from the spot of the
#:   day, 1 cm farther than today's, ``motions/files/robot_types.toml``): real -2.5 to +2.5 cm (4.6-5.1 m; grazes
#:   at -3 and +3), ours -3 to +1 cm (5.0-5.6 m; 0.33 m at +1.5, grazes beyond). Counted from today's spot, the two
#:   overlap from -1.5 to +2 cm: type 3's loose window is that overlap (the default one, -3.4 to +4.1 cm, reaches
#:   far beyond it), and its walk-in plans with the mean of the two servers' distances and aims at +0.6 cm, so that
#:   either server's walk-in (1.3-2.1 cm farther on ours than the other) ends inside the overlap.
KICK_CONFIG_BY_TYPE: dict[int, dict[str, float]] = {
    3: {"walk_in_first_m": 0.306, "walk_in_second_m": 0.41, "stride_m": 0.0975, "walk_in_target_m": 0.006,
        "walk_in_min_after_m": -0.012, "loose_forward_min_m": -0.015, "loose_forward_max_m": 0.02,
        "fine_far_m": 0.02},
}


@dataclass(frozen=True)
class KickConfig:
    """Tolerances and move sizes of the kick skill (numbers measured on our simulator; see the module
    docstring and the kick benchmark)."""

    aim_ball_direction: bool = False
    """Face the aim turned back by the kick's measured ball direction (``Spot.direction_deg``: the shipped kick
    sends the ball 7.6-8.5 deg to the kicking foot's side on the real server), so the ball leaves along the aim.
    Off by default: the turn at the ball shifts it across the kick line and the line-up takes longer. Measured
    2026-11-28 (``motion-studio real skills kick_lineup_<d>cm``, the kick-off taker 45, 50, 55 cm behind the ball;
    real / ours): without it the ball goes 3.80 / 3.96, 4.25 / 3.97, 4.24 / 4.23 m at +7.0, +5.9, -7.4 deg (real),
    ours kicking 6.9, 3.9, 6.3 s into the case; with it 3.77 / 4.38, 4.07 / 4.21, 0.73 (a graze) / 4.30 m at -2.6,
    -0.0, -2.5 deg (real) and +2.8 to +3.4 (ours), ours kicking 12.3, 11.8, 14.2 s in. On ours' kick benchmark
    (``motion-studio bench skills --skill kick``, seed 0): KickToward's direction error 8.8 -> 4.2 deg mean, but 2 of
    18 distance-controlled kicks give up (none without)."""
    heading_tol_deg: float = 5.0
    """Aim error corrected with a turn motion when larger [deg] (the ball's direction error follows it one
    to one; the smallest turn motion turns 2°)."""
    fine_heading_tol_deg: float = 3.0
    """... and this one while a fine kick step is still allowed (see ``fine_steps_within_s``) [deg]."""
    forward_min_m: float = 0.0
    """Kick window along the kick line: the ball at least this far beyond its spot [m]. The kick has two regimes
    along its line, on both servers (``python -m motion_studio.realserver.kick_check kick --offsets-cm=-1,...,3``,
    2026-11-28, offsets from the spot of that day, 4 mm nearer than today's): on the real server 3.2-3.3 m at
    -0.6 deg from up to 2.5 mm short of that spot, 4.0-4.4 m at -8.5 deg from 1 mm short to 3 cm beyond; on ours
    the same boundary with a 3 mm pocket on it (1.2-2.3 m). From 4 mm beyond it, both kick in the far regime, so
    the spot itself moved there (``ball_ahead_m`` of motions/params/kick.toml; real 4.07 / 4.09 m, ours 4.33 m
    for the right / left kick); every window below is counted from the moved spot (4 mm less than before)..."""
    forward_max_m: float = 0.011
    """... and at most this far [m] (the walk-in aims at the window's middle; real 4.05-4.09 m from the spot to 2
    mm beyond, 3.93 m from 6 mm beyond)."""
    lateral_in_m: float = 0.03
    """Ball across the kick line off its spot toward the robot's middle: kick when within [m] (4 cm in
    still flies 1.9-3 m within 8°)..."""
    lateral_out_m: float = 0.015
    """... and away from it [m] (4 cm out sends the ball 12-35° off: the foot meets it off centre)."""
    loose_forward_min_m: float = -0.034
    """Loose window, taken when the correction would be a slow one (kick steps, sideways or backward walks)
    or the corrections are used up: along the line from [m]..."""
    loose_forward_max_m: float = 0.041
    """... to [m]: on the real rcssserver3d 0.7.3 the kick grazes the ball from 6 cm beyond its spot (kick_check,
    2026-11-26: 4.06 m from +5 cm, 0.08 m from +6 cm), and the walk-in there ends 1.5-2.3 cm farther from the ball
    than ours. With 0.08 (the retuned kick of ec1e311 flies 2.8-2.9 m on ours from 3.5-8 cm) the kick-off taker's
    line-up under the beam's noise (robot 0.45-0.55 m behind the ball, heading -8/0/+8 deg, 18 starts: the
    ``kick_lineup_<d>cm`` cases of ``motion-studio real skills`` turned by the heading) grazed the ball (0.02-0.10
    m) in 9 of 18 starts on the real server, from +5.5 to +6.3 cm; with 0.045, kick steps into this window and the
    step back before a walk-in that would end short (``plan``): 0 of 18, every kick 3.1-4.4 m, the ball moving 7.8 s
    after the stand on average instead of 5.8; ours 3 of 18 short kicks (0.5-0.7 m) before, none after..."""
    loose_lateral_in_m: float = 0.04
    """... and across it within this toward the middle [m]..."""
    loose_lateral_out_m: float = 0.022
    """... and this away from it [m]."""
    controlled_loose_forward_max_m: float = 0.031
    """The loose window's far end for a distance-controlled kick (``KickToward(distance_m=...)``) [m]: its
    table was measured with the ball within 2 cm of the spot (on the real server the kick grazes the ball from
    6 cm beyond it). KickToward asked for 2, 3 and 4 m on ours (seeds 0-2, 3 kicks each, ``motion_studio.
    skill_bench.kick.controlled_trials``): within +-1 m 15 -> 21 of 27, grazes 8 -> 3, 3.2 s longer on
    average, against the loose window's 0.08."""
    strong_forward_min_m: float = 0.0
    """The long kick's window (``KickToward(strong=True)``, ``kick_strong``; it bounds the strict window too),
    from [m]... On the real server with its landing retimed (``kick_check --offsets-cm=-1..2``, types 0, 2, 4):
    5.1-5.6 m from the spot to 2 cm beyond (type 4 4.0-5.4), 0.9-4.0 m from 1 cm short and once from 0.5 cm
    short (the toe meets the ball a cycle late). Before the retiming
    (2026-11-27, ball along the kick line from its spot: real server 0.3, 0.8, 7.6 or 0.0 (right / left foot),
    5.1-5.7, 5.1, 6.6, 4.1 and 0.0 m from -4, -3, -2, -1..+1, +2, +3, +3.5 and +4.5 cm; ours 0.3 (fell), 0.3
    (fell), 2.4-2.7, 0.0-0.1, 4.4-4.7, 4.6, 0.0 m from -4, -3, -2, -1.5, -1..+2, +2.5, +3 cm: short of the
    window the toe stubs the ground before the ball, beyond it the swinging foot comes down on the ball; outside
    it the skill kicks the normal kick where that one would kick)..."""
    strong_forward_max_m: float = 0.02
    """... to [m]."""
    walk_in_target_m: float = 0.011
    """A walk-in aims to leave the ball this far beyond its spot [m]..."""
    walk_in_min_after_m: float = -0.009
    """... and never nearer than this (the swinging foot of the last step reaches further than the stance
    toes: a walk-in planned to end 1.8 cm nearer pushed the ball 6 cm away) [m]."""
    walk_in_first_m: float = 0.333
    """Distance of a forward walk stopped in its first cycle (or before it: the start ramp has no exit) [m]
    (measured 0.330-0.337)..."""
    walk_in_second_m: float = 0.441
    """... in its second cycle [m] (measured 0.441-0.448)..."""
    stride_m: float = 0.118
    """... and what each further cycle adds [m] (measured 0.56, 0.675, 0.80 m for 3-5 cycles). These three are
    robot type 0's on ours; :meth:`for_robot_type` puts a type's own in (``KICK_CONFIG_BY_TYPE``)."""
    side_walk_m: float = 0.27
    """Sideways walk stopped in its first cycle [m] (measured 0.27)..."""
    side_stride_m: float = 0.089
    """... and what each further cycle adds [m] (measured 0.357, 0.448, 0.536 m for 2-4 cycles)."""
    backward_walk_m: float = 0.30
    """Backward walk stopped in its first cycle [m] (measured 0.30)..."""
    backward_stride_m: float = 0.096
    """... and what each further backward cycle adds [m] (measured 0.40, 0.50, 0.59 m for 2-4 cycles)."""
    lateral_walk_in_m: float = 0.06
    """A sideways offset up to this is left to the walk-in and the kick steps; a larger one (below the
    sideways walk's reach) is walked round: turn toward a point on the kick line, walk, turn back [m]."""
    approach_back_m: float = 0.47
    """Walking to the ball from afar ends this far behind the kick pose on the kick line [m]: one stride of
    walk-in plus the window's middle, so that an approach off by half a stride still leaves a walk-in."""
    approach_far_m: float = 0.6
    """Not facing the aim, the robot walks to the approach point first when the kick pose is farther than
    this [m] (nearer, it turns in place and walks in)."""
    wrong_side_m: float = 0.05
    """Not facing the aim with the kick pose this far behind the robot, it walks round [m]."""
    turn_near_deg: float = 25.0
    """An aim error larger than this is not turned out with the ball at the feet, nor walked round from
    there: the robot backs off to ``room_m`` first [deg]..."""
    ball_near_m: float = 0.35
    """... when the ball lies nearer than this [m]."""
    room_m: float = 0.6
    """Backing off ends with the kick pose at least this far ahead [m]..."""
    behind_m: float = 0.3
    """... unless the kick pose lies more than this behind the robot (the robot stands on the far side of
    the ball: backing off does not help, it walks round the ball) [m]."""
    walk_to_m: float = 2.5
    """An approach point farther than this is walked toward with ``agent.skills.walk.WalkTo`` (steering,
    obstacle avoidance) until it is ``walk_to_m - 0.5`` away; the counted strides take the rest [m]."""
    approach_min_m: float = 0.25
    """An approach point nearer than this is not walked to; the robot turns to the aim where it is [m]."""
    approach_turn_deg: float = 12.0
    """Before walking to the approach point the robot turns toward it if its bearing is larger [deg]."""
    ball_clearance_m: float = 0.25
    """A walk to the approach point passing nearer than this to the ball goes round it [m]."""
    max_lean: float = 0.4
    """Largest walk lean while walking to a point or along the kick line (a full lean toppled walks)."""
    lean_full_deg: float = 15.0
    """Heading error asking for the full lean (``max_lean``) [deg]."""
    max_fine_steps: int = 1
    """Kick steps taken to bring a ball already in the loose window into the window (2.5 s each), or from
    beyond ``fine_far_m`` along the line to within it..."""
    fine_far_m: float = 0.041
    """... (farther, the kick flies 10-12° off on ours and grazes the ball on the real server: the loose window's
    end) [m]..."""
    fine_steps_within_s: float = 4.0
    """... only this long after the skill's start [s]: later the loose window is kicked at once (in a
    match or the kick challenge a kick now beats a better one 2.5 s later)."""
    max_corrections: int = 10
    """Moves near the ball before kicking within the loose window or giving up."""
    max_approaches: int = 3
    """Walks to an approach point; then only turns and the near-ball moves."""
    settle_s: float = 0.1
    """Wait after a move for a ball sighting taken standing still [s] (a walk ends with 0.2 s on the spot
    already; the camera sees every 3rd cycle)."""
    max_ball_age_s: float = 3.0
    """A ball sighting older than this counts as lost [s]..."""
    remembered_ball_s: float = 10.0
    """... unless localized and seen since the skill started: then the ball's field position is trusted this
    long (turning and walking round the ball, the camera loses it for seconds) [s]."""
    lost_timeout_s: float = 8.0
    """Give up after the ball has been lost this long [s]."""
    head_pitch_deg: float = -45.0
    """Head pitch while lining up close to the ball [deg] (down: the ball lies at the feet)."""

    def for_strong_kick(self) -> KickConfig:
        """These tolerances with both windows along the kick line kept within the long kick's
        (``strong_forward_min_m`` / ``strong_forward_max_m``)."""
        return replace(self, forward_min_m=max(self.forward_min_m, self.strong_forward_min_m),
                       loose_forward_min_m=max(self.loose_forward_min_m, self.strong_forward_min_m),
                       loose_forward_max_m=min(self.loose_forward_max_m, self.strong_forward_max_m))

    def for_robot_type(self, robot_type: int) -> KickConfig:
        """These tolerances with a robot type's own where it has them (``KICK_CONFIG_BY_TYPE``)."""
        return replace(self, **KICK_CONFIG_BY_TYPE.get(robot_type, {}))

    def walk_in_m(self, strides: int) -> float:
        """Distance of a forward walk stopped in its ``strides``-th cycle (>= 1) [m]."""
        if strides <= 1:
            return self.walk_in_first_m
        return self.walk_in_second_m + (strides - 2) * self.stride_m

    @property
    def window_middle_m(self) -> float:
        return (self.forward_min_m + self.forward_max_m) / 2


@dataclass(frozen=True)
class Spot:
    """Where a kick motion wants the ball: ego (forward, left) [m]; and where it sends it."""

    motion: str
    forward_m: float
    left_m: float
    direction_deg: float = 0.0
    """The ball's direction against the robot's heading when this motion kicks it from the spot [deg] (+ = left;
    the motion's constant ``ball_direction_deg``): the robot faces this much the other way of its aim. Measured on
    the real server, the shipped kick sends the ball 7.6-8.5 deg to the kicking foot's side (every robot type
    7.2-8.5), the long kick straight (``motions/params/kick.toml``)."""


@dataclass(frozen=True)
class Alignment:
    """The ball against a spot, in the aim frame (x along the aim from the torso, y to its left)."""

    spot: Spot
    error_f: float
    """Ball beyond its spot along the kick line [m] (+ = too far ahead: walk in)."""
    error_l: float
    """Ball left of its spot across the kick line [m]."""
    aim_rad: float
    """Heading change to the kick pose [rad]: facing the aim (``turned_back_rad`` less)."""
    turned_back_rad: float = 0.0
    """How far the kick pose turns back from the aim for the spot's ball direction [rad] (0 unless directed)."""

    @property
    def aim_deg(self) -> float:
        return math.degrees(self.aim_rad)


#: With ``KickConfig.aim_ball_direction`` the foot of the last plan keeps the kick unless the other one's misfit
#: (``align``) is this much smaller: the two feet's kick poses face 16 deg apart, and a ball near the middle flipped
#: the choice from one plan to the next, each flip a turn (with a margin of 0.5 the distance-controlled kick gave up
#: in 8 of 18 requests on ours, the kick-off taker's line-up from 45 cm never kicked).
KEEP_FOOT_MISFIT = 3.0


def foot_side(motion: str) -> str:
    """The kicking foot of a kick motion: "left" for the mirrored ones (``*_left``), else "right"."""
    return "left" if motion.endswith(LEFT_SUFFIX) else "right"


def align(ball: tuple[float, float], aim_rad: float, spots: list[Spot], config: KickConfig,
          directed: bool = False, keep_side: str | None = None) -> Alignment:
    """The spot (foot) that suits the ball best seen from the kick pose, and the ball's offset from it.

    The foot is chosen in the aim's frame; its kick pose then faces the aim turned back by the spot's
    ``direction_deg`` (``directed``; without it, as when the robot cannot turn, it faces the aim itself), so the
    ball leaves toward the aim. (Chosen in each spot's own frame, the feet's frames 16 deg apart, the choice flipped
    between the feet as the robot turned, and the line-up turned back and forth until it timed out.) The offset is
    also where the kick pose lies: standing (error_f, error_l) further along that frame and facing along it puts
    the ball on the spot. ``keep_side``: the foot of the last plan, kept unless the other fits clearly better
    (``KEEP_FOOT_MISFIT``).
    """
    def frame(facing: float) -> tuple[float, float]:
        c, s = math.cos(facing), math.sin(facing)
        return c * ball[0] + s * ball[1], -s * ball[0] + c * ball[1]

    along, across = frame(aim_rad)

    def misfit(spot: Spot) -> float:
        error_l = across - spot.left_m
        kept = KEEP_FOOT_MISFIT if keep_side is not None and foot_side(spot.motion) == keep_side else 0.0
        return (abs(error_l) / _lateral_limit(config, spot, error_l, loose=False)
                + abs(along - spot.forward_m - config.window_middle_m) / config.stride_m - kept)

    spot = min(spots, key=misfit)
    turned_back = math.radians(spot.direction_deg) if directed else 0.0
    if turned_back:
        along, across = frame(aim_rad - turned_back)
    return Alignment(spot, along - spot.forward_m, across - spot.left_m, aim_rad - turned_back, turned_back)


def _lateral_limit(config: KickConfig, spot: Spot, error_l: float, loose: bool) -> float:
    """The lateral tolerance on the side the ball lies off its spot: outward = away from the robot's
    middle, the side of the spot itself."""
    outward = error_l * spot.left_m > 0
    if loose:
        return config.loose_lateral_out_m if outward else config.loose_lateral_in_m
    return config.lateral_out_m if outward else config.lateral_in_m


def to_ego(point: tuple[float, float], aim_rad: float) -> tuple[float, float]:
    """An aim-frame point in the ego frame."""
    c, s = math.cos(aim_rad), math.sin(aim_rad)
    return c * point[0] - s * point[1], s * point[0] + c * point[1]


@dataclass(frozen=True)
class Move:
    """One move of the line-up.

    ``kind``: ``kick`` (play ``motion``), ``turn`` (``motion`` by ``turn_deg``), ``walk_in`` (forward walk of
    ``strides`` holding the aim), ``approach`` (forward walk of ``strides`` toward ``goal_ego``),
    ``walk_side`` (sideways walk ``motion`` of ``strides``), ``walk_back`` (backward, ``strides``), ``walk_to``
    (the walk skill toward ``goal_ego``, from afar), ``move``
    (one short request of a walk or a kick step), ``give_up``.
    """

    kind: str
    motion: str | None = None
    turn_deg: float | None = None
    strides: int = 0
    goal_ego: tuple[float, float] | None = None
    fine: bool = False
    """A kick step taken from within the loose window (counted against ``max_fine_steps``)."""
    why: str = ""


def strides_for(config: KickConfig, distance_m: float) -> tuple[int, float]:
    """Forward-walk strides that leave the ball nearest to ``walk_in_target_m`` without ending nearer than
    ``walk_in_min_after_m``, and the ball's predicted offset from its spot after them [m] (distance_m: the
    ball's offset now)."""
    target = config.walk_in_target_m
    guess = max(2, 2 + round((distance_m - target - config.walk_in_second_m) / config.stride_m))
    options = [n for n in (guess - 1, guess, guess + 1) if n >= 1]
    clear = [n for n in options if distance_m - config.walk_in_m(n) >= config.walk_in_min_after_m] or [1]
    strides = min(clear, key=lambda n: abs(distance_m - config.walk_in_m(n) - target))
    return strides, distance_m - config.walk_in_m(strides)


def _in_window(config: KickConfig, a: Alignment, loose: bool) -> bool:
    lateral = abs(a.error_l) <= _lateral_limit(config, a.spot, a.error_l, loose)
    if loose:
        return config.loose_forward_min_m <= a.error_f <= config.loose_forward_max_m and lateral
    return config.forward_min_m <= a.error_f <= config.forward_max_m and lateral


def _approach_goal(config: KickConfig, ball: tuple[float, float], a: Alignment) -> tuple[float, float]:
    """The ego point ``approach_back_m`` behind the kick pose on the kick line, or a point beside the ball
    first when the straight walk there would pass over the ball."""
    goal = to_ego((a.error_f - config.approach_back_m, a.error_l), a.aim_rad)
    length = math.hypot(*goal)
    if length < 1e-6:
        return goal
    # Distance of the ball from the segment torso -> goal.
    t = max(0.0, min(1.0, (ball[0] * goal[0] + ball[1] * goal[1]) / length ** 2))
    gap = math.hypot(ball[0] - t * goal[0], ball[1] - t * goal[1])
    if gap >= config.ball_clearance_m or t <= 0.0 or t >= 1.0:
        return goal
    # Round the ball on the side the path already leans to: a point abeam the ball, clearance + margin away.
    side = 1.0 if (goal[0] * ball[1] - goal[1] * ball[0]) < 0 else -1.0
    ux, uy = goal[0] / length, goal[1] / length
    offset = config.ball_clearance_m + 0.1
    return ball[0] - side * uy * offset, ball[1] + side * ux * offset


def plan(config: KickConfig, ball: tuple[float, float], aim_rad: float, spots: list[Spot],
         motions: frozenset[str] | set[str], corrections: int, approaches: int, fine_steps: int, localized: bool,
         step_m: float = KICK_STEP_M, keep_side: str | None = None) -> tuple[Alignment, Move]:
    """The next move for a standing robot.

    Args:
        ball: the ball in the ego frame [m] (a sighting taken standing still).
        aim_rad: heading change that faces the aim (0 when not localized).
        spots: the kick motions' ball spots (see ``agent.skills.kick.kick_spots``).
        motions: names in the motion library (missing moves are skipped: place-and-kick).
        corrections: moves made so far near the ball; approaches: walks to an approach point so far;
        fine_steps: kick steps taken from within the loose window so far.
        localized: a self pose exists (approaches steer by it).
        step_m: what one kick step moves [m].
        keep_side: the kicking foot of the last plan ("right"/"left"), kept unless the other fits clearly better
            (with ``config.aim_ball_direction`` only).
    """
    can_turn = TURN_LEFT in motions and TURN_RIGHT in motions
    # Without turn motions the kick goes where the robot faces: line up along the heading.
    directed = config.aim_ball_direction and can_turn
    a = align(ball, aim_rad if can_turn else 0.0, spots, config, directed=directed,
              keep_side=keep_side if directed else None)
    can_correct = corrections < config.max_corrections
    precise = fine_steps < config.max_fine_steps  # early on: worth a small turn too
    heading_ok = abs(a.aim_deg) <= (config.fine_heading_tol_deg if precise else config.heading_tol_deg)
    kick = Move("kick", a.spot.motion, why="in the window")
    if heading_ok and _in_window(config, a, loose=False):
        return a, kick
    if not can_correct:
        if heading_ok and _in_window(config, a, loose=True):
            return a, Move("kick", a.spot.motion, why="corrections used up, in the loose window")
        return a, Move("give_up", why=f"ball off the kick spot by ({a.error_f:+.2f}, {a.error_l:+.2f}) m, "
                                        f"aim {a.aim_deg:+.0f} deg, and no correction left")
    walk = FORWARD in motions
    if not heading_ok:
        # Far from the kick pose, or on the wrong side of the ball: walk to the approach point first; near
        # it, turn where the robot stands (the walk-in or the fine moves take the rest).
        if (abs(a.aim_deg) > config.turn_near_deg and math.hypot(*ball) < config.ball_near_m
                and BACKWARD in motions and -config.behind_m <= a.error_f < config.room_m):
            # Ball at the feet and far off the aim: a turn here or a walk round would kick it; room first.
            return a, Move("walk_back", BACKWARD, strides=_back_strides(config, config.room_m - a.error_f),
                           why="back off to walk round to the kick line")
        goal = _approach_goal(config, ball, a)
        far = (math.hypot(a.error_f, a.error_l) > config.approach_far_m or a.error_f < -config.wrong_side_m
               or abs(a.error_l) > config.lateral_walk_in_m)
        if (far and walk and localized and approaches < config.max_approaches
                and math.hypot(*goal) > config.approach_min_m):
            return a, _toward(config, goal, can_turn)
        return a, Move("turn", TURN_LEFT if a.aim_rad > 0 else TURN_RIGHT, turn_deg=abs(a.aim_deg), why="face the aim")
    # Facing the aim: a large sideways offset first (walk sideways, or round to the kick line), then the
    # walk-in along the line, then the fine moves for what is left (or the loose window, if they are slow).
    goal = _approach_goal(config, ball, a)
    can_approach = (walk and localized and approaches < config.max_approaches
                    and math.hypot(*goal) > config.approach_min_m)
    if can_approach and math.hypot(a.error_f, a.error_l) > config.walk_to_m:
        return a, _toward(config, goal, can_turn)  # far: a long walk-in or sideways walk drifts
    side = SIDE_LEFT if a.error_l > 0 else SIDE_RIGHT
    if abs(a.error_l) >= config.side_walk_m - config.side_stride_m / 2 and side in motions:
        strides = _side_strides(config, abs(a.error_l))
        return a, Move("walk_side", side, strides=strides, why="sideways walk")
    wide = abs(a.error_l) > config.lateral_walk_in_m
    if wide and can_approach and a.error_f > config.approach_back_m:
        return a, _toward(config, goal, can_turn)
    if a.error_f > config.forward_max_m and walk and not wide:
        strides, after = strides_for(config, a.error_f)
        longer = a.error_f - config.walk_in_m(strides + 1)
        if (strides == 1 and after > config.loose_forward_max_m and longer >= config.walk_in_min_after_m - step_m
                and STEP_BACKWARD in motions):
            # Between the one- and the two-cycle walk-in (10-11 cm apart): the shorter ends beyond the loose window
            # (then kick steps, or a back-off, which walked in to the same place again on the real server: type 3
            # from 55 cm), the longer a step short: step back first. (Farther, the ball's sighting is too coarse
            # for a 2 cm step to count.)
            return a, Move("move", STEP_BACKWARD, why=f"kick step back: a walk-in would end {after:+.3f} m or "
                                                      f"{longer:+.3f} m")
        if after >= config.walk_in_min_after_m:
            return a, Move("walk_in", FORWARD, strides=strides, why=f"walk in, {after:+.3f} m after")
        # One stride too long by a step or two: step back rather than walk onto the ball (planned to end 2.7 cm
        # short, a real walk-in pushed the ball away; the kick-off taker stands in this band after 1 in 4 beams).
        if after >= config.walk_in_min_after_m - 2 * step_m and STEP_BACKWARD in motions:
            return a, Move("move", STEP_BACKWARD, why=f"kick step back: a walk-in would end {after:+.3f} m")
    if fine_steps < config.max_fine_steps:
        fine = _fine_step(config, a, motions, step_m)
        if fine is not None:
            return a, fine
    if _in_window(config, a, loose=True):
        return a, Move("kick", a.spot.motion, why="loose window (the fine moves cost 2.5 s each)")
    # Outside the loose window, near the ball: kick steps for a few centimetres, else back off to make room
    # for a walk-in or an approach.
    if wide and can_approach and BACKWARD in motions:
        return a, Move("move", BACKWARD, why="back off to walk round to the kick line")
    lateral_bad = abs(a.error_l) > _lateral_limit(config, a.spot, a.error_l, loose=False)
    step = STEP_LEFT if a.error_l > 0 else STEP_RIGHT
    if lateral_bad and a.error_f >= 0.0 and step in motions:
        return a, Move("move", step, why="kick step across")
    if a.error_f > config.forward_max_m:
        # Steps that reach the loose window (not only the strict one): on the real server a walk-in ended 5.5-6 cm
        # beyond the spot, one step short of the window's 4.5 cm, and backing off walked in to the same place again.
        if a.error_f - config.loose_forward_max_m <= 2 * step_m and STEP_FORWARD in motions:
            return a, Move("move", STEP_FORWARD, why="kick step forward")
        if BACKWARD in motions:
            return a, Move("move", BACKWARD, why="back off for a walk-in")
    elif a.error_f < config.forward_min_m or lateral_bad:
        if a.error_f >= config.forward_min_m - 2 * step_m and STEP_BACKWARD in motions:
            return a, Move("move", STEP_BACKWARD, why="kick step back (ball at the toes)")
        if BACKWARD in motions:
            return a, Move("move", BACKWARD, why="back off")
    return a, Move("give_up", why=f"ball off the kick spot by ({a.error_f:+.2f}, {a.error_l:+.2f}) m and no motion "
                                  f"left to correct it")


def _back_strides(config: KickConfig, distance_m: float) -> int:
    """Backward-walk cycles that cover at least ``distance_m``."""
    return max(1, 1 + math.ceil((distance_m - config.backward_walk_m) / config.backward_stride_m - 1e-9))


def _side_strides(config: KickConfig, distance_m: float) -> int:
    """Sideways-walk cycles whose walk comes nearest to ``distance_m``."""
    return max(1, 1 + round((distance_m - config.side_walk_m) / config.side_stride_m))


def _fine_step(config: KickConfig, a: Alignment, motions: frozenset[str] | set[str], step_m: float) -> Move | None:
    """One kick step that puts the ball into the (strict) window, if there is one: along the line, or
    across it with the ball clear of the toes (nearer, a sideways step pushed the ball away)."""
    if step_m <= 0.0:
        return None
    along_ok = config.forward_min_m <= a.error_f <= config.forward_max_m
    across_ok = abs(a.error_l) <= _lateral_limit(config, a.spot, a.error_l, loose=False)
    if across_ok and not along_ok:
        name, after = (STEP_FORWARD, a.error_f - step_m) if a.error_f > 0 else (STEP_BACKWARD, a.error_f + step_m)
        into = config.forward_min_m <= after <= config.forward_max_m
        nearer = a.error_f > config.fine_far_m >= after  # out of the loose window's far, inaccurate end
        if (into or nearer) and name in motions:
            return Move("move", name, fine=True, why="one kick step into the window")
    if along_ok and not across_ok and a.error_f >= 0.0:
        name, after = (STEP_LEFT, a.error_l - step_m) if a.error_l > 0 else (STEP_RIGHT, a.error_l + step_m)
        if abs(after) <= _lateral_limit(config, a.spot, after, loose=False) and name in motions:
            return Move("move", name, fine=True, why="one kick step into the window")
    return None


def _toward(config: KickConfig, goal: tuple[float, float], can_turn: bool) -> Move:
    """Turn toward an approach point, or walk there when it lies ahead; from afar with the walk skill
    (steering, obstacle avoidance) to ``walk_to_m`` of it first."""
    distance = math.hypot(*goal)
    if distance > config.walk_to_m:
        return Move("walk_to", FORWARD, goal_ego=goal, why="walk toward the approach point")
    bearing = math.degrees(math.atan2(goal[1], goal[0]))
    if can_turn and abs(bearing) > config.approach_turn_deg:
        return Move("turn", TURN_LEFT if bearing > 0 else TURN_RIGHT, turn_deg=abs(bearing),
                    why="face the approach point")
    strides = min(range(1, 3 + int(distance / config.stride_m)), key=lambda n: abs(config.walk_in_m(n) - distance))
    return Move("approach", FORWARD, strides=strides, goal_ego=goal, why="walk to the approach point")


def plan_with_fallback(config: KickConfig, fallback_config: KickConfig, ball: tuple[float, float], aim_rad: float,
                       spots: list[Spot], fallback_spots: list[Spot], motions: frozenset[str] | set[str],
                       corrections: int, approaches: int, fine_steps: int, localized: bool,
                       step_m: float = KICK_STEP_M, keep_side: str | None = None) -> tuple[Alignment, Move]:
    """:func:`plan` for a kick with a narrow window (the long kick), falling back to another kick (the normal
    one, ``fallback_spots`` with ``fallback_config``) where that one would kick now and the first would first
    correct or give up: a short kick now beats a long one after more corrections (each costs 1-3 s)."""
    alignment, move = plan(config, ball, aim_rad, spots, motions, corrections, approaches, fine_steps, localized,
                           step_m, keep_side)
    if move.kind == "kick":
        return alignment, move
    other, other_move = plan(fallback_config, ball, aim_rad, fallback_spots, motions, corrections, approaches,
                             fine_steps, localized, step_m, keep_side)
    if other_move.kind != "kick":
        return alignment, move
    return other, replace(other_move, why=f"{other_move.why} of the fallback kick (the first would {move.kind})")


__all__ = ["KEEP_FOOT_MISFIT", "LEFT_SUFFIX", "Alignment", "KickConfig", "Move", "Spot", "align", "foot_side", "plan",
           "plan_with_fallback", "strides_for", "to_ego"]
