"""Exceptions of the kinematics room, and the toolkit-wide base class every room's error derives from."""

from __future__ import annotations


class ToolkitError(Exception):
    """Base of every error the toolkit raises on bad input; catch this at the edges (CLI, servers)."""


class SpecError(ToolkitError, ValueError):
    """A request the Nao spec cannot answer: unknown robot type, joint or body name, or a bad value.

    Args:
        message: what is wrong, with the expected and the actual value.
        field: the argument or name that was wrong (e.g. ``"robot_type"``, ``"joint"``).
    """

    def __init__(self, message: str, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field


class IKError(ToolkitError):
    """A whole-body IK target that could not be met within tolerance.

    Args:
        message: human-readable reason.
        task: name of the task that failed (e.g. ``"lfoot"``).
        residual: remaining error of that task (m for positions, rad for orientations).
    """

    def __init__(self, message: str, task: str, residual: float) -> None:
        super().__init__(message)
        self.task = task
        self.residual = residual
