"""The editor's exception: a request the editing session cannot carry out, naming the field that is wrong."""

from __future__ import annotations

from kinematics.errors import ToolkitError


class EditorError(ToolkitError, ValueError):
    """An edit, selection or file request that cannot be done (bad index, joint, value, name or path).

    Args:
        message: what is wrong, with the expected and the actual value.
        field: the request field that was wrong (``"index"``, ``"joint"``, ``"duration_ms"``, ``"path"``...).
    """

    def __init__(self, message: str, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field
