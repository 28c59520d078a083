"""Time-sliced say (REFERENCE §7.9): 3-cycle slots, a rotating label naming the unum that may speak.

* A slot is 3 cycles: the labelled player says in its first cycle, then 2 idle cycles, which keeps the team
  under the server's one message per team every 2 cycles (REFERENCE §3.8).
* The label rises by 1 per slot and wraps after the highest unum; a full round is 3·N cycles.
* Every play-mode change resets the label: all agents see the change in the same server cycle, so it is a
  shared clock. Cycles are counted from server time (``round((now − change) / 0.02)``), not from messages
  received, so a missed sense message in real-time mode does not shift the agent's slots. Before any change
  has been seen (BeforeKickOff after connecting) the reference is server time 0, the same for everybody.
"""

from __future__ import annotations
from agent.protocol.constants import CYCLE_S

SLOT_CYCLES = 3
DEFAULT_TEAM_SIZE = 11


def cycles_since(now_s: float, since_s: float) -> int:
    """Whole cycles between two server times (both printed with 2 decimals)."""
    return round((now_s - since_s) / CYCLE_S)


def slot_label(now_s: float, since_s: float, team_size: int = DEFAULT_TEAM_SIZE) -> int:
    """The unum (1…team_size) whose slot contains this cycle."""
    return (cycles_since(now_s, since_s) // SLOT_CYCLES) % team_size + 1


def may_say(unum: int, now_s: float, since_s: float, team_size: int = DEFAULT_TEAM_SIZE) -> bool:
    """True in the sending cycle (the first of the 3) of the slot labelled ``unum``."""
    cycles = cycles_since(now_s, since_s)
    return cycles % SLOT_CYCLES == 0 and (cycles // SLOT_CYCLES) % team_size + 1 == unum
