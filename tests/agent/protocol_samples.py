"""Real rcssserver3d 0.7.3 wire samples (tests/agent/fixtures), loaded once for the protocol tests."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

FIXTURES = Path(__file__).parent / "fixtures"
TWO_AGENTS = FIXTURES / "rcssserver3d-0.7.3_two_agents.jsonl"
MONITOR_FRAMES = FIXTURES / "rcssserver3d-0.7.3_monitor_first_frames.txt"


@cache
def records() -> tuple[dict[str, object], ...]:
    """Every record of the two-agent session, in file order."""
    with TWO_AGENTS.open(encoding="ascii") as stream:
        return tuple(json.loads(line) for line in stream)


def received() -> list[bytes]:
    """Every sense message the two agents received, as bytes."""
    return [str(r["msg"]).encode("ascii") for r in records() if r["k"] == "recv"]


def sent() -> list[bytes]:
    """Every action message the two agents sent, as bytes."""
    return [str(r["msg"]).encode("ascii") for r in records() if r["k"] == "send"]


def vision_message() -> bytes:
    """A typical vision message: median length among those that see the other robot (used by the bench)."""
    with_players = sorted((m for m in received() if b"(P (team" in m), key=len)
    return with_players[len(with_players) // 2]


def monitor_lines() -> list[bytes]:
    """The three monitor messages, without their newlines."""
    return [line for line in MONITOR_FRAMES.read_bytes().split(b"\n") if line]
