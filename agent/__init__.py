"""agent: the soccer agent; runs without MuJoCo, against our server or the real rcssserver3d.

The core is :class:`Agent` (``step(sense: bytes) -> bytes``, pure); :mod:`agent.runner` is the TCP
transport (``python -m agent``); :class:`WorldModel` holds the beliefs.

The names are loaded on first use, so ``import agent.protocol`` (which sim/ does) does not pull in the
world model and its kinematics (Pinocchio).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from agent.agent import Agent, AgentConfig, Behavior
    from agent.world_model import WorldModel

_EXPORTS = {"Agent": "agent.agent", "AgentConfig": "agent.agent", "Behavior": "agent.agent",
            "WorldModel": "agent.world_model"}

__all__ = ["Agent", "AgentConfig", "Behavior", "WorldModel"]


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'agent' has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(module), name)
