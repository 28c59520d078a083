"""One of our agents alone on our simulator, in PlayOn at a chosen spot: the set-up of the scenario tests that
watch a single player (striker, keeper, ball tracking)."""

from __future__ import annotations

from sim.engine import SimEngine
from sim.inprocess import InProcessHost


def alone_in_play(agent, x_m: float, y_m: float, heading_deg: float = 0.0,
                  seed: int = 0) -> tuple[SimEngine, InProcessHost]:
    """``agent`` (the left team's) connected, the left kick-off turned into PlayOn at once, its robot put at
    (x, y) facing ``heading_deg`` (0 = the opponent goal) [m, deg]."""
    engine = SimEngine(seed=seed)
    host = InProcessHost(engine)
    key = host.add(agent)
    host.run(10)
    engine.referee.kick_off("Left")
    engine.referee.set_play_mode("PlayOn")
    engine.world.place_robot(key, x_m, y_m, heading_deg)
    return engine, host
