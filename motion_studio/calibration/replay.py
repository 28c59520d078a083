"""A recorded real session replayed open loop on our simulator: the same bytes sent at the same cycles.

The agent is scripted (it answers sense message i with what the real agent sent); the trainer commands of a
skill trace go out with the answer to message ``move_cycle``, as the recording tool sent them on the monitor
port. Our poses are read where the real truth was: the state that message i reports.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from agent.protocol.perceptors import Sense
from agent.protocol.sense import parse_sense
from motion_studio.calibration.traces import Pose, Trace
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from sim.physics_params import PhysicsParams
from sim.rules.trainer import apply_trainer_message


class ScriptedAgent:
    """Sends the scene on connect, then ``replies[i]`` in answer to sense message i (``(syn)`` if none)."""

    def __init__(self, replies: dict[int, bytes], scene: bytes) -> None:
        self.replies = replies
        self.scene = scene
        self.received: list[bytes] = []

    def connect_message(self) -> bytes:
        return self.scene

    def step(self, sense: bytes) -> bytes:
        self.received.append(sense)
        return self.replies.get(len(self.received) - 1, b"(syn)")


@dataclass
class Replay:
    """Both sides of one trace: the real truth and sense messages, ours by the same cycle index."""

    trace: Trace
    ours: dict[int, Pose]
    our_messages: list[bytes]
    blow_ups: int = 0
    _parsed: dict[tuple[str, int], Sense] = field(default_factory=dict, repr=False)

    @property
    def real(self) -> dict[int, Pose]:
        return self.trace.truth

    def sense(self, side: str, index: int) -> Sense:
        """Sense message ``index`` of ``side`` ("real" or "ours"), parsed once."""
        key = (side, index)
        if key not in self._parsed:
            messages = self.trace.received if side == "real" else self.our_messages
            self._parsed[key] = parse_sense(messages[index])
        return self._parsed[key]


def replay_trace(trace: Trace, physics: PhysicsParams | None = None, seed: int = 0) -> Replay:
    """Replay ``trace`` on a fresh engine (the full referee, as the real server) with ``physics``."""
    agent = ScriptedAgent({i: m for i, m in trace.replies.items() if i >= 0}, trace.scene)
    engine = SimEngine(seed=seed, physics=physics)
    host = InProcessHost(engine)
    key = host.add(agent)
    world = engine.world
    ours: dict[int, Pose] = {}
    move_cycle = trace.meta.get("move_cycle")
    wanted = len(trace.received)
    for _ in range(4 * wanted + 100):
        if len(agent.received) >= wanted:
            break
        count = len(agent.received)
        host.run(1)
        if len(agent.received) == count or key not in world.by_key:
            continue
        index = len(agent.received) - 1
        # The engine delivers the message made at the end of the previous step, then steps: the world now
        # holds the state message index + 1 will report (the real truth of cycle i is the state of message i).
        rotation = world.torso_rotation(key)
        ours[index + 1] = Pose(tuple(world.torso_position(key).tolist()), float(rotation[2, 2]),
                               world.heading_deg(key), world.ball_position())
        if index == move_cycle:
            for command in trace.meta["trainer"]:
                apply_trainer_message(command, engine.referee, world)
    return Replay(trace, ours, agent.received, world.divergences)
