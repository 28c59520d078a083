"""The agents `motion-studio match` fields: our soccer agent, built by a module-level (picklable) factory."""

from __future__ import annotations

from agent.agent import Agent, AgentConfig
from agent.player import idle_agent, soccer_agent


def make_agent(team: str, unum: int, robot_type: int) -> Agent:
    """Our soccer agent (``agent.team.soccer_behavior``) for (team, unum, robot type)."""
    return soccer_agent(AgentConfig(team=team, unum=unum, robot_type=robot_type))


def make_idle_agent(team: str, unum: int, robot_type: int) -> Agent:
    """An agent that connects, beams, localizes and talks but never moves (runner plumbing, baselines)."""
    return idle_agent(AgentConfig(team=team, unum=unum, robot_type=robot_type))
