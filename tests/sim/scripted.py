"""Helpers for the sim tests: a scripted in-process agent and small engine set-ups."""

from __future__ import annotations

import re

from agent.protocol.sense import parse_sense
from sim.engine import FrozenReferee, SimEngine
from sim.inprocess import InProcessHost
from sim.vision import VisionConfig

SCENE = b"(scene rsg/agent/nao/nao_hetero.rsg 0)"


class Scripted:
    """Sends ``scene`` on connect, then ``replies[i]`` in answer to sense message i (default ``(syn)``)."""

    def __init__(self, replies: dict[int, bytes] | None = None, scene: bytes = SCENE) -> None:
        self.replies = replies or {}
        self.scene = scene
        self.received: list[bytes] = []

    def connect_message(self) -> bytes:
        return self.scene

    def step(self, sense: bytes) -> bytes:
        self.received.append(sense)
        return self.replies.get(len(self.received) - 1, b"(syn)")

    def sense(self, index: int):  # noqa: ANN201 - agent.protocol.Sense
        return parse_sense(self.received[index])


def engine(seed: int = 0, noise: bool = False, referee: object | None = None) -> SimEngine:
    """An engine with the frozen referee (BeforeKickOff forever) and, by default, noise-free vision."""
    vision = VisionConfig(noise=noise, calibration=noise)
    return SimEngine(seed=seed, referee=referee or FrozenReferee(), vision=vision)


def run_until(host: InProcessHost, agent: Scripted, messages: int, limit: int = 2000) -> None:
    """Step until ``agent`` has received ``messages`` sense messages."""
    for _ in range(limit):
        if len(agent.received) >= messages:
            return
        host.run(1)
    raise AssertionError(f"agent got only {len(agent.received)} messages")


def predicate_names(message: bytes) -> list[str]:
    """Top-level predicate heads in wire order, HJ/FRP with their sensor name (``HJ hj1``, ``FRP rf``)."""
    text = message.decode()
    names, depth, start = [], 0, 0
    for i, char in enumerate(text):
        if char == "(":
            if depth == 0:
                start = i
            depth += 1
        elif char == ")":
            depth -= 1
            if depth == 0:
                item = text[start:i + 1]
                head = re.match(r"\((\w+)", item).group(1)  # type: ignore[union-attr]
                name = re.match(r"\(\w+ \(n (\w+)\)", item)
                names.append(f"{head} {name.group(1)}" if head in ("HJ", "FRP") and name else head)
    return names
