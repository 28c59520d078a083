"""The agents `motion-studio match` fields, per side: our soccer agent, the baseline opponent (the seed's kicks),
our on-ball play without coordination (solo), robots that only stand, or (``sim.external``) a user's command
over TCP. Factories are module-level or frozen dataclasses so that batches can pickle them into worker
processes."""

from __future__ import annotations

from dataclasses import dataclass

from agent.agent import Agent, AgentConfig
from agent.player import baseline_agent, idle_agent, soccer_agent, solo_agent

#: Built-in team kinds for ``--left`` / ``--right`` (``cmd:...`` names an external command).
TEAM_KINDS = ("ours", "baseline", "solo", "standing")
EXTERNAL_PREFIX = "cmd:"


def make_agent(team: str, unum: int, robot_type: int) -> Agent:
    """Our soccer agent (``agent.team.soccer_behavior``) for (team, unum, robot type)."""
    return soccer_agent(AgentConfig(team=team, unum=unum, robot_type=robot_type))


#: The formation of the baseline and standing teams: the seed's beam spots (as when issue 15's "3 robots that
#: only stand" were measured: goalkeeper and two defenders in front of their goal), not ours.
OPPONENT_FORMATION = "thesis"


def make_baseline_agent(team: str, unum: int, robot_type: int) -> Agent:
    """The baseline opponent (``agent.team.baseline``): the seed without coordination, the nearest player kicks
    toward the goal."""
    return baseline_agent(AgentConfig(team=team, unum=unum, robot_type=robot_type, formation=OPPONENT_FORMATION))


def make_solo_agent(team: str, unum: int, robot_type: int) -> Agent:
    """Our on-ball play without coordination (``agent.team.baseline``): the nearest player dribbles."""
    return solo_agent(AgentConfig(team=team, unum=unum, robot_type=robot_type, formation=OPPONENT_FORMATION))


def make_idle_agent(team: str, unum: int, robot_type: int) -> Agent:
    """An agent that connects, beams (the seed's spots), localizes and talks but never moves."""
    return idle_agent(AgentConfig(team=team, unum=unum, robot_type=robot_type, formation=OPPONENT_FORMATION))


_BUILDERS = {"ours": make_agent, "baseline": make_baseline_agent, "solo": make_solo_agent,
             "standing": make_idle_agent}


def check_kind(kind: str) -> str:
    """``kind`` if it names a team (``ours``, ``baseline``, ``solo``, ``standing`` or ``cmd:COMMAND``).

    Raises:
        ValueError: anything else (the message lists what is accepted).
    """
    if kind in _BUILDERS or (kind.startswith(EXTERNAL_PREFIX) and kind[len(EXTERNAL_PREFIX):].strip()):
        return kind
    raise ValueError(f"unknown team {kind!r}: expected one of {', '.join(TEAM_KINDS)} or "
                     f"'{EXTERNAL_PREFIX}COMMAND {{host}} {{port}} {{team}} {{unum}}'")


@dataclass(frozen=True)
class SideAgents:
    """An agent factory (team name, unum, robot type) -> agent that builds each side's kind of agent.

    Sides are told apart by team name (``team_left`` is the left team's), as ``sim.match.run_match`` calls
    the factory with the team name only. External commands (``cmd:``) are not built here: the match runner
    starts them as processes (``sim.external``); this factory must not be asked for them.
    """

    left: str = "ours"
    right: str = "ours"
    team_left: str = "Left"

    def __post_init__(self) -> None:
        check_kind(self.left)
        check_kind(self.right)

    def kind_of(self, team: str) -> str:
        return self.left if team == self.team_left else self.right

    def __call__(self, team: str, unum: int, robot_type: int) -> Agent:
        kind = self.kind_of(team)
        if kind not in _BUILDERS:
            raise ValueError(f"{kind!r} is an external command: the match runner starts it, not this factory")
        return _BUILDERS[kind](team, unum, robot_type)
