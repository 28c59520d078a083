"""The agents `motion-studio match` fields: our soccer agent, built by a module-level (picklable) factory."""

from __future__ import annotations

from agent.agent import Agent, AgentConfig


def make_agent(team: str, unum: int, robot_type: int) -> Agent:
    """Our agent with its default behaviour for (team, unum, robot type)."""
    return Agent(AgentConfig(team=team, unum=unum, robot_type=robot_type))
