"""Dribble: walk the ball toward a field point, pushing it with the forward walk.

Why: the kick needs the ball within ±1.5 cm of its spot, and lining up for it took 13-35 s in matches on
our simulator (turns, walk-ins, backing off); the forward walk pushes a ball that lies in front of the feet
and keeps going. This skill is a moving-target walk: behind the ball (on the line target -> ball) the robot
walks at a point just beyond the ball on that line, so each step pushes the ball on toward the target;
elsewhere it walks to the approach point ``behind_m`` behind the ball on that line, going round the ball
when it stands on the wrong side. Steering is the walk's (``agent.skills.walk._Steer``: lean within a band,
a turn motion beyond); near the ball, facing off the target direction, the robot circles the ball with an orbit
(``orbit_left`` / ``orbit_right``) or lines up with short walks; far from the ball other robots are avoided
(``agent.skills.avoid``: walking into an opponent is a charging foul).

``done`` never becomes True by itself: the caller replaces the skill (e.g. when a kick is on).
All positions in the team frame [m], angles [deg] where named ``_deg``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from agent.motion import MotionController, MotionRequest
from agent.protocol.constants import CYCLE_S
from agent.skills.avoid import Avoider
from agent.skills.base import Skill
from agent.skills.walk import (BACKWARD, FORWARD, FORWARD_WALKS, LEFT, ORBIT_LEFT, ORBIT_RIGHT, ORBITS, RIGHT, WALKS,
                               WalkConfig, _Steer, report_walk_odometry)
from agent.world.field import GOAL_HALF_WIDTH_M, HALF_LENGTH_M
from agent.world.frames import Pose2D, wrap_angle_rad
from agent.world_model import WorldModel


@dataclass(frozen=True)
class DribbleConfig:
    """Geometry of the dribble (chosen on our simulator)."""

    behind_m: float = 0.4
    """Going round the ball: the point this far behind it (and ``round_m`` beside it) [m]."""
    behind_min_m: float = 0.05
    """The robot counts as behind the ball when this far behind it along the target line [m]."""
    behind_per_m: float = 0.6
    """Behind the ball and off the target line by d, the robot walks at the point this many times d behind
    the ball on the line [m/m] (1.2 sent a robot 1 m beside the ball on a 3 m detour behind it; with 0.6 the
    path is shorter and the last turn larger, which chained turns make cheap)..."""
    behind_max_m: float = 1.5
    """... at most this far behind it [m]."""
    push_through_m: float = 0.6
    """Pushing, the robot walks at the point this far beyond the ball on the ball -> target line [m]."""
    centre_until_m: float = 0.3
    """Pushing, the robot walks at the ball itself while it lies farther ahead than this, and at the point
    beyond it only from here on [m]. Why: walking at the point beyond, a ball 0.1 m off the walking line stayed
    there (the bearing to a point 1 m away barely leans the walk), and a foot meeting the ball that far out
    sends it 20-50 deg aside or misses it. From 24 starts behind the ball (0.7 and 1.5 m, +-0.04 to +-0.25 m
    across, +-15 deg; a measurement script, not kept) the ball's direction after 12 s was off by 8.3 deg on average
    instead of 13.2 (more than 20 deg: 2 instead of 4)."""
    push_aim_left_m: tuple[float, ...] = (0.0, 0.08, 0.0, 0.11, 0.08)
    """Pushing, the robot walks at a point this far left (ego) of the ball or the push point, per robot type 0-4
    [m], so that the ball meets the front of the right foot rather than the gap between the feet, whose inner
    edges sent it off sideways. Measured from 16 starts 1.0 and 2.2 m behind the ball (+-0.03 and +-0.1 m
    across, +-10 deg, seeds 0 and 1; a measurement script, not kept): the ball's direction 0.3 m after the first touch
    was off by 29 / 24 / 19 deg on average for types 1 / 3 / 4 when walking at the ball itself, 3-5 deg with
    these offsets, and the ball went 5.5-6.0 / 4.6 / 4.8-5.0 m in 12 s instead of 3.2 / 2.8 / 3.6 m. Types 0 and
    2 (the same legs once type 2's ankle is capped) were already straight (4-7 deg); 0.025 did not change that
    (striker alone: 24 of 30 scored instead of 26) and 0.05 sent the ball 11 deg off
    after 12 s."""
    push_lateral_m: float = 0.12
    """Pushing goes on while the ball lies within this of the robot's walking line (ego left) [m]..."""
    push_max_deg: float = 35.0
    """... and the robot's heading is within this of the ball -> target direction [deg]."""
    push_line_deg: float = 25.0
    """Pushing starts only when the line robot -> ball points within this of the ball -> target direction
    [deg]: the robot walks at the ball, so the ball leaves along that line, whatever the heading (the approach
    point ``push_start_m`` behind the ball let a robot 0.33 m off the line start a push 30-50 deg aside)..."""
    push_line_goal_deg: float = 10.0
    """... and within this once the ball is ``goal_zone_m`` from the target [deg]: on the real server a push
    started 22 deg off, 1.7 m before a keeper that only stands, put the ball at its feet for 35 s."""
    goal_zone_m: float = 4.0
    """The ball this near the target counts as near the goal (the tighter push and keep limits) [m]."""
    keep_across_m: float = 0.35
    """Pushing goes on while the robot stays within this of the target line [m]..."""
    keep_lateral_m: float = 0.2
    """... the ball within this of its walking line [m]..."""
    keep_across_goal_m: float = 0.15
    """... within this once the ball is ``goal_zone_m`` from the target [m] (with 0.35 m pushes toward an aim
    beside the keeper went on 0.3 m off their line and over the goal line beside the post)..."""
    keep_ahead_m: float = 1.5
    """... at most this far ahead (a pushed ball rolls on; the robot follows it) [m]..."""
    keep_max_deg: float = 50.0
    """... and its heading within this of the ball -> target direction [deg]."""
    push_start_m: float = 0.2
    """Pushing (walking at the point beyond the ball) once the approach point is within this of the ball [m]."""
    round_m: float = 0.45
    """On the wrong side of the ball, the robot walks to a point this far beside it [m]."""
    avoid_beyond_m: float = 1.0
    """Other robots are avoided while the ball is farther than this [m] (near it, the ball is played)."""
    blocked_ahead_m: float = 0.6
    """An opponent nearer than this in front (torso centres) ...[m]"""
    blocked_side_m: float = 0.3
    """... and within this to the side blocks the forward walk: the robot side-steps [m]."""
    play_through_m: float = 0.25
    """... unless the ball lies ahead of the robot, nearer than that opponent and within this to the side, in
    the opponent penalty area (``play_through_box_m``) [m]: then the robot plays the ball on. Side-stepping
    there left the ball at a standing keeper's feet and the robot stepped back to it, round and round for up to
    90 s of a 120 s match (3 v 3 against robots that only stand, on our simulator, 16 matches during
    development: 26 goals with play-through and 21 without, one 0:0 instead of two). Everywhere on the field
    it doubled the falls of both teams in 11 v 11 against the baseline (walking into opponents that fight for
    the ball: 13-21 falls and 4 INCAPABLE calls per team and match instead of 5)."""
    play_through_box_m: tuple[float, float] = (13.2, 3.0)
    """The opponent penalty area: x beyond the first, |y| within the second (team frame) [m]."""
    goal_mouth_m: float = 1.0
    """A ball ahead of the robot and this near the opponent goal line between the posts is played on even when
    the opponent in front stands nearer than the ball [m]: on the real server a ball came to rest 4 cm before the
    line beside a keeper that only stands, 0.19 m from its torso; the keeper stood nearer to our robot than the
    ball, so the robot side-stepped back and forth for the last 76 s of the match (3 v 3, 120 s, seed 16). 0.5 m
    (its first value) left out a ball 0.52 m before the line beside a keeper that lined up with it: 50 s of side
    steps (11 v 11 against the baseline on ours, seed 0, 120-170 s); with 1.0 that start scored after 17 s."""
    opponent_fresh_s: float = 1.5
    """Opponent sightings older than this are not used [s]."""
    max_ball_age_s: float = 3.0
    """An own ball sighting older than this gives way to ``ball_source`` [s]..."""
    stale_ball_s: float = 10.0
    """... and is still walked toward (looking for the ball) up to this age [s]; then the robot searches."""
    search_turn_s: float = 4.2
    """Searching, the robot turns by a turn motion every this long [s] (the head sweeps one full period)."""
    near_ball_m: float = 0.6
    """Within this of the ball, facing the target direction within ``near_heading_deg``, the robot lines up
    with single short walks (sideways, backward) instead of going round the ball with turns [m] (each short
    walk takes 2-2.5 s for 0.27 m or more, so they only pay off for the last few decimetres)..."""
    near_ball_keep_m: float = 0.8
    """... and while lining up there (the last cycle's request was a near-ball one: a stop, a short walk), within
    this [m]. Why: the steps of the stop before a short walk push the ball on, and on the real server it rolled
    just past ``near_ball_m`` (to 0.61-0.62 m, 0.28-0.41 m aside) in 4 of 6 straight dribbles; the approach then
    turned 40-55 deg toward a point behind the ball and back again, 5-8 s, where one side walk (2.4 s) did it."""
    near_heading_deg: float = 20.0
    """... [deg]; beyond it (and farther than ``turn_clear_m`` from the ball) it turns toward the target
    direction in place (45 left robots lined up 30-45 deg off, and the short walks that followed pushed the
    ball aside). Striker alone, 15 starts x 2 seeds, 60 s (with chained turns): 0.8 m / 45 deg scored 18 of 30,
    0.6 m / 20 deg 22; with ``behind_per_m`` 0.6 too, 25 and the first push after 17.5 s."""
    turn_clear_m: float = 0.3
    """A turn in place only with the ball at least this far (torso centre) [m]: nearer, the feet swing into it."""
    orbit_ball_deg: float = 30.0
    """Near the ball and facing off the target direction by more than ``near_heading_deg``, with the ball within this
    of straight ahead [deg], the robot circles the ball (``orbit_left`` / ``orbit_right``: a sideways walk that turns
    round a point 0.45 m ahead) instead of turning in place, which swung the ball out to the side of the feet and
    led to side steps or a walk round the ball (a negative value disables it; without the orbit motions the robot
    turns). Measured 2026-11-29 against the turns alone: the dribble cases on the real rcssserver3d 0.7.3
    (``motion-studio real skills dribble dribble_turn_left dribble_turn_right``, one run each): 10 m straight 26.1
    -> 24.0 s (0.38 -> 0.42 m/s), 4 m after a 90 deg turn left 29.2 -> 22.9 s, right 19.8 -> 14.9 s; the ball
    within 0.5 m of the torso for a smaller share (0.47 / 0.82 / 0.86 -> 0.45 / 0.64 / 0.56: the orbit keeps it
    near 0.5 m). Ours (``motion-studio bench skills --skill dribble``, seed 0): straight 0.478 -> 0.535 m/s, the
    turns 18.2 -> 14.3 / 15.4 s. Not in matches (``agent.team.soccer_behavior.MATCH_DRIBBLE`` turns it off): 3 v 3
    against robots that only stand, 120 s, ours, seeds 0-15, 27 -> 25 goals; the real server, seeds 1-16, 22 -> 16
    goals, falls 4 -> 1 (with the 8-cycle orbit measured first, seeds 1-15: 20 -> 19 goals, falls 4 -> 6)..."""
    orbit_done_deg: float = 10.0
    """... until it faces the target direction within this [deg] (its stop turns it a few degrees more), the ball
    leaves the ``orbit_ball_deg`` cone, or the ball is no longer near. An orbit starts only with the ball at least
    ``turn_clear_m`` away (nearer, the side steps meet it)."""
    ahead_min_m: float = 0.1
    """The ball counts as in front of the feet this far ahead of the torso centre [m]."""
    side_step_m: float = 0.14
    """The ball this far or more to the side (ahead of the feet): one side walk toward it [m] (a side walk
    moves at least 0.27 m, so a smaller error would swing to the other side)."""
    clear_lateral_m: float = 0.15
    """The ball beside or behind the feet within this to the side: one side walk away from it first [m]."""
    free_line_deg: float = 0.0
    """Far from the target the ball may go this far toward the field's long axis off the line ball -> target [deg]
    (``free_line_out_deg`` away from it): the robot pushes along its own line to the ball when that line lies within
    this cone, and otherwise lines up on the cone's nearer edge, not on the line to the target. 0 = always toward
    the target (the skill benchmark's dribbles, which measure the way along that line). Why: on the real server a
    touch sent the ball 25-50 deg off the walking line, the push ended, and lining up again behind the ball on the
    line to the goal took 7-20 s of turns and short walks each time (3 v 3 against robots that only stand: the ball
    moved from x = 5 to x = 12 m in 26.6 s on average, the walk alone covers that in 14 s)."""
    free_line_out_deg: float = 10.0
    """... but only this far to the side away from the field's long axis (y = 0) once the ball lies
    ``free_line_middle_m`` or more off it [deg] (a ball nearer the axis gets this on both sides): a cone of 40 deg
    both ways let balls drift to y = -3 m by x = 9-13 m on the real server, where the angle to the goal is narrow
    and the finishing slow (x = 12 m to the end 18.9 s instead of 14.5)."""
    free_line_middle_m: float = 0.3
    """See ``free_line_out_deg`` [m]."""
    free_line_full_m: float = 8.0
    """The whole cone while the ball lies farther than this from the target [m]; ..."""
    free_line_none_m: float = 5.0
    """... none nearer than this (near the goal the line to it matters); in between it narrows linearly [m]."""
    rolling_m_s: float = 0.6
    """A ball rolling at least this fast and farther than ``near_ball_m`` is approached where it will come to
    rest (``agent.world.ball_track``), not where it was seen [m/s] (inf = never). Why: after our kick-off
    the receiver turned toward the ball rolling past it, 80 deg away from where it stopped 2.8 m on, and back
    again: 8 s from the kick to its first push (ours, 3 v 3 against robots that only stand, seed 0); with the rest
    point 5 s. The receiver alone, the ball launched past it at 4.5 m/s (the scenario test): pushed 0.5 m on from
    where it stopped 12.4 s after the launch before, 6.4 s after. 3 v 3 against robots that only stand, 120 s:
    ours, seeds 0-15, 27 goals either way, falls 4 -> 3; the real rcssserver3d 0.7.3, seeds 1-16, 20 -> 22 goals,
    falls 5 -> 4."""
    free_line_field_y_m: float = 8.5
    """A line whose 3 m ahead of the ball leaves |y| <= this is turned back toward the target [m] (the touch
    line is at 10 m: a kick-in for the opponents)."""


class Dribble(Skill):
    """Push the ball toward a team-frame point with the forward walk; see the module docstring.

    Args:
        target_x_m, target_y_m: where the ball should go (team frame).
        config: geometry; walk_config: the walk's steering thresholds.
    """

    def __init__(self, target_x_m: float, target_y_m: float, config: DribbleConfig | None = None,
                 walk_config: WalkConfig | None = None,
                 ball_source: Callable[[WorldModel], tuple[float, float] | None] | None = None) -> None:
        super().__init__()
        self.ball_source = ball_source
        """Where the ball is believed when the own sighting is stale (e.g. the teammates' reports): the
        robot walks there and looks for it instead of standing with its back to it."""
        self.target = (float(target_x_m), float(target_y_m))
        self.config = config or DribbleConfig()
        self.walk_config = walk_config or WalkConfig()
        self.name = f"dribble toward ({target_x_m:.1f}, {target_y_m:.1f})"
        self.reset()

    def reset(self) -> None:
        super().reset()
        self._steer = _Steer(self.walk_config)
        self._avoider = Avoider(self.walk_config.avoid) if self.walk_config.avoid else None
        self.pushing = False
        """The robot walks through the ball this cycle (for logs and tests)."""
        self.mode = "start"
        """What this cycle's request does, for the decision log: search, turn, near:<motion or stop>, blocked,
        push, avoid or approach."""
        self._search_cycles = 0
        self._short: str | None = None
        self._short_started = False

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        return self._steer.guard(motion, self._step(world, motion))

    def _step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        pose = world.pose
        ball = world.ball
        seen = ball is not None and ball.position is not None and ball.age_s(world.now_s) <= self.config.max_ball_age_s
        if seen:
            believed: tuple[float, float] | None = ball.position
        else:
            believed = self.ball_source(world) if self.ball_source is not None else None
            if believed is None and ball is not None and ball.position is not None \
                    and ball.age_s(world.now_s) <= self.config.stale_ball_s:
                believed = ball.position  # stale, but better to walk there and look than stand still
        if pose is None or believed is None:
            self.mode = "search"
            return self._search(motion)
        if seen:
            believed = self._rest_point(world, pose, believed)
        self._search_cycles = 0
        bx, by = believed
        line = self.line_rad(pose.x_m, pose.y_m, (bx, by))
        point, avoid = self._aim_point(pose.x_m, pose.y_m, pose.heading_rad, (bx, by), line)
        ego = pose.to_ego(*point)
        ball_ego = pose.to_ego(bx, by)
        head = _head(world, ball_ego)
        # A chained turn toward a ball farther than the near-ball turns is checked against where the ball is now.
        fresh = math.degrees(math.atan2(ego[1], ego[0])) if math.hypot(*ball_ego) > self.config.near_ball_m else None
        under_way = self._steer.turn_step(motion, fresh)
        if under_way is not None:
            self.mode = "turn"
            return MotionRequest(under_way.motion, under_way.lean, under_way.turn_deg, under_way.gain, head)
        near = self._near_ball(motion, pose.heading_rad, line, ball_ego, head)
        if near is not None:
            self.mode = f"near:{near.motion or 'stop'}"
            return near
        if self.pushing:
            avoid = False
            if ball_ego[0] <= self.config.centre_until_m:
                ego = pose.to_ego(*self._push_point((bx, by), line))
            else:
                ego = ball_ego
            ego = (ego[0], ego[1] + self.config.push_aim_left_m[world.robot_type])
        blocker = self._opponent_ahead(world)
        if blocker is not None and self._play_through(ball_ego, blocker, (bx, by)):
            blocker = None
        if blocker is not None:
            # An opponent right in front: step sideways away from it (a side walk stays under the charging
            # rule's 0.4 m/s; walking on into a standing opponent gave 52 charging fouls in 120 s on the
            # real server, each sending our player off to the touch line).
            self.pushing = False
            self.mode = "blocked"
            name = RIGHT if blocker[1] > 0 else LEFT
            return MotionRequest(name if name in motion.library else None, head_deg=head)
        bearing_deg = math.degrees(math.atan2(ego[1], ego[0]))
        self.mode = "push" if self.pushing else "approach"
        if avoid and self._avoider is not None:
            escape = self._avoider.bearing_deg(world, ego)
            if escape is not None:
                bearing_deg = escape
                if self._avoider.detouring:
                    self.mode = "avoid"  # walking round another robot, not straight at the point
            # None ("surrounded"): walk on toward the point; standing to let the others pass never ends
            # against robots that do not move (a dribbler stood 6 s behind two standing opponents)
        request = self._steer.heading(motion, bearing_deg)
        return MotionRequest(request.motion, request.lean, request.turn_deg, request.gain, head)

    def _rest_point(self, world: WorldModel, pose: Pose2D, ball: tuple[float, float]) -> tuple[float, float]:
        """``ball`` (the own fresh sighting) [m, team frame], or where it will stop when it rolls at ``rolling_m_s``
        or faster, the robot neither pushing it nor within ``near_ball_m`` of it (there the feet play the ball as
        it is). Teammates' reports are taken as they are: the track fits the own sightings only."""
        if self.pushing or self._short is not None \
                or math.hypot(ball[0] - pose.x_m, ball[1] - pose.y_m) <= self.config.near_ball_m:
            return ball   # decided without the track's least-squares fit (the on-ball player's every cycle)
        velocity = world.ball_track.velocity_m_s()
        if velocity is None or math.hypot(*velocity) < self.config.rolling_m_s:
            return ball
        return world.ball_track.rest_point() or ball

    def _near_ball(self, motion: MotionController, heading_rad: float, line_rad: float,
                   ball_ego: tuple[float, float], head: tuple[float, float]) -> MotionRequest | None:
        """Near the ball and roughly facing the target direction: one short walk that brings the ball in
        front of the feet (measured on our simulator: going round the ball with turns after the ball slipped
        aside took 10-20 s; a side or backward walk takes about 2 s). None = walk on as usual (pushing, or
        the approach from afar)."""
        c = self.config
        if motion.motion_name in ORBITS:
            return self._orbit_on(motion, heading_rad, line_rad, ball_ego, head)
        if self._short is not None:
            # One short walk of its smallest length: asked for until it plays, then stopped at once.
            if not self._short_started:
                if motion.motion_name == self._short:
                    self._short_started = True
                else:
                    return MotionRequest(self._short, head_deg=head)
            if motion.motion_name in WALKS and not motion.idle:
                return MotionRequest(None, head_deg=head)
            self._short = None
        if self.pushing:
            return None
        forward, left = ball_ego
        distance = math.hypot(forward, left)
        if distance > (c.near_ball_keep_m if self.mode.startswith("near:") else c.near_ball_m):
            return None
        error_deg = math.degrees(wrap_angle_rad(line_rad - heading_rad))
        walking_forward = motion.motion_name in FORWARD_WALKS and not motion.stopping
        if abs(error_deg) > c.near_heading_deg:
            if distance >= c.turn_clear_m and self._orbit_fits(motion, ball_ego):
                if not motion.idle and motion.motion_name in WALKS:
                    return MotionRequest(None, head_deg=head)  # stop the walk under way first
                return MotionRequest(ORBIT_LEFT if error_deg > 0.0 else ORBIT_RIGHT, head_deg=head)
            if distance >= c.turn_clear_m and self._steer.can_turn(motion):
                return self._steer.turn(motion, error_deg)
            name = BACKWARD if forward > 0.0 else (RIGHT if left > 0.0 else LEFT)
        elif forward >= c.ahead_min_m:
            if abs(left) < c.side_step_m:
                self.pushing = True  # in front of the feet: walk at the point beyond the ball
                return None
            name = LEFT if left > 0.0 else RIGHT
        elif abs(left) < c.clear_lateral_m:
            name = RIGHT if left > 0.0 else LEFT
        else:
            name = BACKWARD
        if walking_forward:
            return MotionRequest(None, head_deg=head)  # stop first
        if name not in motion.library:
            return None
        if not motion.idle and motion.motion_name in WALKS:
            return MotionRequest(None, head_deg=head)  # let the walk under way stop first
        self._short, self._short_started = name, False
        return MotionRequest(name, head_deg=head)

    def _orbit_fits(self, motion: MotionController, ball_ego: tuple[float, float]) -> bool:
        """The library has both orbits and the ball lies ahead within ``orbit_ball_deg``."""
        forward, left = ball_ego
        return (ORBIT_LEFT in motion.library and ORBIT_RIGHT in motion.library and forward > 0.0
                and abs(math.degrees(math.atan2(left, forward))) <= self.config.orbit_ball_deg)

    def _orbit_on(self, motion: MotionController, heading_rad: float, line_rad: float,
                  ball_ego: tuple[float, float], head: tuple[float, float]) -> MotionRequest:
        """An orbit under way: on while the ball stays ahead and near and the heading is more than
        ``orbit_done_deg`` off the target direction on the orbit's side; else stopped (waited for while it stops)."""
        c = self.config
        self.pushing = False
        error_deg = math.degrees(wrap_angle_rad(line_rad - heading_rad))
        name = motion.motion_name
        toward = error_deg if name == ORBIT_LEFT else -error_deg
        if (not motion.stopping and toward > c.orbit_done_deg and self._orbit_fits(motion, ball_ego)
                and math.hypot(*ball_ego) <= c.near_ball_keep_m):
            return MotionRequest(name, head_deg=head)
        return MotionRequest(None, head_deg=head)

    def line_rad(self, x_m: float, y_m: float, ball: tuple[float, float]) -> float:
        """The direction the ball is played in from the robot at (``x_m``, ``y_m``) [rad, team frame]: toward
        the target, or within ``free_line_deg`` of it (``free_line_out_deg`` outward) along the robot's own line
        to the ball (the nearer edge of that cone when the robot stands outside it), narrowing near the target
        (``free_line_full_m``)."""
        c = self.config
        to_target = math.atan2(self.target[1] - ball[1], self.target[0] - ball[0])
        distance = math.hypot(self.target[0] - ball[0], self.target[1] - ball[1])
        share = (distance - c.free_line_none_m) / max(1e-6, c.free_line_full_m - c.free_line_none_m)
        cone = math.radians(c.free_line_deg) * max(0.0, min(1.0, share))
        if cone <= 0.0:
            return to_target
        out = cone * min(1.0, c.free_line_out_deg / c.free_line_deg)
        # Left of the line (positive) turns the ball toward +y: outward for a ball at y > 0.
        left, right = (out, cone) if ball[1] >= c.free_line_middle_m else \
            (cone, out) if ball[1] <= -c.free_line_middle_m else (out, out)
        from_robot = math.atan2(ball[1] - y_m, ball[0] - x_m)
        line = to_target + max(-right, min(left, wrap_angle_rad(from_robot - to_target)))
        ahead_y = ball[1] + 3.0 * math.sin(line)
        if abs(ahead_y) > c.free_line_field_y_m and abs(ahead_y) > abs(ball[1] + 3.0 * math.sin(to_target)):
            return to_target
        return line

    def _push_point(self, ball: tuple[float, float], line_rad: float) -> tuple[float, float]:
        """The point ``push_through_m`` beyond the ball along the line it is played (``line_rad``) [m]."""
        through = self.config.push_through_m
        return ball[0] + through * math.cos(line_rad), ball[1] + through * math.sin(line_rad)

    def _play_through(self, ball_ego: tuple[float, float], blocker: tuple[float, float],
                      ball: tuple[float, float]) -> bool:
        """The ball lies between the robot and the opponent ahead, in the opponent penalty area, or in the goal
        mouth (``goal_mouth_m``): play it on."""
        c = self.config
        ahead = 0.0 < ball_ego[0] and abs(ball_ego[1]) < c.play_through_m
        if ahead and ball[0] > HALF_LENGTH_M - c.goal_mouth_m and abs(ball[1]) < GOAL_HALF_WIDTH_M:
            return True
        in_box = ball[0] > c.play_through_box_m[0] and abs(ball[1]) < c.play_through_box_m[1]
        return in_box and ahead and ball_ego[0] < blocker[0]

    def _opponent_ahead(self, world: WorldModel) -> tuple[float, float] | None:
        """The nearest opponent seen lately inside the box in front of the robot (ego forward, left) [m]."""
        pose = world.pose
        if pose is None:
            return None
        c = self.config
        ahead = []
        for opponent in world.opponents.values():
            if opponent.position is None or opponent.age_s(world.now_s) > c.opponent_fresh_s:
                continue
            forward, left = pose.to_ego(*opponent.position)
            if 0.0 < forward <= c.blocked_ahead_m and abs(left) <= c.blocked_side_m:
                ahead.append((forward, left))
        return min(ahead, default=None)

    def _search(self, motion: MotionController) -> MotionRequest:
        """No ball anywhere: sweep the head, and every ``search_turn_s`` turn on by a turn motion (the ball
        may lie behind the robot, out of the head's reach)."""
        self.pushing = False
        self._search_cycles += 1
        under_way = self._steer.turn_step(motion)
        if under_way is not None:
            return under_way
        sweep = 60.0 * math.sin(self._search_cycles * CYCLE_S * 1.5)
        if self._search_cycles % round(self.config.search_turn_s / CYCLE_S) == 0 and self._steer.can_turn(motion):
            return self._steer.turn(motion, 90.0)
        return self._steer.request(None, head_deg=(sweep, -25.0))

    def _aim_point(self, x_m: float, y_m: float, heading_rad: float, ball: tuple[float, float],
                   line: float) -> tuple[tuple[float, float], bool]:
        """The point to walk at, and whether to avoid other robots on the way; the ball is played along ``line``
        (``line_rad()`` from this position) [rad]."""
        c = self.config
        tx, ty = self.target
        ux, uy = math.cos(line), math.sin(line)
        # Robot relative to the ball in the (along u, left of u) frame, u along the line the ball is played.
        rx, ry = x_m - ball[0], y_m - ball[1]
        along, across = rx * ux + ry * uy, -rx * uy + ry * ux
        heading_error = abs(math.degrees(wrap_angle_rad(line - heading_rad)))
        # Ball in the robot's ego frame.
        ch, sh = math.cos(heading_rad), math.sin(heading_rad)
        ball_left = -(ball[0] - x_m) * sh + (ball[1] - y_m) * ch
        ball_forward = (ball[0] - x_m) * ch + (ball[1] - y_m) * sh
        distance = math.hypot(rx, ry)
        avoid = distance > c.avoid_beyond_m
        near_goal = math.hypot(tx - ball[0], ty - ball[1]) <= c.goal_zone_m
        if self.pushing:
            # Hysteresis: walk on through the ball while it stays roughly in front, even when it rolled
            # ahead (switching between pushing and the approach point swung the aim and turned the robot
            # back and forth beside the ball).
            self.pushing = (along < c.behind_min_m
                            and abs(across) <= (c.keep_across_goal_m if near_goal else c.keep_across_m)
                            and abs(ball_left) <= c.keep_lateral_m and -0.02 < ball_forward <= c.keep_ahead_m
                            and heading_error <= c.keep_max_deg)
            if self.pushing:
                return self._push_point(ball, line), False
        if along < -c.behind_min_m:
            # Behind the ball: walk at a point on the line target -> ball, the farther behind the ball the
            # farther the robot is off that line, so the walk curves into the line and then through the
            # ball (a vector field; a fixed approach point made the walk overshoot onto the ball).
            back = min(c.behind_max_m, c.behind_per_m * abs(across))
            line_deg = math.degrees(math.atan2(abs(across), -along))
            self.pushing = (back <= c.push_start_m and abs(ball_left) <= c.push_lateral_m and ball_forward > 0.0
                            and heading_error <= c.push_max_deg
                            and line_deg <= (c.push_line_goal_deg if near_goal else c.push_line_deg))
            if self.pushing:
                return self._push_point(ball, line), False
            return (ball[0] - back * ux, ball[1] - back * uy), avoid
        self.pushing = False
        # Beside or in front of the ball: go round it on the robot's side, to a point abeam and behind.
        side = 1.0 if across >= 0.0 else -1.0
        return (ball[0] - c.behind_m * ux - side * c.round_m * uy,
                ball[1] - c.behind_m * uy + side * c.round_m * ux), avoid


def _head(world: WorldModel, ball_ego: tuple[float, float]) -> tuple[float, float]:
    """Head (yaw, pitch) [deg] toward the ball, pitched down as it comes nearer (the ball at the feet is
    below a level view); level enough far away that landmarks stay in view for localization."""
    distance = math.hypot(*ball_ego)
    yaw = max(-60.0, min(60.0, math.degrees(math.atan2(ball_ego[1], ball_ego[0]))))
    depression = math.degrees(math.atan2(world.body.camera_height_m, max(distance, 0.05)))
    return yaw, -max(0.0, min(45.0, depression - 25.0))


__all__ = ["Dribble", "DribbleConfig"]
