"""An agent for the match tests: the idle agent, raising on every 10th sense message (a user's buggy
behaviour). A module of its own so that agent worker processes import it by name."""

from motion_studio.match_agents import make_idle_agent


class CrashingAgent:
    """The idle agent, raising on every 10th sense message."""

    def __init__(self, team, unum, robot_type):
        self.inner = make_idle_agent(team, unum, robot_type)
        self.count = 0

    def connect_message(self):
        return self.inner.connect_message()

    def step(self, sense):
        self.count += 1
        if self.count % 10 == 0:
            raise RuntimeError("boom")
        return self.inner.step(sense)
