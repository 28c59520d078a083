"""The calibration room's error: a trace or parameter file that cannot be used, with file and line."""

from __future__ import annotations

from pathlib import Path

from kinematics.errors import ToolkitError


class CalibrationError(ToolkitError, ValueError):
    """A bad trace or calibration input; ``path`` and ``line`` (1-based, 0 = the whole file) say where."""

    def __init__(self, path: Path | str, line: int, message: str) -> None:
        self.path, self.line = Path(path), line
        where = f"{self.path}:{line}" if line else str(self.path)
        super().__init__(f"{where}: {message}")
