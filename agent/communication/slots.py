"""Time-sliced say (REFERENCE §7.9): 3-cycle slots, a rotating label naming the unum that may speak.

* A slot is 3 cycles: the labelled player says in its first cycle, then 2 idle cycles, which keeps the team
  under the server's one message per team every 2 cycles (REFERENCE §3.8).
* The label rises by 1 per slot and wraps after the highest unum; a full round is 3·N cycles.
* Every play-mode change resets the label: all agents see the change in the same server cycle, so it is a
  shared clock. The world model counts the cycles since the change (``GameInfo.play_mode_cycles``) one per
  sense message, more when the server time jumped (``cycles_elapsed``: a sense message missed in real-time
  mode does not shift the agent's slots). Before any change has been seen (BeforeKickOff after connecting)
  the count starts from server time 0, the same for everybody.

Why not ``round((now - change) / 0.02)``: the real rcssserver3d prints its clock with 2 decimals from a float
that drifts off the 0.02 s grid, so that difference often came out at a half cycle (5.99 s, 6.01 s) and
rounding skipped one cycle and repeated the next: players lost their say turn or said twice, teammates did
not hear each other for more than ``REPORT_FRESH_S``, and two of them went for the ball and ran into each
other (3 v 3 on the real server: the keeper missed 90 % of its teammates' reports).
"""

from __future__ import annotations
from agent.protocol.constants import CYCLE_S

SLOT_CYCLES = 3
DEFAULT_TEAM_SIZE = 11


def cycles_elapsed(previous_s: float, now_s: float) -> int:
    """Cycles between two consecutive sense messages from their server times [s] (as printed, 2 decimals):
    one, unless the clock moved on by at least 1.75 cycles (then the rounded count). Printed times are off by
    up to 5 ms each, so one cycle reads as 10-30 ms."""
    elapsed = now_s - previous_s
    return 1 if elapsed < 1.75 * CYCLE_S else round(elapsed / CYCLE_S)


def slot_label(play_mode_cycles: int, team_size: int = DEFAULT_TEAM_SIZE) -> int:
    """The unum (1…team_size) whose slot contains this cycle (``play_mode_cycles`` since the last change)."""
    return (play_mode_cycles // SLOT_CYCLES) % team_size + 1


def may_say(unum: int, play_mode_cycles: int, team_size: int = DEFAULT_TEAM_SIZE) -> bool:
    """True in the sending cycle (the first of the 3) of the slot labelled ``unum``."""
    return play_mode_cycles % SLOT_CYCLES == 0 and slot_label(play_mode_cycles, team_size) == unum
