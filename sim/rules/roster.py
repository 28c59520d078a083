"""Who plays: team names to sides, uniform numbers, robot-type composition and init spots (REFERENCE §3.2,
§2.5), as rcssserver3d's GameStateAspect hands them out at ``init``."""

from __future__ import annotations

import logging
from collections import Counter
from dataclasses import dataclass

from sim.rules.params import LEFT, RIGHT, SIDES, RefereeConfig

logger = logging.getLogger(__name__)

# REFERENCE §2.5: team composition, checked at init.
MAX_PLAYERS = 11
MAX_ROBOTS_OF_TYPE = 7
MIN_ROBOT_TYPES = 3
MAX_SUM_TWO_TYPES = 9


@dataclass(frozen=True)
class Assignment:
    """The result of a successful ``init``: side ("left"/"right"), uniform number and the init spot
    (torso x, y, z [m] in the field frame, heading [deg], 0 = facing +x)."""

    side: str
    unum: int
    position_m: tuple[float, float, float]
    heading_deg: float


class Roster:
    """Team names, numbers and robot types in use; the first team name seen plays left, the second right.

    Args:
        config: field size and AgentRadius (the init spots: (-+14.2, 9.2), then 1.2 m lower each).
    """

    def __init__(self, config: RefereeConfig) -> None:
        self.config = config
        self.team_names: dict[str, str | None] = {LEFT: None, RIGHT: None}
        self.unums: dict[str, set[int]] = {LEFT: set(), RIGHT: set()}
        self.robot_types: dict[str, Counter[int]] = {LEFT: Counter(), RIGHT: Counter()}
        half_l, half_w, radius = config.half_length_m, config.half_width_m, config.agent_radius_m
        self._init_spot = {LEFT: [-half_l + 2 * radius, half_w - 2 * radius],
                           RIGHT: [half_l - 2 * radius, half_w - 2 * radius]}

    def assign(self, team: str, unum: int, robot_type: int = 0) -> Assignment | None:
        """Hand out a uniform; None when the team, number or robot type is refused (logged)."""
        side = self._side_of(team)
        if side is None:
            logger.warning("init refused: a third team name %r (teams: %s)", team, self.team_names)
            return None
        if unum == 0:
            unum = next((n for n in range(1, MAX_PLAYERS + 1) if n not in self.unums[side]), 0)
        if not 1 <= unum <= MAX_PLAYERS or unum in self.unums[side]:
            logger.warning("init refused: uniform number %s of team %r is taken or out of 1-11", unum, team)
            return None
        if not self._robot_type_allowed(side, robot_type):
            logger.warning("init refused: robot type %s would break the team composition of %r", robot_type, team)
            return None
        self.unums[side].add(unum)
        self.robot_types[side][robot_type] += 1
        c = self.config
        spot = self._init_spot[side]
        position = (spot[0], spot[1], c.agent_radius_m)
        spot[1] -= 3 * c.agent_radius_m
        if spot[1] < -c.half_width_m:  # the server then starts a new column 0.8 m further in +x
            spot[1] = c.half_width_m - 2 * c.agent_radius_m
            spot[0] += 2 * c.agent_radius_m
        return Assignment(side, unum, position, 0.0 if side == LEFT else 180.0)

    def release(self, side: str, unum: int, robot_type: int = 0) -> None:
        """Return a uniform when its agent disconnects."""
        self.unums[side].discard(unum)
        if self.robot_types[side][robot_type] > 0:
            self.robot_types[side][robot_type] -= 1

    def _side_of(self, team: str) -> str | None:
        for side in SIDES:
            if self.team_names[side] is None:
                self.team_names[side] = team
                return side
            if self.team_names[side] == team:
                return side
        return None

    def _robot_type_allowed(self, side: str, robot_type: int) -> bool:
        counts = self.robot_types[side]
        if counts[robot_type] >= MAX_ROBOTS_OF_TYPE:
            return False
        others = [n for t, n in counts.items() if t != robot_type and n > 0]
        if counts[robot_type] + 1 + max(others, default=0) > MAX_SUM_TWO_TYPES:
            return False
        players = sum(counts.values())
        types_used = sum(1 for n in counts.values() if n > 0)
        return not (MAX_PLAYERS - players <= MIN_ROBOT_TYPES - types_used and counts[robot_type] != 0)
