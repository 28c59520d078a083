"""Own set pieces under the rules' one-touch limit (REFERENCE §4.4): who took the last one, and the kick-off
kick played at once.

Why: the taker of a kick-off, kick-in, corner, goal kick or free kick may not touch the ball again before
another player did ("double touch": an indirect free kick for the opponents). Dribbling from a set piece did
exactly that on our simulator (kick-off, then free_kick_right 0.3 s later). So the taker plays one kick and
then stays out of the on-ball choice until someone else was at the ball (or ``TAKER_WAIT_S`` passed); every
player keeps the same memory from the same beliefs, so the team agrees on it without a message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.skills.kick_lineup import KickConfig
from agent.team.roles import GOALKEEPER_UNUM, Candidate
from agent.world_model import WorldModel

#: The set-piece taker stays out of the on-ball choice at most this long after its set piece ended [s] (with 8 s
#: the taker went back to its kick-off ball before the teammate had reached it: free kick for the opponents).
TAKER_WAIT_S = 30.0
#: Another player this near the ball (torso centre) counts as having touched it [m].
TOUCH_NEAR_M = 0.3
#: Play modes of set pieces (the suffix names the team taking it).
SET_PIECE_PREFIXES = ("KickOff_", "KickIn_", "corner_kick_", "goal_kick_", "free_kick_", "direct_free_kick_",
                      "pass_")


def own_set_piece(play_mode: str, side: str | None) -> bool | None:
    """True for the own team's set piece, False for the opponents', None when no set piece."""
    for prefix in SET_PIECE_PREFIXES:
        if play_mode.startswith(prefix):
            taker = play_mode[len(prefix):].lower()
            return side is not None and taker == side
    return None


@dataclass
class TakerMemory:
    """Who took the own team's last set piece and whether it must still keep off the ball."""

    taker: int | None = None
    """The unum that held the ball during the last own set piece."""
    since_s: float | None = None
    """Server time the set piece ended (None while it runs or without one)."""
    _holder_in_set_piece: int | None = None

    def update(self, world: WorldModel, own: bool | None, holder: int | None) -> None:
        """Called every cycle with this cycle's set-piece state and the on-ball choice."""
        if own is True:
            self._holder_in_set_piece = holder
            self.taker, self.since_s = None, None
            return
        if own is None and self._holder_in_set_piece is not None:
            self.taker, self.since_s = self._holder_in_set_piece, world.now_s
            self._holder_in_set_piece = None
        elif own is False:
            self._holder_in_set_piece = None
            self.taker, self.since_s = None, None

    def excluded(self, world: WorldModel, ball: tuple[float, float], players: list[Candidate]) -> int | None:
        """The unum that must not play the ball now (None when everyone may)."""
        if self.taker is None or self.since_s is None:
            return None
        if world.now_s - self.since_s > TAKER_WAIT_S or _someone_else_at(world, ball, players, self.taker):
            self.taker, self.since_s = None, None
            return None
        if not any(p.unum not in (self.taker, GOALKEEPER_UNUM) for p in players):
            return None  # nobody else can play it (fallen, silent): the taker must, double touch or not
        return self.taker


def _someone_else_at(world: WorldModel, ball: tuple[float, float], players: list[Candidate], taker: int) -> bool:
    """A teammate other than the taker, or an opponent, is believed at the ball."""
    for player in players:
        if player.unum != taker and math.hypot(player.x_m - ball[0], player.y_m - ball[1]) <= TOUCH_NEAR_M:
            return True
    for opponent in world.opponents.values():
        if opponent.position is not None and opponent.age_s(world.now_s) <= 1.0 and \
                math.hypot(opponent.position[0] - ball[0], opponent.position[1] - ball[1]) <= TOUCH_NEAR_M:
            return True
    return False


#: The set-piece windows below count from the kick motion's spot, which moved 4 mm out on 2026-11-28 (into the
#: kick's far regime on both servers, see ``KickConfig.forward_min_m``); the measurements quoted are from the spot
#: before, the numbers 4 mm less, so the taker plays the same ball positions as before.
#:
#: The set-piece kick window: the ball this far beyond the kick motion's spot at most [m] (on our simulator a
#: kick from 8-15 cm beyond still moves the ball about 1 m: a pass that lets a teammate play on), ...
SET_PIECE_FORWARD_MAX_M = 0.146
#: ... but beyond this [m] the taker first closes in with kick steps (2 cm each, ``SET_PIECE_MAX_STEPS`` at
#: most): on the real rcssserver3d 0.7.3 a set-piece kick from 6-12 cm beyond the spot moved the ball 0.01-0.9 m
#: in 5 of 6 kick-offs (grazes; one was touched again: a free kick for the opponents), from 0-5.3 cm beyond it
#: 2.8-4.0 m in all 9 (3 v 3 runs at cd49592-05ecef2). The line-up's walk-in covers more there than the
#: strides it plans with, so its kick-offs end farther beyond the spot than ours (0.011-0.05 m in 8 seeds). The
#: kick itself (``python -m motion_studio.realserver.kick_check kick --offsets-cm=2,3,4,5,6``, 2026-11-26) goes
#: 4.32, 4.28, 4.18, 4.06 m and then 0.08 m at +6 cm on the real server (ours on the ball contacts fitted on
#: pushes: 4.38, 4.22, 4.17, 4.14, 0.59 m): the cliff lies between 5 and 6 cm, and the ball seen standing is
#: off by up to a centimetre, so the steps go on down to 4.5 cm (with 5.5 ours grazed the kick-off of seed 0
#: from 5.3 cm as seen: 0.33 m). ...
SET_PIECE_STEP_BEYOND_M = 0.041
SET_PIECE_MAX_STEPS = 4
#: ... this far short of it at most [m] (nearer, the toes reach under the ball), ...
SET_PIECE_FORWARD_MIN_M = -0.034
#: ... and this far across it [m].
SET_PIECE_LATERAL_M = 0.04


def kick_window(ball_ego: tuple[float, float], spot_forward_m: float, spot_left_m: float) -> bool:
    """The ball lies where the kick motion still moves it on: a set piece plays the kick as is."""
    forward, left = ball_ego[0] - spot_forward_m, ball_ego[1] - spot_left_m
    return SET_PIECE_FORWARD_MIN_M <= forward <= SET_PIECE_FORWARD_MAX_M and abs(left) <= SET_PIECE_LATERAL_M


#: The long kick's set-piece window (``kick_strong``): along the kick line the kick skill's (``KickConfig.
#: strong_forward_min_m`` / ``_max_m``, whose docstrings have the measured cliffs), and across its spot
#: this far [m] (on the real server 5.0-5.7 m with the ball 1.5 and 3 cm across, ours 4.2-4.8 m).
LONG_KICK_LATERAL_M = 0.03


def long_kick_window(ball_ego: tuple[float, float], spot_forward_m: float, spot_left_m: float) -> bool:
    """The ball lies where the long kick sends it its full distance: a set piece plays it instead of the kick."""
    forward, left = ball_ego[0] - spot_forward_m, ball_ego[1] - spot_left_m
    return (KickConfig.strong_forward_min_m <= forward <= KickConfig.strong_forward_max_m
            and abs(left) <= LONG_KICK_LATERAL_M)


#: A ball off to the side of the window by up to this (across the kick spot) [m] is brought in with kick steps
#: sideways (about 2 cm each on both servers) rather than the kick line-up's walk round the ball: on our simulator
#: a kick-off whose walk-in left the ball 6.2 cm aside walked round it for 10 s.
SET_PIECE_SIDE_STEP_REACH_M = 0.08
#: ... and only with the ball at least this far along the line from the spot [m] (nearer, a sideways step pushes
#: the ball away; the spot before 2026-11-28 itself).
SET_PIECE_SIDE_STEP_MIN_M = -0.004


def set_piece_move(ball_ego: tuple[float, float], spot_forward_m: float, spot_left_m: float,
                   steps_taken: int) -> str | None:
    """What a set-piece taker standing still and facing its aim does: ``"kick"`` with the ball in the kick
    window; ``"step"`` (one kick step forward) first while it lies beyond ``SET_PIECE_STEP_BEYOND_M``;
    ``"step_left"`` / ``"step_right"`` (one kick step sideways) while it lies beside the window within
    ``SET_PIECE_SIDE_STEP_REACH_M`` and not short of ``SET_PIECE_SIDE_STEP_MIN_M`` (nearer, a sideways step pushes the
    ball away);
    steps only while fewer than ``SET_PIECE_MAX_STEPS`` were taken; None otherwise (line up again)."""
    forward, left = ball_ego[0] - spot_forward_m, ball_ego[1] - spot_left_m
    if kick_window(ball_ego, spot_forward_m, spot_left_m):
        return "step" if forward > SET_PIECE_STEP_BEYOND_M and steps_taken < SET_PIECE_MAX_STEPS else "kick"
    if (SET_PIECE_SIDE_STEP_MIN_M <= forward <= SET_PIECE_FORWARD_MAX_M and abs(left) <= SET_PIECE_SIDE_STEP_REACH_M
            and steps_taken < SET_PIECE_MAX_STEPS):
        return "step_left" if left > 0.0 else "step_right"  # beside the window (outside it, so |left| > its width)
    return None


__all__ = ["SET_PIECE_MAX_STEPS", "SET_PIECE_SIDE_STEP_MIN_M", "SET_PIECE_SIDE_STEP_REACH_M", "SET_PIECE_STEP_BEYOND_M",
           "TAKER_WAIT_S", "TakerMemory", "kick_window", "long_kick_window", "own_set_piece", "set_piece_move"]
