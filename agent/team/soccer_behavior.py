"""The agent's default soccer behaviour: one role per player each cycle, played through the skills.

Roles (``agent.team.roles``): the player that the shared on-ball rule picks dribbles the ball toward the
opponent goal and over its line (``agent.skills.dribble``; the seed kicked instead, REFERENCE §7.8, and the
kick's line-up cost more time than it won), and takes its own side's set pieces with one kick; the goalkeeper
guards its line facing the ball; the second attacker (``roles.second_attacker``) waits 2.5 m behind the ball,
to the side, to take over; the others walk to support spots that follow the ball and face it, all clear of the
on-ball player's path. Nobody moves while the play mode forbids it (before kick-off, after a goal, game over);
during the opponents' set pieces the on-ball player waits behind the ball (``restart_spot``), at the distance
the others keep; at their goal kick it waits behind the corner of their penalty area where the ball comes back if
they never take it (``drop_ready_spot``).

Skills are kept while the decision stays the same (a new ``WalkTo`` only when its target moved more than
``RETARGET_M``), so their internal state (turns under way, stops) is not cut off every cycle. Falls are
handled by ``SkillBehavior`` (stand-up first, then the role's skill again).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Hashable

from agent.formation import kick_off_spot
from agent.motion import MotionController
from agent.protocol.effectors import Action
from agent.skills.base import PlayMotion, Skill
from agent.skills.behavior import SkillBehavior
from agent.skills.dribble import Dribble, DribbleConfig
# KICK: the kick a set-piece taker plays once the ball lies in its window (without it, the kick skill);
# LONG_KICK: the one it plays instead while the ball lies in that one's narrower window.
from agent.skills.kick import KICK, KickToward
from agent.skills.kick import STRONG as LONG_KICK
from agent.skills.kick_lineup import STEP_FORWARD, STEP_LEFT, STEP_RIGHT
from agent.skills.turn import TurnToFace
from agent.skills.walk import STAND, WalkTo
from agent.skills.walk_ball import WalkToBall
from agent.team import roles
from agent.team.attack import goal_target, over_the_line, seen_opponents, set_piece_target
from agent.team.set_pieces import (SET_PIECE_MAX_STEPS, TakerMemory, long_kick_window, own_set_piece,
                                    set_piece_move)
from agent.world.field import goal_kick_drop_m
from agent.world_model import WorldModel

#: A support or keeper target that moved less than this keeps the running WalkTo [m].
RETARGET_M = 0.5
#: The goalkeeper re-targets when its guard spot moved this much [m] (a shot's crossing point moves it less
#: than ``RETARGET_M`` across a goal 2.1 m wide).
KEEPER_RETARGET_M = 0.2
#: Facing error a player standing on its spot tolerates before turning to the ball [deg].
FACE_TOLERANCE_DEG = 20.0
#: Play modes in which nobody moves (REFERENCE §4.2).
FROZEN_MODES = frozenset({"BeforeKickOff", "Goal_Left", "Goal_Right", "GameOver", "unknown"})
#: A set-piece taker kicks at once when facing the opponent goal within this [deg] (the kick follows the heading).
SET_PIECE_AIM_DEG = 12.0
#: Distance the players keep from the ball at the opponents' set pieces [m] (the referee clears 2 m).
SET_PIECE_CLEARANCE_M = 2.2
#: At the opponents' set pieces the player that will play the ball next waits this far behind it, on the line
#: from the opponent goal through the ball, facing it [m]: when the set piece is played or runs out (drop ball)
#: it walks straight into a push. Waiting beside the ball (the kick-off spots keep 1.2 m off the centre line)
#: cost 10-11 s from the drop ball to the first push against robots that only stand: a turn, a walk round the
#: ball, another turn, and both field players went for it (equal distances).
RESTART_BEHIND_M = 2.3
#: The player waiting for the drop ball of the opponents' untaken goal kick stands this far from the drop spot
#: [m]: the drop moves every player whose bounding box reaches 2 m of the ball to 2.5 m before it (along x, toward
#: its own goal); at 2.3 m on the diagonal line from the penalty-area corner the real server moved ours from
#: (11.7, 4.8) to (10.6, 4.7), off its line; at 2.8 m it stayed (3 v 3 against robots that only stand, 2026-11-27).
DROP_READY_BEHIND_M = 2.8
#: At the own kick-off the second attacker waits here [m] (team frame; on its beam spot's side, in the
#: opponent half but wholly inside the centre circle, where the kick-off rule lets the kicking team stand,
#: REFERENCE §4.4): the kick-off flies about 4 m straight ahead and the taker may not touch the ball again, so
#: this player goes for it next. Its usual spot (2.5 m behind the ball, across from the taker) sent it from its
#: beam spot (-2.2, 1.2) across to (-2.5, -1.5) on the real server, turned sideways, and from there it reached
#: the ball 12 s after the kick; from (-1.0, 0.9) the ball reached x = 5 m 17.8 s after PlayOn (real server,
#: seeds 1-10, 11-28 s), from here 15.6 s (14-17 s; a tenth run ended in a double-touch free kick, as base
#: runs sometimes do).
KICK_OFF_FOLLOW_SPOT_M = (1.0, 1.1)
#: ... facing this point (team frame) [m], where the kick-off ball comes to rest (4 m straight ahead: real kicks
#: stopped at x = 3.0-5.4 m, y = -0.9-0.0), not the ball on the centre spot behind it: facing the ball, it turned
#: 130-180 deg after the kick (4 s) whenever the kick-off took long enough for it to stand on its spot (real
#: server, 3 v 3 against robots that only stand, 2026-11-27: first touch after the kick 13.8-15.9 s when the kick
#: came 10-13 s into the kick-off, 7.3-14.1 s when it came at 3-6 s).
KICK_OFF_FOLLOW_FACING_M = (4.0, 0.0)
#: The match dribble: far from the goal the ball may go up to 40 deg aside of the line to the aim toward the
#: field's long axis and 10 deg away from it (``DribbleConfig.free_line_deg``), so a ball that rolled off the
#: walking line is pushed on from where the robot stands instead of lined up again on the line to the goal.
#: 3 v 3 against robots that only stand, 120 s, seeds 1-16: real server 14 -> 16 goals (40 deg both ways: 15
#: in 15; 25 deg both ways: 12 in 14), goal kicks after attacks past x = 12 m 2 -> 1; ours 25 -> 22 goals.
#: ``near_ball_keep_m`` as ``near_ball_m`` (no line-up hysteresis): with 0.8 our 3 v 3 against robots that only stand
#: (seeds 0-31, on ours) scored 50 goals instead of 56 (52 with it off within 4 m of the goal; seed 7 stood 13.7 s in
#: near-ball stops before the goal line).
#: No orbits (``orbit_ball_deg`` < 0; the robot turns in place near the ball, as before them): they speed up the
#: dribble cases on both servers but not the matches. 3 v 3 against robots that only stand, 120 s, with the orbit:
#: ours, seeds 0-15, 25 goals (27 without); the real server, seeds 1-16, 16 goals (22), falls 1 (4).
MATCH_DRIBBLE = DribbleConfig(free_line_deg=40.0, free_line_out_deg=10.0, near_ball_keep_m=0.6, orbit_ball_deg=-1.0)
#: Every change of a player's decision (its key, and the running skill's ``mode`` where it has one) is logged here
#: at DEBUG level with the server time, pose and ball: enable it (``motion-studio real match --decisions``) to see
#: where the time of a match goes; off, it costs one level check per cycle.
decision_log = logging.getLogger("agent.decisions")


class SoccerBehavior:
    """A ``Behavior`` (``world -> actions``) that plays soccer with the skills; see the module docstring.

    Args:
        robot_type: 0-4 (the motion library and the kinematics).
        controller: the motion controller (default: the shipped motions and dynamic elements).
    """

    def __init__(self, robot_type: int = 0, controller: MotionController | None = None) -> None:
        self.skills = SkillBehavior(controller, None, robot_type)
        self.holder: int | None = None
        """The unum this player believes plays the ball (hysteresis of the on-ball rule)."""
        self.role = "idle"
        """This cycle's role: idle, on_ball, keeper, support (for logs and tests)."""
        self._holder_watch = roles.HolderWatch()
        """Whether the believed holder (another player) is playing the ball, else its bonus lapses."""
        self.taker = TakerMemory()
        """Who took the own team's last set piece (it may not touch the ball again first)."""
        self._world: WorldModel | None = None
        self._set_piece_aim: tuple[float, float] | None = None
        self._key: Hashable = None
        self._target: tuple[float, float] | None = None
        self._second_side: float | None = None
        self._aim_y: float | None = None
        """The y of the goal-mouth point the dribble aims at (``attack.AIM_YS_M``), kept while its path is clear."""
        self._logged: tuple[Hashable, str | None] | None = None

    @property
    def motion(self) -> MotionController:
        return self.skills.motion

    def __call__(self, world: WorldModel) -> list[Action]:
        self._world = world
        self._decide(world)
        actions = self.skills(world)
        if decision_log.isEnabledFor(logging.DEBUG):
            self._log_decision(world)
        return actions

    def _log_decision(self, world: WorldModel) -> None:
        decision = (self._key, getattr(self.skills.skill, "mode", None))
        if decision == self._logged:
            return
        self._logged = decision
        pose, ball = world.pose, world.ball
        where = "-" if pose is None else f"({pose.x_m:.2f}, {pose.y_m:.2f}, {math.degrees(pose.heading_rad):.0f} deg)"
        seen = "-" if ball is None or ball.forward_m is None else f"({ball.forward_m:.2f}, {ball.left_m or 0.0:.2f})"
        decision_log.debug("t=%.2f #%s %s %s %s pose %s ball ego %s", world.now_s, world.unum, self.role,
                           decision[0], decision[1] or "", where, seen)

    # --- decisions --------------------------------------------------------------------------------------
    def _decide(self, world: WorldModel) -> None:
        game = world.game
        if self._idle_while_frozen(world):
            return
        ball = roles.ball_belief(world)
        set_piece = own_set_piece(game.play_mode, game.side)
        if world.unum == roles.GOALKEEPER_UNUM and not (ball is not None and roles.keeper_plays_ball(ball)):
            self.role = "keeper"
            crossing = world.ball_track.crossing_y(roles.KEEPER_X_M)
            self._stand_at(world, roles.keeper_spot(ball, crossing), ball, KEEPER_RETARGET_M)
            return
        if ball is None:
            self.role = "search"
            self._use(("search",), WalkToBall)  # stands and sweeps the head until the ball is seen
            return
        players = roles.candidates(world)
        # The memory first (with the last cycle's holder), so that the cycle a set piece ends in already keeps
        # its taker off the ball: updated after the choice, the taker was the on-ball player for that cycle
        # (every kick-off on ours: a dribble started 0.02 s after the kick; on the real server a kick-off
        # ended in a free kick for the opponents 0.1 s after it, in 2 of 8 kick-offs there today).
        self.taker.update(world, set_piece, self.holder)
        excluded = self.taker.excluded(world, ball, players)
        allowed = [p for p in players if p.unum != excluded]
        # At the opponents' goal kick the ball that matters is the one the drop will bring (see goal_kick_drop).
        drop = goal_kick_drop(world)
        on_ball = ball if drop is None else drop
        holder = self.holder if self._holder_watch.keeps_bonus(world.now_s, self.holder, world.unum, players, on_ball,
                                                               open_play=set_piece is None) else None
        if set_piece is False and game.play_mode.startswith("KickOff_"):
            self.holder = roles.kick_off_receiver(allowed)
        else:
            self.holder = roles.choose_on_ball(allowed, on_ball, holder)
        if self.holder == world.unum and set_piece is True:
            self.role = "set_piece"
            self._take_set_piece(world, ball)
            return
        if self.holder == world.unum and set_piece is None:
            self.role = "on_ball"
            self._play_ball(ball)
            return
        if self.holder == world.unum and set_piece is False:
            self.role = "restart"
            if drop is None:
                self._stand_at(world, restart_spot(ball), ball)
            else:
                self._stand_at(world, drop_ready_spot(drop, seen_opponents(world)), drop)
            return
        self.role = "support"
        holder = next(((p.x_m, p.y_m) for p in players if p.unum == self.holder), None)
        second_attacker = roles.second_attacker(players, self.holder) == world.unum
        kick_off = game.play_mode.startswith("KickOff_")
        if second_attacker and set_piece is True and kick_off:
            # Inside the centre circle: the rule lets it stand there, so kick_off_spot's own-half clamp is skipped.
            self._stand_at(world, KICK_OFF_FOLLOW_SPOT_M, KICK_OFF_FOLLOW_FACING_M)
            return
        if second_attacker:
            self._second_side = roles.second_attacker_side(ball, holder, self._second_side)
            spot = roles.second_attacker_spot(ball, holder, self._second_side)
        else:
            spot = roles.support_spot(world.unum, ball, holder)
        if set_piece is False:
            spot = _keep_clear(spot, ball, SET_PIECE_CLEARANCE_M)
        if kick_off:
            spot = kick_off_spot(*spot, world.unum, opponents_kick_off=set_piece is False)
        self._stand_at(world, spot, ball)

    def _play_ball(self, ball: tuple[float, float]) -> None:
        """Dribble the ball toward the opponent goal and over its line (``agent.skills.dribble``): on our
        simulator it moved the ball 10-13 m in 40 s where the kick's line-up took 13-35 s per 2.4 m kick.

        No shot in open play: a dribbler that stopped within 4 m of the goal to kick from the standing window
        found the ball there in 1 of 40 stops on our simulator (the stop's last steps push the ball on by 0.02 to
        1.8 m; 36 finishing starts) and in none of 6 on the real server (4 matches); each stop, and the 3 s of
        dribbling before the next, cost about 2 s."""
        world = self._world
        skill = self.skills.skill
        previous_y = self._aim_y if self._key == ("dribble",) and isinstance(skill, Dribble) else None
        aim = goal_target(ball, seen_opponents(world), previous_y) if world is not None else (15.5, 0.0)
        self._aim_y = aim[1]
        target = over_the_line(ball, aim)
        if self._key == ("dribble",) and isinstance(skill, Dribble) and skill.target != target \
                and not skill.pushing:
            skill.target = target  # a new aim point: keep the skill (and its steering state)
        self._use(("dribble",), lambda: Dribble(*target, MATCH_DRIBBLE, ball_source=roles.ball_belief))

    def _take_set_piece(self, world: WorldModel, ball: tuple[float, float]) -> None:
        """One kick toward the opponent goal (the taker may touch the ball only once): the kick motion as
        soon as the robot stands still with the ball in the set-piece window (``set_pieces.set_piece_move``:
        wider than the kick skill's, a short kick now beats a long one later; kick steps first when the ball
        lies in its far part, where real kicks grazed it), else the kick skill's line-up
        (straight into it: WalkToBall walked through the ball first, and that touch made the kick a second
        one). On the real server the line-up backed off and walked in again for the whole 15 s of a kick-off
        (its walks cover more there than the strides it plans with)."""
        if self._key == ("set_piece_kick",):
            skill = self.skills.skill
            if skill is None or skill.done:
                self.role = "set_piece_done"
            return
        steps = self._key[1] if isinstance(self._key, tuple) and self._key[0] == "set_piece_step" else 0
        if steps and self.skills.skill is not None and not self.skills.skill.done:
            return  # a kick step under way
        seen = world.ball
        if self._key != ("kick",) or self._set_piece_aim is None:
            # A kick-off aims straight: the opponents seen at its start still stand where they were beamed, and
            # the referee then moves them out of the circle (x = 2.5) into that path; an aim turned away from
            # them sent the line-up round the ball until the 15 s ran out (ours against ours, on both servers).
            kick_off = world.game.play_mode.startswith("KickOff_")
            self._set_piece_aim = set_piece_target(ball, [] if kick_off else seen_opponents(world))
        aim = self._set_piece_aim
        standing = self.motion.idle or self.motion.motion_name == STAND
        if KICK in self.motion.library and standing and seen is not None and seen.forward_m is not None \
                and seen.age_s(world.now_s) < 0.2 and not self.skills.recovering:
            ball_ego = (seen.forward_m, seen.left_m or 0.0)
            facing = self._facing(world, aim, SET_PIECE_AIM_DEG)
            if LONG_KICK in self.motion.library and facing:
                long_spot = self.motion.library.get(LONG_KICK).constants
                if long_kick_window(ball_ego, float(long_spot.get("ball_forward_m", 0.125)),
                                    float(long_spot.get("ball_left_m", 0.0))):
                    self._use(("set_piece_kick",), lambda: PlayMotion(LONG_KICK))
                    return
            spot = self.motion.library.get(KICK).constants
            move = set_piece_move(ball_ego, float(spot.get("ball_forward_m", 0.125)), float(spot.get("ball_left_m", 0.0)),
                                  steps if STEP_FORWARD in self.motion.library else SET_PIECE_MAX_STEPS)
            step = {"step": STEP_FORWARD, "step_left": STEP_LEFT, "step_right": STEP_RIGHT}.get(move or "")
            if step is not None and step not in self.motion.library:
                move = None
            if move is not None and facing:
                if step is not None:
                    self._use(("set_piece_step", steps + 1), lambda: PlayMotion(step))
                else:
                    self._use(("set_piece_kick",), lambda: PlayMotion(KICK))
                return
        if self._key == ("kick",):
            skill = self.skills.skill
            if skill is not None and skill.done:
                self.role = "set_piece_done"
            return
        self._use(("kick",), lambda: KickToward(aim[0], aim[1], strong=False))

    def _stand_at(self, world: WorldModel, spot: tuple[float, float], ball: tuple[float, float] | None,
                  retarget_m: float = RETARGET_M) -> None:
        target = self._target
        moved = target is None or math.hypot(spot[0] - target[0], spot[1] - target[1]) > retarget_m
        skill = self.skills.skill
        walking = isinstance(skill, WalkTo) and not skill.done
        if moved or (not walking and not self._on_spot(world, spot)):
            self._target = spot
            self._use(("walk", spot), lambda: WalkTo(*spot))
            return
        if walking:
            return
        if ball is not None and not self._facing(world, ball):
            self._use(("face", round(ball[0]), round(ball[1])), lambda: TurnToFace(*ball))

    def _on_spot(self, world: WorldModel, spot: tuple[float, float]) -> bool:
        pose = world.pose
        return pose is not None and math.hypot(spot[0] - pose.x_m, spot[1] - pose.y_m) <= RETARGET_M

    @staticmethod
    def _facing(world: WorldModel, point: tuple[float, float], tolerance_deg: float = FACE_TOLERANCE_DEG) -> bool:
        pose = world.pose
        if pose is None:
            return True
        forward, left = pose.to_ego(*point)
        return abs(math.degrees(math.atan2(left, forward))) <= tolerance_deg

    def _idle_while_frozen(self, world: WorldModel) -> bool:
        """In a frozen play mode (or before the side is known) crouch into the walk stance and wait: the first
        walk then starts from its own stance instead of the upright beam pose. True = nothing else to decide."""
        if world.game.play_mode in FROZEN_MODES or world.game.side is None:
            self.role = "idle"
            self._use(("idle",), lambda: PlayMotion(STAND) if STAND in self.motion.library else None)
            return True
        return False

    def _use(self, key: Hashable, make: Callable[[], Skill | None]) -> None:
        """Switch to the skill ``make()`` unless the decision ``key`` is the one already running."""
        if key == self._key:
            return
        self._key = key
        self.skills.set_skill(make())


def goal_kick_drop(world: WorldModel) -> tuple[float, float] | None:
    """Where the ball of the opponents' goal kick comes into play when they never take it (team frame) [m], or
    None outside their goal kick (``agent.world.field.goal_kick_drop_m``: the penalty area's front corner)."""
    game = world.game
    if not game.play_mode.startswith("goal_kick_") or own_set_piece(game.play_mode, game.side) is not False:
        return None
    return world.frame.point_from_world(*goal_kick_drop_m(game.play_mode.removeprefix("goal_kick_")))


def drop_ready_spot(drop: tuple[float, float], opponents: list[tuple[float, float]]) -> tuple[float, float]:
    """Where the next on-ball player waits for the ``drop`` of the opponents' untaken goal kick [m, team frame]:
    ``DROP_READY_BEHIND_M`` behind the drop spot on the line it will push the ball along (toward
    ``attack.goal_target``'s aim from there, ``attack.over_the_line``), so it walks straight into the push when the
    ball reappears. Waiting
    behind the goal-kick spot on the axis instead, it reached the ball 17-20 s after the drop on our simulator
    (10 seeds: a turn, a walk round the defender in front of the goal, turns beside the ball) and 22-29 s on
    the real server (2 of 4 drops)."""
    aim = over_the_line(drop, goal_target(drop, opponents))
    to_aim = math.atan2(aim[1] - drop[1], aim[0] - drop[0])
    x = drop[0] - DROP_READY_BEHIND_M * math.cos(to_aim)
    y = drop[1] - DROP_READY_BEHIND_M * math.sin(to_aim)
    return (max(-roles.FIELD_X_LIMIT_M, min(roles.FIELD_X_LIMIT_M, x)),
            max(-roles.FIELD_Y_LIMIT_M, min(roles.FIELD_Y_LIMIT_M, y)))


def restart_spot(ball: tuple[float, float]) -> tuple[float, float]:
    """Where the next on-ball player waits at the opponents' set piece (``RESTART_BEHIND_M``) [m]: behind the
    ball on the line from the opponent goal, in the field, and never nearer the ball than the referee allows
    (at a corner or goal kick by the own goal line the line leads out of the field)."""
    goal = roles.OPPONENT_GOAL_M
    to_goal = math.atan2(goal[1] - ball[1], goal[0] - ball[0])
    x = ball[0] - RESTART_BEHIND_M * math.cos(to_goal)
    y = ball[1] - RESTART_BEHIND_M * math.sin(to_goal)
    x = max(-roles.FIELD_X_LIMIT_M, min(roles.FIELD_X_LIMIT_M, x))
    y = max(-roles.FIELD_Y_LIMIT_M, min(roles.FIELD_Y_LIMIT_M, y))
    return _keep_clear((x, y), ball, SET_PIECE_CLEARANCE_M)


def _keep_clear(spot: tuple[float, float], ball: tuple[float, float], clearance_m: float) -> tuple[float, float]:
    """``spot`` moved away from the ball to at least ``clearance_m`` (toward the own goal if on the ball)."""
    dx, dy = spot[0] - ball[0], spot[1] - ball[1]
    distance = math.hypot(dx, dy)
    if distance >= clearance_m:
        return spot
    if distance < 1e-6:
        dx, dy, distance = -1.0, 0.0, 1.0
    return ball[0] + dx / distance * clearance_m, ball[1] + dy / distance * clearance_m


__all__ = ["SoccerBehavior", "own_set_piece"]  # own_set_piece re-exported (agent.team.set_pieces)
