"""The baseline opponent: the seed's behaviour without coordination (issue 15 item 4).

Why: a team to measure ours against that plays the ball but does not coordinate. Every player applies one
rule on its own beliefs: the player nearest to the ball (by the positions it hears from its teammates; no
angle term, no holder bonus) goes to the ball and kicks it toward the opponent goal; the others walk to
their formation spots (``agent.formation.beam_spot``) and face the ball; the goalkeeper keeps its line.
The skills, fall recovery and play-mode handling are our ``SoccerBehavior``'s.
"""

from __future__ import annotations

import math

from agent.team import roles
from agent.team.soccer_behavior import SoccerBehavior, own_set_piece
from agent.formation import beam_spot
from agent.skills.walk_ball import WalkToBall
from agent.world_model import WorldModel


def nearest_to_ball(players: list[roles.Candidate], ball: tuple[float, float]) -> int | None:
    """The unum of the field player nearest to the ball (lower unum on ties; None without candidates)."""
    field = [p for p in players if p.unum != roles.GOALKEEPER_UNUM]
    if not field:
        return None
    return min(field, key=lambda p: (math.hypot(ball[0] - p.x_m, ball[1] - p.y_m), p.unum)).unum


class BaselineBehavior(SoccerBehavior):
    """Nearest field player to the ball kicks toward the goal; the rest hold their formation spots."""

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


__all__ = ["BaselineBehavior", "nearest_to_ball"]
