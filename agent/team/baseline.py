"""Opponents without coordination to measure ours against (issue 15 item 4).

Why two: the issue asks for "the seed's behaviour without coordination: the nearest player goes to the ball
and kicks toward the goal" (REFERENCE §7.8), and that is ``BaselineBehavior``. ``SoloBehavior`` is our own
on-ball play (the dribble) without the coordination: against it a match measures what the team layer adds
and nothing else. Until 2026-11-26 the shipped "baseline" was the solo team, while its docstrings said it
kicked.

In both, every player applies one rule on its own beliefs: the field player nearest to the ball (by the
positions it hears from its teammates; no angle term, no holder bonus) plays it; the others walk to their
formation spots (``agent.formation.beam_spot``) and face the ball; the goalkeeper keeps its line. As in the
seed, the taker of a set piece may go on playing the ball (a double touch gives the opponents a free kick). The
skills, fall recovery and play-mode handling are our ``SoccerBehavior``'s.
"""

from __future__ import annotations

import math

from agent.formation import beam_spot
from agent.skills.kick import KickToward
from agent.skills.walk_ball import WalkToBall
from agent.team import roles
from agent.team.soccer_behavior import SoccerBehavior, own_set_piece
from agent.world_model import WorldModel

#: The seed plays its normal kick when the goal is nearer than this, else the strong kick (REFERENCE §7.8) [m].
SEED_NORMAL_KICK_WITHIN_M = 2.5


def nearest_to_ball(players: list[roles.Candidate], ball: tuple[float, float]) -> int | None:
    """The unum of the field player nearest to the ball (lower unum on ties; None without candidates)."""
    field = [p for p in players if p.unum != roles.GOALKEEPER_UNUM]
    if not field:
        return None
    return min(field, key=lambda p: (math.hypot(ball[0] - p.x_m, ball[1] - p.y_m), p.unum)).unum


def seed_kick_is_strong(ball: tuple[float, float]) -> bool:
    """The seed's kick choice: the strong kick unless the opponent goal is within 2.5 m of the ball."""
    goal = roles.OPPONENT_GOAL_M
    return math.hypot(goal[0] - ball[0], goal[1] - ball[1]) >= SEED_NORMAL_KICK_WITHIN_M


class SoloBehavior(SoccerBehavior):
    """The nearest field player plays the ball with our on-ball play (the dribble); the rest hold their
    formation spots. Subclasses change only how the ball is played (``_play_ball``)."""

    def _decide(self, world: WorldModel) -> None:
        game = world.game
        if self._idle_while_frozen(world):
            return
        ball = roles.ball_belief(world)
        if world.unum == roles.GOALKEEPER_UNUM:
            self.role = "keeper"
            self._stand_at(world, roles.keeper_spot(ball), ball)
            return
        if ball is None:
            self.role = "search"
            self._use(("search",), WalkToBall)
            return
        self.holder = nearest_to_ball(roles.candidates(world), ball)
        if self.holder == world.unum and own_set_piece(game.play_mode, game.side) is not False:
            self.role = "on_ball"
            self._play_ball(ball)
            return
        self.role = "support"
        home = beam_spot(world.unum, "thesis")
        self._stand_at(world, (home.x_m, home.y_m), ball)


class BaselineBehavior(SoloBehavior):
    """The seed without coordination: the nearest field player walks to the ball, lines up and kicks it toward
    the centre of the opponent goal (``KickToward``: the seed's walk-to-ball, align, prepare and kick states),
    strong unless the goal is near; then the next kick."""

    def _play_ball(self, ball: tuple[float, float]) -> None:
        skill = self.skills.skill
        kicks = self._key[1] if isinstance(self._key, tuple) and self._key[0] == "seed_kick" else 0
        if kicks and skill is not None and not skill.done:
            return  # the kick under way keeps its line-up, even when the ball belief wanders
        strong = seed_kick_is_strong(ball)
        self._use(("seed_kick", kicks + 1), lambda: KickToward(*roles.OPPONENT_GOAL_M, strong=strong))


__all__ = ["BaselineBehavior", "SEED_NORMAL_KICK_WITHIN_M", "SoloBehavior", "nearest_to_ball", "seed_kick_is_strong"]
