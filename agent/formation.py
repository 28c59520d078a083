"""Beam spots before kick-off (REFERENCE §7.10 "Initial beam spots", the idea of the 2012 code).

The thesis' 9 spots are for its 21 × 14 m field; both axes scale by the same factor to 0.7.3's 30 × 20 m
field (15/10.5 = 10/7 = 1.4286), so the shape is kept. Unums 10 and 11 did not exist in the thesis: they
get two wide midfield spots (our choice). All spots are in the team frame (own goal at −x), outside the
centre circle and inside beam's clamp (x in [−15, 0], REFERENCE §3.7); rotation 0 faces the opponent goal.
"""

from __future__ import annotations

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


#: Formation name -> unum -> spot; ``thesis`` is the default.
FORMATIONS: dict[str, dict[int, BeamSpot]] = {"thesis": _scaled()}
DEFAULT_FORMATION = "thesis"


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
