"""Which robot type each of our players asks for (REFERENCE §2.5: a team fields at least 3 types, at most 7
robots of one type and 9 of any two).

Why 0, 2 and 4: those are the types whose every skill works on both servers. Types 1 and 3 (longer legs) stand up
from both sides since 2026-11-26 (their own stand-ups, ``motions/authoring/standup_types.py``) and, since
2026-11-27, kick from their own spot (``motions/files/robot_types.toml``: the shared kick grazed the ball from type
0's spot on the real server): type 1 4.2-4.8 m there but it falls after about half of its kicks, type 3 4.8-5.1 m
without a fall (ours falls after every type-3 kick of the kick bench, not in the real-skills case: a disagreement
of ours); since 2026-11-28 both play long kicks of their own (real 5.8 / 6.1 m on the spot), and since 2026-11-30
type 3 lines up for its kick with its own walk-in (``agent.skills.kick_lineup.KICK_CONFIG_BY_TYPE``). Their dribble
keeps them out: 10 m took 40 s (type 1, 2026-11-27) or more than 45 s (type 3) on the real server, and neither
finished within the 46 s of ``motion-studio real skills dribble`` on 2026-11-30. The types cycle by uniform number, so every team size from 3 up is
legal (11 players: four of type 0, four of type 2, three of type 4) and the goalkeeper (unum 1) is type 0, the type
every motion was tuned on.
"""

from __future__ import annotations

#: The types our players use, in the order uniform numbers take them.
TEAM_TYPES: tuple[int, ...] = (0, 2, 4)
#: The type an agent asks for when its uniform number is left to the server (unum 0).
UNKNOWN_UNUM_TYPE = 0


def robot_type_for(unum: int) -> int:
    """Robot type for uniform number ``unum`` (1-11); ``UNKNOWN_UNUM_TYPE`` for 0 (the server picks)."""
    if unum <= 0:
        return UNKNOWN_UNUM_TYPE
    return TEAM_TYPES[(unum - 1) % len(TEAM_TYPES)]


def parse_robot_type(text: str) -> int | None:
    """A ``--type`` option: 0-4, or None for ``auto`` (then :func:`robot_type_for` decides).

    Raises:
        ValueError: anything else (the message says what is accepted).
    """
    if text == "auto":
        return None
    try:
        value = int(text)
    except ValueError:
        raise ValueError(f"robot type must be 0-4 or auto, got {text!r}") from None
    if not 0 <= value <= 4:
        raise ValueError(f"robot type must be 0-4 or auto, got {value}")
    return value


__all__ = ["TEAM_TYPES", "UNKNOWN_UNUM_TYPE", "parse_robot_type", "robot_type_for"]
