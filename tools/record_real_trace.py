"""Record a scripted agent session against a running rcssserver3d (ours or the real 0.7.3) as a JSONL trace.

Used to calibrate our simulator against the real server (joint response under load, foot forces, falls);
the traces are data fixtures, recorded by hand, never in CI. Format as ../shared/samples: one JSON object
per line, {"k": "send"|"recv", "a": "A", "i": I, "msg": TEXT}, gzip-compressed when the path ends in .gz.

    ../shared/real-server/netns.sh bash -c '../shared/real-server/server.sh & sleep 3; \
        python tools/record_real_trace.py crouch tests/sim/fixtures/real_0.7.3_crouch.jsonl.gz'
"""

from __future__ import annotations

import argparse
import gzip
import json
import socket
import time
from collections.abc import Callable
from pathlib import Path

from agent.protocol import read_frame, write_frame

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


def record(scenario: str, out: Path, cycles: int, host: str, port: int) -> None:
    script = SCENARIOS[scenario]
    lines: list[dict] = []
    deadline = time.monotonic() + 20
    while True:
        try:
            sock = socket.create_connection((host, port), timeout=5)
            break
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.3)

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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", choices=sorted(SCENARIOS))
    parser.add_argument("out", type=Path)
    parser.add_argument("--cycles", type=int, default=250)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=3100)
    args = parser.parse_args()
    record(args.scenario, args.out, args.cycles, args.host, args.port)


if __name__ == "__main__":
    main()
