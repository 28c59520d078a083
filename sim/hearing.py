"""Say/hear (REFERENCE §3.8): who hears which message, with SimSpark's per-listener capacity.

Rules: a message reaches every robot within 50 m of the speaker's torso; the speaker always hears its own
message as ``self``; each listener has two channels (own team, other team) with capacity max 2, +1 per
cycle, -2 per accepted message, so at most one message per team every two cycles; within a cycle the first
speaker (connection order) wins and the rest are lost. The direction is the atan2 of the listener->speaker
offset in the listener's team frame (point-reflected for the right team), not relative to the head.
Message text is checked by `agent.protocol.Say` when parsed (length, characters).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.protocol.perceptors import Hear

HEAR_RANGE_M = 50.0
CHANNEL_CAPACITY = 2
CAPACITY_PER_MESSAGE = 2


@dataclass(frozen=True)
class Speaker:
    """A say this cycle: who (key), their team name and side, torso position (world), the text."""

    key: int
    team: str
    side: str
    position_m: tuple[float, float, float]
    message: str


@dataclass(frozen=True)
class Listener:
    """A robot that can hear: key, team name and side ("left"/"right"), torso position (world)."""

    key: int
    team: str
    side: str
    position_m: tuple[float, float, float]


class Hearing:
    """Channel capacities of every listener, and the delivery of one cycle's says."""

    def __init__(self) -> None:
        self._capacity: dict[tuple[int, bool], int] = {}
        self._full: frozenset[int] = frozenset()   # listeners whose channels are all at capacity

    def forget(self, key: int) -> None:
        """Drop a listener's channels (disconnect)."""
        self._capacity.pop((key, True), None)
        self._capacity.pop((key, False), None)
        self._full = self._full - {key}

    def refill(self, keys: list[int]) -> None:
        """The per-cycle +1 of every listener's two channels (capped at 2); `deliver` does it itself.

        Quiet cycles (no says) call it for every robot: once all channels are full it changes nothing.
        """
        if self._full.issuperset(keys):
            return
        capacity = self._capacity
        for key in keys:
            for channel in ((key, True), (key, False)):
                capacity[channel] = min(CHANNEL_CAPACITY, capacity.get(channel, CHANNEL_CAPACITY - 1) + 1)
        self._full = frozenset(key for key in keys
                               if capacity[(key, True)] == capacity[(key, False)] == CHANNEL_CAPACITY)

    def deliver(self, speakers: list[Speaker], listeners: list[Listener],
                game_time_s: float) -> dict[int, list[Hear]]:
        """One cycle: refill every channel by one, then hand out the says in speaker order.

        Returns:
            listener key -> the hears of this cycle, own message first, then own team, then the other.
        """
        self.refill([listener.key for listener in listeners])
        heard: dict[int, list[tuple[int, Hear]]] = {}
        for speaker in speakers:
            for listener in listeners:
                if listener.key == speaker.key:
                    heard.setdefault(listener.key, []).append(
                        (0, Hear(speaker.team, game_time_s, None, speaker.message)))
                    continue
                dx = speaker.position_m[0] - listener.position_m[0]
                dy = speaker.position_m[1] - listener.position_m[1]
                dz = speaker.position_m[2] - listener.position_m[2]
                if dx * dx + dy * dy + dz * dz > HEAR_RANGE_M * HEAR_RANGE_M:
                    continue
                same_team = speaker.side == listener.side
                channel = (listener.key, same_team)
                if self._capacity.get(channel, 0) < CAPACITY_PER_MESSAGE:
                    continue
                self._capacity[channel] -= CAPACITY_PER_MESSAGE
                self._full = self._full - {listener.key}
                if listener.side == "right":   # the right team's frame is the world point-reflected
                    dx, dy = -dx, -dy
                direction = math.degrees(math.atan2(dy, dx))
                heard.setdefault(listener.key, []).append(
                    (1 if same_team else 2, Hear(speaker.team, game_time_s, direction, speaker.message)))
        return {key: [hear for _, hear in sorted(items, key=lambda item: item[0])] for key, items in heard.items()}
