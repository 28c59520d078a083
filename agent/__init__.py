"""agent: the soccer agent; runs without MuJoCo, against our server or the real rcssserver3d.

The core is :class:`Agent` (``step(sense: bytes) -> bytes``, pure); :mod:`agent.runner` is the TCP
transport (``python -m agent``); :class:`WorldModel` holds the beliefs.
"""

from agent.agent import Agent, AgentConfig, Behavior
from agent.world_model import WorldModel

__all__ = ["Agent", "AgentConfig", "Behavior", "WorldModel"]
