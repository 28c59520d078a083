"""Beam spots before kick-off (REFERENCE §7.10 "Initial beam spots", the idea of the 2012 code).

The thesis' 9 spots are for its 21 × 14 m field; both axes scale by the same factor to 0.7.3's 30 × 20 m
field (15/10.5 = 10/7 = 1.4286), so the shape is kept. Unums 10 and 11 did not exist in the thesis: they
get two wide midfield spots (our choice). All spots are in the team frame (own goal at −x), outside the
centre circle and inside beam's clamp (x in [−15, 0], REFERENCE §3.7); rotation 0 faces the opponent goal.
"""

from __future__ import annotations

import math

from dataclasses import dataclass

from agent.errors import ConfigError

_THESIS_FIELD_HALF_LENGTH_M = 10.5
_FIELD_HALF_LENGTH_M = 15.0
SCALE = _FIELD_HALF_LENGTH_M / _THESIS_FIELD_HALF_LENGTH_M

#: The 2012 code's 9 spots on the 21 × 14 field, by unum (∓ read as: the lower unum on the −y side).
THESIS_SPOTS_M: dict[int, tuple[float, float]] = {
    1: (-10.4, 0.0), 2: (-8.5, -3.0), 3: (-8.5, 3.0), 4: (-8.5, 0.0), 5: (-5.0, -1.0), 6: (-5.0, 1.0),
    7: (-2.0, -2.0), 8: (-2.0, 2.0), 9: (-2.0, 0.0),
}
#: Spots for the 2 players the thesis did not have [m], already on the 30 × 20 field.
EXTRA_SPOTS_M: dict[int, tuple[float, float]] = {10: (-5.0, -5.0), 11: (-5.0, 5.0)}


@dataclass(frozen=True, slots=True)
class BeamSpot:
    """Where to beam, team frame."""

    x_m: float
    y_m: float
    rot_deg: float = 0.0


def _scaled() -> dict[int, BeamSpot]:
    spots = {unum: BeamSpot(round(x * SCALE, 2), round(y * SCALE, 2)) for unum, (x, y) in THESIS_SPOTS_M.items()}
    spots.update({unum: BeamSpot(x, y) for unum, (x, y) in EXTRA_SPOTS_M.items()})
    return spots


#: The kick-off spot of the striker (unum 2) [m]: one walk-in stride (0.333 m) behind the kick motion's spot
#: (ball_forward_m 0.129) plus 4 cm, so the kick skill's line-up is a turn (beam noise: +-10 deg, +-5 cm)
#: and one stride; nearer, the robot's 0.15 m footprint reaches into the opponent half (the referee moves it
#: to x = -2.5) or the line-up has to back off first (with the thesis spots the nearest field player of a
#: 3-player team stood 12 m from the ball and the kick-off ran out its 15 s).
KICK_OFF_SPOT_M = (-0.5, 0.0)
#: Unum 3's spot [m]: beside the striker, just outside the centre circle (2.5 m from the centre: at (-1.2, 1.0)
#: it stood inside, and at the opponents' kick-off the referee moved it to x = -2.5 from there).
SECOND_ATTACKER_SPOT_M = (-2.2, 1.2)
#: The ``attack`` formation by unum: goalkeeper, striker at the ball, two forwards beside the centre circle,
#: then the thesis' defenders and midfielders (the low unums play in small teams, so they are the attackers).
_ATTACK_FROM_THESIS = {5: 4, 6: 2, 7: 3, 8: 5, 9: 6}


def _attack() -> dict[int, BeamSpot]:
    thesis = _scaled()
    spots = {1: thesis[1], 2: BeamSpot(*KICK_OFF_SPOT_M), 3: BeamSpot(*SECOND_ATTACKER_SPOT_M), 4: BeamSpot(-2.6, -2.0)}
    spots.update({unum: thesis[source] for unum, source in _ATTACK_FROM_THESIS.items()})
    spots.update({10: thesis[10], 11: thesis[11]})
    return spots


#: Formation name -> unum -> spot; ``attack`` is the default.
FORMATIONS: dict[str, dict[int, BeamSpot]] = {"thesis": _scaled(), "attack": _attack()}
DEFAULT_FORMATION = "attack"


#: At a kick-off the players not taking it stand this far inside the own half [m] ...
KICK_OFF_HALF_MARGIN_M = 0.4
#: ... and, at the opponents' kick-off, this far from the centre spot (the circle's radius is 2 m) [m] ...
KICK_OFF_CIRCLE_CLEARANCE_M = 2.5
#: ... and, within ``KICK_OFF_NEAR_M`` of the centre spot, this far beside the line through it along the field,
#: on the side given by the unum [m]: a player waiting on the line (the circle pushed a spot at x = -0.4
#: straight back to (-2.5, 0)) stood in the path of the kick-off, whose taker then lined up a 35 deg kick for
#: 11 s (ours against ours); and a spot whose side came from the ball's noise flipped, so the player turned
#: back and forth.
KICK_OFF_LINE_CLEARANCE_M = 1.2
KICK_OFF_NEAR_M = 4.0


def kick_off_spot(x_m: float, y_m: float, unum: int, opponents_kick_off: bool) -> tuple[float, float]:
    """(x, y) moved where the kick-off rules (REFERENCE §4.4) let a player that does not take the kick-off
    stand, team frame [m]: in the own half, and at the opponents' kick-off outside the centre circle. The
    referee moves a player standing elsewhere, and a robot set down there falls as it walks on (measured on
    our simulator: 2-3 falls in most 120 s matches, all at the opponents' kick-off after our goal: players
    beamed into the circle at their kick-off spots, or walking to support spots in the opponent half)."""
    x, y = min(x_m, -KICK_OFF_HALF_MARGIN_M), y_m
    if opponents_kick_off and math.hypot(x, y) < KICK_OFF_NEAR_M:
        y = (1.0 if unum % 2 == 0 else -1.0) * max(abs(y), KICK_OFF_LINE_CLEARANCE_M)
        distance = math.hypot(x, y)
        if distance < KICK_OFF_CIRCLE_CLEARANCE_M:
            x, y = x / distance * KICK_OFF_CIRCLE_CLEARANCE_M, y / distance * KICK_OFF_CIRCLE_CLEARANCE_M
    return x, y


def beam_spot(unum: int, formation: str = DEFAULT_FORMATION) -> BeamSpot:
    """The beam spot of ``unum`` in a formation.

    Raises:
        ConfigError: unknown formation (the message lists the known ones) or a unum outside 1-11.
    """
    try:
        spots = FORMATIONS[formation]
    except KeyError:
        raise ConfigError(f"unknown formation {formation!r}; known: {', '.join(FORMATIONS)}", "formation") from None
    try:
        return spots[unum]
    except KeyError:
        raise ConfigError(f"no beam spot for unum {unum} in formation {formation!r}: expected 1-11", "unum") from None
