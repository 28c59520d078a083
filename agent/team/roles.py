"""Who plays the ball, and where the others stand: decided by every player from its own beliefs.

Why decentralised: the seed's coordinator (REFERENCE §7.10) needs a full say round (≈ 2 s) before an
order arrives; each player already hears every teammate's position within one round (§7.9), so each can
apply the same rule itself. The rule is §7.10's on-ball choice: cost = d + a·ϑ (d: distance to the ball
[m], ϑ: how far the player must go around the ball to face the goal [deg], a = 0.01), the previous holder
gets −1 (hysteresis, so two players do not swap the role every cycle). Teammates that said ``x`` (fallen,
lost) or whose last report is older than ``REPORT_FRESH_S`` are left out; with equal costs the lower unum
plays. The goalkeeper (unum 1) plays the ball only inside its own penalty area.

All positions are in the team frame (own goal at −x), metres; angles in degrees where named ``_deg``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.formation import beam_spot
from agent.world_model import WorldModel
from agent.protocol.constants import HALF_LENGTH_M

#: Weight of the angle term of the on-ball cost [m/deg] (REFERENCE §7.10).
ANGLE_WEIGHT_M_PER_DEG = 0.01
#: Cost bonus of the current holder [m] (REFERENCE §7.10).
HOLDER_BONUS_M = 1.0
#: A teammate's report older than this is not used [s]: a full say round of 11 players is 0.66 s (§7.9), so a
#: teammate that fell silent (taken off, crashed) loses the ball to the next player within 1 s (issue 15; with
#: 3 s its teammates kept "hearing" a striker that had been taken off at the ball).
REPORT_FRESH_S = 0.9
#: The own ball sighting is used while younger than this [s]; else a teammate's (c) report.
BALL_FRESH_S = 2.0
#: Opponent goal centre, team frame [m] (field 30 × 20, REFERENCE §4).
OPPONENT_GOAL_M = (HALF_LENGTH_M, 0.0)
#: Goalkeeper's guard line x [m] and half-width of its guard segment [m] (goal 2.1 m wide).
KEEPER_X_M = -14.2
KEEPER_HALF_WIDTH_M = 0.8
#: Own penalty area, where the goalkeeper plays the ball itself: x below, |y| below [m] (REFERENCE §4).
PENALTY_AREA_X_M = -13.2
PENALTY_AREA_HALF_WIDTH_M = 3.0
GOALKEEPER_UNUM = 1
#: Support players stay at least this far from the ball [m].
SUPPORT_CLEARANCE_M = 1.5
#: Support spots stay this far from the on-ball player's path to the ball and from the ball's path on
#: toward the goal [m] (a supporter standing there blocked the approach or the kick, and robots collided).
PATH_CLEARANCE_M = 1.0
#: Length of the ball's path toward the goal that support spots keep clear of [m].
BALL_PATH_M = 3.0
#: The second attacker (the lowest unum among the field players that do not play the ball) stands this far
#: behind the ball, toward the own goal, and this far to the side [m]: near enough to take the ball over when
#: the on-ball player falls or loses it (with formation spots alone, the only supporter of a 3 v 3 team
#: stood 9-12 m from the ball all match).
SECOND_BEHIND_M = 2.5
SECOND_SIDE_M = 1.5
#: Field bounds the support spots are kept inside, team frame [m]; field players stay out of the own
#: penalty area (more than 3 defenders there is a foul, REFERENCE §4.5 "illegal defence").
FIELD_X_MIN_M = PENALTY_AREA_X_M + 0.4
FIELD_X_LIMIT_M = 14.0
FIELD_Y_LIMIT_M = 9.5


@dataclass(frozen=True, slots=True)
class Candidate:
    """A player that may take the ball: its unum and its team-frame position."""

    unum: int
    x_m: float
    y_m: float


def ball_belief(world: WorldModel) -> tuple[float, float] | None:
    """The ball's team-frame position: the own sighting if fresh, else the freshest teammate (c) report."""
    now = world.now_s
    ball = world.ball
    if ball is not None and ball.position is not None and ball.age_s(now) <= BALL_FRESH_S:
        return ball.position
    reports = [r for r in world.reports.values()
               if r.ball is not None and r.active and now - r.heard_s <= REPORT_FRESH_S]
    if not reports:
        return None
    return max(reports, key=lambda r: r.heard_s).ball


def candidates(world: WorldModel) -> list[Candidate]:
    """Self (if localized) and the teammates with a fresh position report, by unum.

    The own position is the one of the own last message as the server echoed it, when fresh: every
    teammate decides with that same position, so all players reach the same choice.
    """
    now = world.now_s
    out: dict[int, Candidate] = {}
    pose = world.pose
    if pose is not None and world.localized and not world.body.fallen:
        own = world.own_report
        if own is not None and own.position is not None and own.active and now - own.heard_s <= REPORT_FRESH_S:
            out[world.unum] = Candidate(world.unum, *own.position)
        else:
            out[world.unum] = Candidate(world.unum, pose.x_m, pose.y_m)
    for unum, report in world.reports.items():
        if unum == world.unum or not report.active or report.position is None:
            continue
        if now - report.heard_s > REPORT_FRESH_S:
            continue
        out[unum] = Candidate(unum, *report.position)
    return [out[u] for u in sorted(out)]


def around_ball_deg(x_m: float, y_m: float, ball: tuple[float, float],
                    goal: tuple[float, float] = OPPONENT_GOAL_M) -> float:
    """Angle between the player→ball and ball→goal directions [deg], 0 = already behind the ball."""
    to_ball = math.atan2(ball[1] - y_m, ball[0] - x_m)
    to_goal = math.atan2(goal[1] - ball[1], goal[0] - ball[0])
    return abs(math.degrees(math.remainder(to_goal - to_ball, math.tau)))


def on_ball_cost(candidate: Candidate, ball: tuple[float, float], holder: int | None) -> float:
    """REFERENCE §7.10's on-ball cost [m]; lower plays the ball."""
    distance = math.hypot(ball[0] - candidate.x_m, ball[1] - candidate.y_m)
    cost = distance + ANGLE_WEIGHT_M_PER_DEG * around_ball_deg(candidate.x_m, candidate.y_m, ball)
    return cost - HOLDER_BONUS_M if candidate.unum == holder else cost


#: A teammate believed to play the ball keeps the holder bonus only while it plays: nearer the ball than
#: ``HOLDER_ENGAGED_M`` [m], or come ``HOLDER_PROGRESS_M`` nearer it within the last ``HOLDER_STALL_S`` [m, s].
#: Why: each player applies the bonus to its own belief of the holder, so two players that each believed the other
#: the holder both stood still, and their costs (0.1 m apart) never changed: on the real server two field players
#: stood 2.9 m from the ball on the centre spot for the last 58 s of a match (3 v 3 against robots that only
#: stand, seed 72 at b2a64a5; tests/scenarios/test_holder_deadlock.py). 5 s leaves a holder its chained turns
#: (a 180 deg turn before a walk takes 3.6 s) and its walk round the ball (within 1 m of it).
HOLDER_ENGAGED_M = 1.5
HOLDER_PROGRESS_M = 0.2
HOLDER_STALL_S = 5.0


@dataclass(slots=True)
class HolderWatch:
    """Whether the teammate this player believes to play the ball is playing it (keeps the holder bonus)."""

    holder: int | None = None
    since_s: float = 0.0
    nearest_m: float = math.inf

    def keeps_bonus(self, now_s: float, holder: int | None, me: int, players: list[Candidate],
                    ball: tuple[float, float], open_play: bool) -> bool:
        """False once a believed holder other than ``me`` has neither been near the ball nor come nearer it for
        ``HOLDER_STALL_S`` of open play; then the on-ball choice is made without the bonus (the plain costs,
        from positions every player shares, end a crossed belief)."""
        player = next((p for p in players if p.unum == holder), None)
        if holder == me or player is None or not open_play:
            self.holder = None
            return True
        distance = math.hypot(ball[0] - player.x_m, ball[1] - player.y_m)
        if holder != self.holder or distance <= HOLDER_ENGAGED_M or distance <= self.nearest_m - HOLDER_PROGRESS_M:
            self.holder, self.since_s, self.nearest_m = holder, now_s, distance
            return True
        return now_s - self.since_s < HOLDER_STALL_S


def keeper_plays_ball(ball: tuple[float, float]) -> bool:
    """The ball is in the own penalty area, where the goalkeeper clears it itself."""
    return ball[0] < PENALTY_AREA_X_M and abs(ball[1]) < PENALTY_AREA_HALF_WIDTH_M


def choose_on_ball(players: list[Candidate], ball: tuple[float, float], holder: int | None) -> int | None:
    """The unum that plays the ball (None without candidates)."""
    allowed = [p for p in players if p.unum != GOALKEEPER_UNUM or keeper_plays_ball(ball)]
    if not allowed:
        return None
    return min(allowed, key=lambda p: (on_ball_cost(p, ball, holder), p.unum)).unum


def clear_of_segment(point: tuple[float, float], start: tuple[float, float], end: tuple[float, float],
                     clearance_m: float) -> tuple[float, float]:
    """``point`` moved straight away from the segment start-end until it is ``clearance_m`` from it (unchanged
    if already that far; a point on the segment goes to its left side, seen from start to end)."""
    sx, sy = end[0] - start[0], end[1] - start[1]
    length_sq = sx * sx + sy * sy
    t = 0.0 if length_sq < 1e-12 else max(0.0, min(1.0, ((point[0] - start[0]) * sx + (point[1] - start[1]) * sy)
                                                    / length_sq))
    nearest = (start[0] + t * sx, start[1] + t * sy)
    dx, dy = point[0] - nearest[0], point[1] - nearest[1]
    distance = math.hypot(dx, dy)
    if distance >= clearance_m:
        return point
    if distance < 1e-6:
        length = math.sqrt(length_sq) or 1.0
        dx, dy, distance = -sy / length, sx / length, 1.0
    return nearest[0] + dx / distance * clearance_m, nearest[1] + dy / distance * clearance_m


def support_spot(unum: int, ball: tuple[float, float] | None,
                 holder: tuple[float, float] | None = None) -> tuple[float, float]:
    """Where a player that does not play the ball stands [m]: its formation spot shifted with the ball
    (forward when the ball is forward), kept in the field, out of the own penalty area,
    ``SUPPORT_CLEARANCE_M`` from the ball, and ``PATH_CLEARANCE_M`` from the paths of the play: the on-ball
    player's (``holder``'s position, if known) to the ball and the ball's on toward the opponent goal."""
    home = beam_spot(unum)
    if ball is None:
        return home.x_m, home.y_m
    x = home.x_m + 0.6 * (ball[0] + 5.0)
    y = home.y_m + 0.3 * ball[1]
    x = max(FIELD_X_MIN_M, min(FIELD_X_LIMIT_M, x))
    y = max(-FIELD_Y_LIMIT_M, min(FIELD_Y_LIMIT_M, y))
    dx, dy = x - ball[0], y - ball[1]
    distance = math.hypot(dx, dy)
    if distance < SUPPORT_CLEARANCE_M:
        # Step back toward the own goal side of the ball.
        if distance < 1e-6:
            dx, dy, distance = -1.0, 0.0, 1.0
        x, y = ball[0] + dx / distance * SUPPORT_CLEARANCE_M, ball[1] + dy / distance * SUPPORT_CLEARANCE_M
    to_goal = math.atan2(OPPONENT_GOAL_M[1] - ball[1], OPPONENT_GOAL_M[0] - ball[0])
    ahead = (ball[0] + BALL_PATH_M * math.cos(to_goal), ball[1] + BALL_PATH_M * math.sin(to_goal))
    x, y = clear_of_segment((x, y), ball, ahead, PATH_CLEARANCE_M)
    if holder is not None:
        x, y = clear_of_segment((x, y), holder, ball, PATH_CLEARANCE_M)
    x = max(FIELD_X_MIN_M, min(FIELD_X_LIMIT_M, x))
    y = max(-FIELD_Y_LIMIT_M, min(FIELD_Y_LIMIT_M, y))
    return x, y


def kick_off_receiver(players: list[Candidate]) -> int | None:
    """Who waits to play the ball at the opponents' kick-off: the lowest field-player unum, named alike by every
    player without positions. Why: after the kick-off beam the field players stand symmetric about the centre
    line, 2.5 m from the ball, so the on-ball costs tie within centimetres and each player's own hysteresis
    decided; on the real server two of them both walked to the waiting spot behind the ball and bumped there
    (3 v 3 against robots that only stand, seed 98: the ball lay 14.7 s after the kick-off's PlayOn), or each
    named the other and both stood aside (seeds 69 and 72: 41 and 58 s)."""
    return min((p.unum for p in players if p.unum != GOALKEEPER_UNUM), default=None)


def second_attacker(players: list[Candidate], holder: int | None) -> int | None:
    """The unum of the second attacker: the lowest field-player unum that does not play the ball."""
    others = [p.unum for p in players if p.unum not in (holder, GOALKEEPER_UNUM)]
    return min(others, default=None)


#: The on-ball player this far over the ball->goal line onto the second attacker's side moves it across [m].
SECOND_SIDE_SWITCH_M = 0.5


def second_attacker_side(ball: tuple[float, float], holder: tuple[float, float] | None,
                         current: float | None = None) -> float:
    """The side of the ball->goal line the second attacker takes (+1 left, -1 right): the one the on-ball player
    is not on. ``current`` (the side taken so far) is kept until the holder is ``SECOND_SIDE_SWITCH_M`` over the
    line onto it: a holder circling the ball near the line flipped the side every few seconds, and the second
    attacker crossing behind the ball ran into it (11 v 11 on our simulator, seed 1: 7 falls in 150 s, all of
    the second attacker and the on-ball player within 0.5 m of each other)."""
    if holder is None:
        return 1.0 if current is None else current
    to_goal = math.atan2(OPPONENT_GOAL_M[1] - ball[1], OPPONENT_GOAL_M[0] - ball[0])
    ux, uy = math.cos(to_goal), math.sin(to_goal)
    across = ux * (holder[1] - ball[1]) - uy * (holder[0] - ball[0])  # holder left of the line: > 0
    if current is not None and across * current < SECOND_SIDE_SWITCH_M:
        return current
    return -1.0 if across > 0 else 1.0


def second_attacker_spot(ball: tuple[float, float], holder: tuple[float, float] | None,
                         side: float | None = None) -> tuple[float, float]:
    """Where the second attacker stands [m]: ``SECOND_BEHIND_M`` behind the ball on the line from the opponent
    goal, ``SECOND_SIDE_M`` to ``side`` (default: the side the on-ball player is not on,
    ``second_attacker_side``), clear of the play's paths, in the field."""
    to_goal = math.atan2(OPPONENT_GOAL_M[1] - ball[1], OPPONENT_GOAL_M[0] - ball[0])
    ux, uy = math.cos(to_goal), math.sin(to_goal)
    if side is None:
        side = second_attacker_side(ball, holder)
    if abs(ball[1] + side * SECOND_SIDE_M * ux) > FIELD_Y_LIMIT_M:
        side = -side
    x = ball[0] - SECOND_BEHIND_M * ux - side * SECOND_SIDE_M * uy
    y = ball[1] - SECOND_BEHIND_M * uy + side * SECOND_SIDE_M * ux
    if holder is not None:
        x, y = clear_of_segment((x, y), holder, ball, PATH_CLEARANCE_M)
    return max(FIELD_X_MIN_M, min(FIELD_X_LIMIT_M, x)), max(-FIELD_Y_LIMIT_M, min(FIELD_Y_LIMIT_M, y))


#: A rolling ball that will cross the keeper's line within this of the centre is a shot the keeper blocks [m]
#: (the goal is 2.1 m wide, REFERENCE §4; a ball and a margin beyond the posts).
KEEPER_INTERCEPT_HALF_WIDTH_M = 1.3


def keeper_spot(ball: tuple[float, float] | None, crossing_y_m: float | None = None) -> tuple[float, float]:
    """The goalkeeper's guard spot [m]: on its line, following the ball's y within the goal's width; where a
    rolling ball will cross that line (``crossing_y_m``, from ``agent.world.ball_track``) when it will cross it
    within ``KEEPER_INTERCEPT_HALF_WIDTH_M`` of the centre (a shot on goal: block it)."""
    if crossing_y_m is not None and abs(crossing_y_m) <= KEEPER_INTERCEPT_HALF_WIDTH_M:
        return KEEPER_X_M, max(-KEEPER_HALF_WIDTH_M, min(KEEPER_HALF_WIDTH_M, crossing_y_m))
    y = 0.0 if ball is None else max(-KEEPER_HALF_WIDTH_M, min(KEEPER_HALF_WIDTH_M, 0.3 * ball[1]))
    return KEEPER_X_M, y


__all__ = ["Candidate", "ball_belief", "candidates", "choose_on_ball", "clear_of_segment", "keeper_plays_ball",
           "keeper_spot", "on_ball_cost", "second_attacker", "second_attacker_side", "second_attacker_spot",
           "support_spot"]
