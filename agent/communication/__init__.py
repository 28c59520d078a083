"""agent.communication: team messages (compact code, ≤ 20 characters) and time-sliced say slots."""

from agent.communication.messages import MAX_LENGTH, TeamMessage, decode, encode
from agent.communication.slots import may_say, slot_label

__all__ = ["MAX_LENGTH", "TeamMessage", "decode", "encode", "may_say", "slot_label"]
