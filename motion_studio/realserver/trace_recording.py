"""A scripted agent session against a running rcssserver3d (ours or the real 0.7.3) recorded as a JSONL trace
(``motion-studio real trace``).

Used to calibrate our simulator against the real server (joint response under load, foot forces, falls); the
traces are data fixtures, recorded by hand, never in CI. Format as ../shared/samples: one JSON object per line,
{"k": "send"|"recv", "a": "A", "i": I, "msg": TEXT}, gzip-compressed when the path ends in .gz.
"""

from __future__ import annotations

import gzip
import json
from collections.abc import Callable
from pathlib import Path

from agent.protocol import read_frame, write_frame
from motion_studio.realserver.process import connect

LEGS = ("lle3", "lle4", "lle5", "rle3", "rle4", "rle5")


def _joints(**velocities: float) -> str:
    return "".join(f"({name} {value:.4f})" for name, value in velocities.items())


def stand(cycle: int) -> str:
    """Nothing commanded: the robot stands at zero pose (all joint velocities stay 0)."""
    return ""


def crouch(cycle: int) -> str:
    """Hips +2, knees -4, ankles +2 rad/s for cycles 20-34 (a 34 deg / 69 deg crouch), then hold."""
    if cycle == 20:
        return _joints(lle3=2.0, lle4=-4.0, lle5=2.0, rle3=2.0, rle4=-4.0, rle5=2.0, he1=1.0)
    if cycle == 35:
        return _joints(**{name: 0.0 for name in LEGS}, he1=0.0)
    return ""


def fall(cycle: int) -> str:
    """Both hips flex at 3 rad/s from cycle 20: the torso pitches forward and the robot falls."""
    if cycle == 20:
        return _joints(lle3=3.0, rle3=3.0)
    return ""


SCENARIOS: dict[str, Callable[[int], str]] = {"stand": stand, "crouch": crouch, "fall": fall}


def record(scenario: str, out: Path, cycles: int = 250, host: str = "127.0.0.1", port: int = 3100) -> Path:
    """Connect to the server on ``host``:``port``, play ``scenario`` for ``cycles`` cycles (scene, init at
    cycle 0, beam to (-5, 0) at cycle 2) and write the trace to ``out``; returns ``out``."""
    script = SCENARIOS[scenario]
    lines: list[dict] = []
    sock = connect(port, host=host)

    def send(i: int, text: str) -> None:
        lines.append({"k": "send", "a": "A", "i": i, "msg": text})
        write_frame(sock, text.encode())

    send(-1, "(scene rsg/agent/nao/nao.rsg)")
    for i in range(cycles):
        message = read_frame(sock).decode()
        lines.append({"k": "recv", "a": "A", "i": i, "msg": message})
        if i == 0:
            send(i, "(init (unum 1)(teamname Calib))(syn)")
        elif i == 2:
            send(i, "(beam -5.0 0.0 0.0)(syn)")
        else:
            send(i, script(i) + "(syn)")
    sock.close()
    opener = gzip.open if out.suffix == ".gz" else open
    with opener(out, "wt") as handle:
        for line in lines:
            handle.write(json.dumps(line) + "\n")
    return out
