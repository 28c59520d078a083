"""3 v 3 of our agents (types 0, 2, 4) against robots that only stand, on our simulator, for scenario tests."""

from __future__ import annotations

from motion_studio.match_agents import SideAgents
from sim.engine import SimEngine
from sim.inprocess import InProcessHost


def our_team_against_standing(seed: int = 0) -> tuple[SimEngine, InProcessHost, dict[tuple[str, int], int]]:
    """Both teams connected (one agent per 2 cycles, as a match connects them) and 2 s in BeforeKickOff; returns
    the engine, the host and the robot keys by (team, unum)."""
    engine = SimEngine(seed=seed)
    host = InProcessHost(engine)
    factory = SideAgents("ours", "standing")
    keys = {}
    for unum in range(1, 4):
        for team in ("Left", "Right"):
            keys[team, unum] = host.add(factory(team, unum, (0, 2, 4)[unum - 1]))
            host.run(2)
    host.run(100)
    return engine, host, keys
