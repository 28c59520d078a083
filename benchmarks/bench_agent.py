"""Think time of the agent: ``Agent.step`` per cycle on recorded sense messages (figures, never assertions).

Run: ``python benchmarks/bench_agent.py [--json] [--repeats N]``. Feeds every recorded message of each trace
to fresh agents in order (so init, beam, localization and say run as in a game) and times each call.
Traces: the real 0.7.3 two-agent sample (tests/agent/fixtures), our server's trace when present
(tests/agent/fixtures/oursim_*.jsonl), and a crowd made now on our server (sim.inprocess, 11 v 11 agents
beamed to their formation spots, 200 cycles; the messages of Home #9, who sees about 12 robots and 4 kB
per vision message; ``--no-crowd`` skips it). Prints median, p90, p99 and max microseconds per step, all
cycles and vision cycles only. Goal: median <= 1 ms, p99 <= 2 ms (issue 15 item 6).
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

from agent import Agent, AgentConfig

FIXTURES = ROOT / "tests" / "agent" / "fixtures"
GOALS_US = {"median": 1000.0, "p99": 2000.0}


def traces() -> dict[str, tuple[str, list[bytes]]]:
    """Trace name -> (own team name, sense messages of one agent in order)."""
    out: dict[str, tuple[str, list[bytes]]] = {}
    real = FIXTURES / "rcssserver3d-0.7.3_two_agents.jsonl"
    records = [json.loads(line) for line in real.read_text().splitlines()]
    out["real-0.7.3"] = ("CapL", [r["msg"].encode() for r in records if r["k"] == "recv" and r["a"] == "L"])
    for path in sorted(FIXTURES.glob("oursim_*.jsonl")):
        rows = [json.loads(line) for line in path.read_text().splitlines()]
        header = rows[0]
        out[path.stem] = (header.get("team", "Ours"), [r["msg"].encode() for r in rows[1:] if "msg" in r])
    return out


def crowd_trace(cycles: int = 200) -> tuple[str, list[bytes]]:
    """Home #9's sense messages in an 11 v 11 game on our server (in-process, no rules, formation beams)."""
    from sim.engine import FrozenReferee, SimEngine
    from sim.inprocess import InProcessHost

    host = InProcessHost(SimEngine(seed=4, referee=FrozenReferee()), record=True)
    ids = {}
    for team in ("Home", "Away"):
        for unum in range(1, 12):
            ids[(team, unum)] = host.add(Agent(AgentConfig(team, unum)))
            host.run(3)  # one after another: robots built in the same cycle collide
    host.run(cycles)
    target = ids[("Home", 9)]
    return "Home", [message for _, agent_id, message in host.stats.transcript if agent_id == target]


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q / 100.0 * (len(ordered) - 1))))]


def measure(team: str, messages: list[bytes], repeats: int, unum: int = 1) -> dict[str, float]:
    all_us: list[float] = []
    vision_us: list[float] = []
    for _ in range(repeats):
        agent = Agent(AgentConfig(team, unum))
        for message in messages:
            start = time.perf_counter_ns()
            agent.step(message)
            elapsed = (time.perf_counter_ns() - start) / 1000.0
            all_us.append(elapsed)
            if b"(See" in message:
                vision_us.append(elapsed)
    return {
        "cycles": len(all_us),
        "median_us": statistics.median(all_us),
        "p90_us": percentile(all_us, 90),
        "p99_us": percentile(all_us, 99),
        "max_us": max(all_us),
        "vision_median_us": statistics.median(vision_us) if vision_us else float("nan"),
        "vision_p99_us": percentile(vision_us, 99) if vision_us else float("nan"),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--repeats", type=int, default=5, help="passes over each trace (fresh agents)")
    parser.add_argument("--no-crowd", action="store_true", help="skip the 11 v 11 trace made on our server")
    args = parser.parse_args()
    Agent(AgentConfig("Warmup", 1))  # import and build the kinematics model before timing
    all_traces = traces()
    if not args.no_crowd:
        all_traces["oursim-11v11-crowd"] = crowd_trace()
    results = {name: measure(team, messages, args.repeats) for name, (team, messages) in all_traces.items()}
    if args.json:
        print(json.dumps({"python": platform.python_version(), "goals_us": GOALS_US, "traces": results}))
        return
    print(f"Agent.step think time (python {platform.python_version()}; goals: median <= {GOALS_US['median']:.0f} us,"
          f" p99 <= {GOALS_US['p99']:.0f} us)")
    for name, r in results.items():
        print(f"  {name:<24} {r['cycles']:>6} cycles  median {r['median_us']:7.1f} us  p90 {r['p90_us']:7.1f}"
              f"  p99 {r['p99_us']:7.1f}  max {r['max_us']:8.1f}  |  vision cycles: median"
              f" {r['vision_median_us']:7.1f}  p99 {r['vision_p99_us']:7.1f}")


if __name__ == "__main__":
    main()
