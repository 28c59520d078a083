"""The tuning room's error: a bad problem, parameter, checkpoint or objective, with what and where."""

from __future__ import annotations

from kinematics.errors import ToolkitError


class TuningError(ToolkitError, ValueError):
    """A tuning input that cannot be used; the message is one line naming the parameter, file or candidate."""
