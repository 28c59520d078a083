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
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

from agent.protocol import (
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


def measure(cases: dict[str, tuple[Callable[[], object], int]], batches: int) -> dict[str, dict[str, float]]:
    """Median, p90 and min of the per-call time [us] of each case, over ``batches`` timed batches.

    Args:
        cases: name -> (call, calls per batch).
        batches: timed batches per case. The cases take turns batch by batch, so a burst of load from
            other processes on the machine spreads over all of them instead of spoiling one.
    """
    for call, per_batch in cases.values():  # warm caches and the regex engine
        for _ in range(per_batch * 5):
            call()
    per_call_us: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(batches):
        for name, (call, per_batch) in cases.items():
            start = time.perf_counter_ns()
            for _ in range(per_batch):
                call()
            per_call_us[name].append((time.perf_counter_ns() - start) / per_batch / 1000.0)
    results = {}
    for name, samples in per_call_us.items():
        samples.sort()
        results[name] = {
            "median_us": round(statistics.median(samples), 2),
            "p90_us": round(samples[int(0.9 * (len(samples) - 1))], 2),
            "min_us": round(samples[0], 2),
        }
    return results


def run(batches: int) -> dict[str, object]:
    """Every benchmark case; returns the results keyed by case name."""
    vision, plain, action = sample_messages()
    vision_sense = parse_sense(vision)
    actions = parse_actions(action)
    stream = b"".join(frame(m) for m in (vision, plain) * 10)
    cases: dict[str, tuple[Callable[[], object], int]] = {
        "parse_sense_vision": (lambda: parse_sense(vision), 20),
        "parse_sense_vision_general_path": (lambda: parse_sense(vision, fast_path=False), 3),
        "format_sense_vision": (lambda: format_sense(vision_sense), 20),
        "parse_sense_no_vision": (lambda: parse_sense(plain), 20),
        "parse_actions_22_joints": (lambda: parse_actions(action), 20),
        "format_actions_22_joints": (lambda: format_actions(actions), 20),  # type: ignore[arg-type]
        "decode_20_frames": (lambda: FrameDecoder().feed(stream), 20),
    }
    results: dict[str, object] = dict(measure(cases, batches))
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
