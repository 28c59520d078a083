"""Agents as the runner and the match runner build them: the soccer player (default) or an idle body.

Why a separate module: ``agent.agent.Agent`` is the pure protocol/world-model core and knows no skills;
this is where a behaviour is chosen for it by name (``python -m agent --behavior NAME``).
"""

from __future__ import annotations

from collections.abc import Callable

from agent.agent import Agent, AgentConfig
from agent.errors import ConfigError


def soccer_agent(config: AgentConfig) -> Agent:
    """An agent that plays soccer with the shipped motions (``agent.team.soccer_behavior``)."""
    from agent.team.soccer_behavior import SoccerBehavior

    return Agent(config, SoccerBehavior(config.robot_type))


def baseline_agent(config: AgentConfig) -> Agent:
    """The baseline opponent, the seed without coordination: the nearest player lines up and kicks toward the
    goal (``agent.team.baseline``)."""
    from agent.team.baseline import BaselineBehavior

    return Agent(config, BaselineBehavior(config.robot_type))


def solo_agent(config: AgentConfig) -> Agent:
    """Our on-ball play without coordination: the nearest player dribbles toward the goal
    (``agent.team.baseline``)."""
    from agent.team.baseline import SoloBehavior

    return Agent(config, SoloBehavior(config.robot_type))


def idle_agent(config: AgentConfig) -> Agent:
    """An agent that connects, beams, localizes and talks, but sends no joint commands."""
    return Agent(config)


BEHAVIORS: dict[str, Callable[[AgentConfig], Agent]] = {"soccer": soccer_agent, "baseline": baseline_agent,
                                                      "solo": solo_agent, "idle": idle_agent}
DEFAULT_BEHAVIOR = "soccer"


def agent_factory(behavior: str) -> Callable[[AgentConfig], Agent]:
    """The agent builder for a behaviour name.

    Raises:
        ConfigError: unknown name (the message lists the known ones).
    """
    try:
        return BEHAVIORS[behavior]
    except KeyError:
        raise ConfigError(f"unknown behavior {behavior!r}; known: {', '.join(BEHAVIORS)}", "behavior") from None


__all__ = ["BEHAVIORS", "DEFAULT_BEHAVIOR", "agent_factory", "baseline_agent", "idle_agent", "soccer_agent", "solo_agent"]
