"""The agent room's exceptions: bad configuration, a message that cannot be said, a server that never answers."""

from __future__ import annotations

from kinematics.errors import ToolkitError


class AgentError(ToolkitError):
    """Base of the agent room's errors (the wire-level :class:`agent.protocol.errors.ProtocolError` is separate).

    Args:
        message: what is wrong, with the expected and the actual value.
        field: the argument, option or message field that was wrong, when there is one.
    """

    def __init__(self, message: str, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field


class ConfigError(AgentError, ValueError):
    """An agent setting out of range (unum, robot type, team name, formation table)."""


class MessageError(AgentError, ValueError):
    """A team message that cannot be encoded (value out of range, too long) or decoded (garbage, bad check)."""


class ServerUnreachable(AgentError, ConnectionError):
    """No server answered at host:port after every retry.

    Args:
        message: what was tried.
        attempts: connection attempts made.
    """

    def __init__(self, message: str, attempts: int) -> None:
        super().__init__(message, field="host")
        self.attempts = attempts
