"""The real-server room's errors: a server that cannot be found or run, a fixture that cannot be read."""

from __future__ import annotations

from pathlib import Path

from kinematics.errors import ToolkitError


class RealServerError(ToolkitError):
    """The real rcssserver3d or its scripts are missing, or a session with it failed."""


class FixtureError(RealServerError, ValueError):
    """A recorded real-server session that cannot be used.

    Args:
        path: the fixture file.
        line: 1-based line of the problem; 0 = the file as a whole (missing, or a line it lacks).
        message: what is wrong.
    """

    def __init__(self, path: Path | str, line: int, message: str) -> None:
        self.path, self.line = Path(path), line
        where = f"{self.path}:{line}" if line else str(self.path)
        super().__init__(f"{where}: {message}")
