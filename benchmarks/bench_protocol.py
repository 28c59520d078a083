"""Benchmark of the wire protocol's per-cycle work: parse and format a real 0.7.3 sense message.

Run: ``python benchmarks/bench_protocol.py [--json] [--batches N]``. Prints median and p90 microseconds per
call. The vision message is the median-length one among the sample messages that see the other robot
(flags, goal posts, ball, two players, ~17 lines, 22 joints, both feet: ~2 kB). Target: parse_sense of it
at a median <= 100 us. Timing is per batch of calls (the timer's own cost stays out), batches repeated.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # runnable as a plain script from any directory
    sys.path.insert(0, str(ROOT))

from agent.protocol import (  # noqa: E402
    FrameDecoder,
    format_actions,
    format_sense,
    frame,
    parse_actions,
    parse_sense,
)

SAMPLE = ROOT / "tests" / "agent" / "fixtures" / "rcssserver3d-0.7.3_two_agents.jsonl"


def sample_messages() -> tuple[bytes, bytes, bytes]:
    """(typical vision message, typical non-vision message, typical action message) from the sample."""
    records = [json.loads(line) for line in SAMPLE.read_text(encoding="ascii").splitlines()]
    received = [r["msg"].encode("ascii") for r in records if r["k"] == "recv"]
    with_players = sorted((m for m in received if b"(P (team" in m), key=len)
    without_vision = sorted((m for m in received if b"(See" not in m), key=len)
    action = b"".join(f"({e} {0.1 * i - 1:.4g})".encode() for i, e in enumerate(_EFFECTORS)) + b"(syn)"
    return with_players[len(with_players) // 2], without_vision[len(without_vision) // 2], action


_EFFECTORS = ["he1", "he2"] + [f"{side}ae{i}" for side in "lr" for i in range(1, 5)] + [
    f"{side}le{i}" for side in "lr" for i in range(1, 7)
]


def measure(call: Callable[[], object], batches: int, per_batch: int) -> dict[str, float]:
    """Median and p90 of the per-call time [us] over ``batches`` batches of ``per_batch`` calls."""
    for _ in range(per_batch * 5):  # warm caches and the regex engine
        call()
    per_call_us = []
    for _ in range(batches):
        start = time.perf_counter_ns()
        for _ in range(per_batch):
            call()
        per_call_us.append((time.perf_counter_ns() - start) / per_batch / 1000.0)
    per_call_us.sort()
    return {
        "median_us": round(statistics.median(per_call_us), 2),
        "p90_us": round(per_call_us[int(0.9 * (len(per_call_us) - 1))], 2),
        "min_us": round(per_call_us[0], 2),
    }


def run(batches: int) -> dict[str, object]:
    """Every benchmark case; returns the results keyed by case name."""
    vision, plain, action = sample_messages()
    vision_sense = parse_sense(vision)
    actions = parse_actions(action)
    stream = b"".join(frame(m) for m in (vision, plain) * 10)
    cases: dict[str, Callable[[], object]] = {
        "parse_sense_vision": lambda: parse_sense(vision),
        "parse_sense_vision_general_path": lambda: parse_sense(vision, fast_path=False),
        "format_sense_vision": lambda: format_sense(vision_sense),
        "parse_sense_no_vision": lambda: parse_sense(plain),
        "parse_actions_22_joints": lambda: parse_actions(action),
        "format_actions_22_joints": lambda: format_actions(actions),  # type: ignore[arg-type]
        "decode_20_frames": lambda: FrameDecoder().feed(stream),
    }
    results: dict[str, object] = {
        name: measure(call, batches, per_batch=5 if "general" in name else 20) for name, call in cases.items()
    }
    results["message_bytes"] = {"vision": len(vision), "no_vision": len(plain), "actions": len(action)}
    results["python"] = platform.python_version()
    results["machine"] = platform.machine()
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--batches", type=int, default=200, help="timed batches per case")
    args = parser.parse_args()
    results = run(args.batches)
    if args.json:
        print(json.dumps(results, indent=2))
        return
    for name, value in results.items():
        if isinstance(value, dict) and "median_us" in value:
            print(f"{name:34s} median {value['median_us']:8.1f} us   p90 {value['p90_us']:8.1f} us")
        else:
            print(f"{name:34s} {value}")


if __name__ == "__main__":
    main()
