"""Exceptions of the sim room, under the toolkit's base, each saying which agent or which cycle.

They stay ValueErrors (and the unknown robot a KeyError) so callers that caught those keep working; the
servers catch them at the edge, log them with the agent and go on (DESIGN.md: servers survive bad input).
"""

from __future__ import annotations

from kinematics.errors import ToolkitError


class SimError(ToolkitError, ValueError):
    """A request the simulated world, its referee or its files cannot carry out.

    Args:
        message: what is wrong, with the expected and the actual value.
        agent: the agent (world key) it concerns, if any; cycle: the server cycle it happened at, if known.
    """

    def __init__(self, message: str, *, agent: int | None = None, cycle: int | None = None) -> None:
        self.agent = agent
        self.cycle = cycle
        where = [f"agent {agent}" if agent is not None else "", f"cycle {cycle}" if cycle is not None else ""]
        prefix = ", ".join(part for part in where if part)
        super().__init__(f"{prefix}: {message}" if prefix else message)


class WorldError(SimError):
    """A robot that cannot be added (key taken, world full) or a world request that makes no sense."""


class UnknownRobotError(SimError, KeyError):
    """No robot with that side and uniform number."""

    def __str__(self) -> str:  # KeyError would quote the message
        return self.args[0]


class RuleError(SimError):
    """A referee request with an unknown play mode or side (trainer commands, tests)."""


class TrainerCommandError(SimError):
    """A trainer command on the monitor port that does not parse (logged and skipped by the server)."""


class PhysicsFileError(SimError):
    """A physics parameter file that is missing, not TOML, or names an unknown parameter."""


class MonitorLogError(SimError):
    """A monitor log that cannot be written as asked or replayed (no full state)."""
