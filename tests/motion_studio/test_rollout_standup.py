"""The stand-up rollout backend without the real server: seeded lying starts, the figures of a stand-up phase,
whole rollouts on our simulator (the same bench and trainer resets the real server gets), the worker's JSON
protocol, and the tuner's evaluator on a stand-in pool."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from agent.motion import default_library
from motion_studio.realserver.rollout_standup import (CYCLE_S, HOLD_S, CycleRecord, RealStart, SimWorld,
                                                      StandUpBench, StandUpOutcome, TruthSample, outcome_of,
                                                      real_starts, transfer_starts)
from motion_studio.realserver.standup_backend import RealEvaluator, rollout_loss
from motion_studio.realserver.standup_pool import RolloutRequest
from motions.authoring.standup import load_standup_params
from motions.xml_phase import dumps_xml

ROOT = Path(__file__).resolve().parents[2]


def test_starts_are_seeded_and_tip_the_robot_towards_their_side():
    assert RealStart("back", 3).plan() == RealStart("back", 3).plan()
    assert RealStart("back", 3).plan() != RealStart("back", 4).plan()
    for seed in range(5):
        back, front = RealStart("back", seed).plan()["script"][0], RealStart("front", seed).plan()["script"][0]
        assert back["lle5"] < 0 and back["rle5"] < 0  # toes down: onto the back
        assert front["lle5"] > 0 and front["rle5"] > 0  # toes up: onto the front
    starts = real_starts("front", 4, seed=2, noise=True)
    assert [s.seed for s in starts] == [2000, 2001, 2002, 2003]
    assert starts[0].noise_seed is None and all(s.noise_seed is not None for s in starts[1:])


def test_transfer_starts_copy_the_lying_starts_of_motion_studio_transfer():
    from motion_studio.realserver.cases import CASES, fall_steps
    from motion_studio.realserver.transfer import vary_fall

    starts = transfer_starts("back", 10, seed=0)
    case = vary_fall(CASES["standup_front"], 5, 0)  # the transfer case that lies on its back
    plan = starts[5].plan()
    assert plan["script"] == fall_steps(case) and plan["settle_cycles"] == case.settle_cycles
    assert plan["spot_m"] == case.position_m and plan["yaw_deg"] == case.heading_deg
    assert starts[0].plan()["script"] == fall_steps(CASES["standup_front"])  # start 0: the case as shipped
    assert transfer_starts("front", 1)[0].transfer_case().name == "standup_back"
    request = RolloutRequest({}, "standup_back", starts[5], use_skill=True, world="sim")
    assert json.loads(request.to_json())["start"] == ["back", 5, None, 0]


def _sample(cycle: int, z: float, up_z: float = 1.0) -> TruthSample:
    return TruthSample(cycle * CYCLE_S, (0.0, 0.0, z), up_z, 0.0)


def test_the_time_to_stand_starts_when_the_torso_stays_up_for_a_second():
    hold = round(HOLD_S / CYCLE_S)
    heights = [0.05] * 40 + [0.32] * 10 + [0.2] * 5 + [0.33] * (hold + 20)
    samples = {100 + i: _sample(100 + i, z, 0.0 if z < 0.1 else 1.0) for i, z in enumerate(heights)}
    records = [CycleRecord((100 + i) * CYCLE_S, 46.0 if z > 0.3 else 0.0, "") for i, z in enumerate(heights)]
    outcome = outcome_of(samples, records, 99 * CYCLE_S, 2)
    assert outcome.time_s == pytest.approx((40 + 10 + 5 + 1) * CYCLE_S)  # the 0.32 m stretch was too short
    assert outcome.lying_up_z == 0.0 and outcome.self_collisions == 2
    assert outcome.best_feet_load == pytest.approx(1.0) and outcome.final_score > 0.95
    never = outcome_of({k: _sample(k, 0.1, 0.2) for k in samples}, records, 99 * CYCLE_S, 0)
    assert never.time_s is None and never.best_score < 0.5


def test_a_rollout_the_referee_interfered_with_is_void():
    from motion_studio.realserver.rollout_standup import void_reason

    lying = {i: _sample(i, 0.09, 0.0) for i in range(100, 200)}
    assert void_reason(lying, 100 * CYCLE_S) is None
    # the Incapable foul lifts the robot to z = 1 for 0.5 s, then puts it down standing
    lifted = {**lying, **{i: _sample(i, 1.0) for i in range(150, 175)}, **{i: _sample(i, 0.4) for i in range(175, 200)}}
    assert "referee" in void_reason(lifted, 100 * CYCLE_S)
    assert void_reason(lifted, 180 * CYCLE_S) is not None  # standing when the stand-up began
    assert void_reason({**lying, 90: _sample(90, 1.0)}, 100 * CYCLE_S) is None  # before the stand-up: not its business


def test_a_missing_monitor_frame_takes_the_previous_one():
    records = [CycleRecord(i * CYCLE_S, 0.0, "") for i in range(1, 80)]
    samples = {i: _sample(i, 0.34) for i in range(1, 80) if i % 7}
    assert outcome_of(samples, records, 0.0, 0).time_s == pytest.approx(CYCLE_S)


@pytest.fixture(scope="module")
def sim_bench():
    bench = StandUpBench(lambda behavior: SimWorld(behavior), default_library(0))
    yield bench
    bench.close()


@pytest.mark.parametrize("side", ["back", "front"])
def test_on_our_simulator_a_seeded_fall_ends_lying_and_the_shipped_standup_gets_up(sim_bench, side):
    library = default_library(0)
    name = f"standup_{side}"
    outcome = sim_bench.rollout({name: library.get(name)}, name, RealStart(side, 2), trace=True)
    assert abs(outcome.lying_up_z) < 0.5  # lying, not standing, when the stand-up began
    assert (outcome.lying_forward_z > 0.8) == (side == "back")  # chest up on the back, down on the front
    assert outcome.time_s is not None and outcome.time_s < 4.0
    played = [row for row in outcome.trace if "phase" in row]
    assert played and {"t", "z", "up_z", "joints"} <= set(played[0])
    assert any(row["phase"].startswith(name) for row in played)


def test_the_next_rollout_starts_from_a_trainer_reset_on_the_same_server(sim_bench):
    library = default_library(0)
    motion = library.get("standup_back")
    # start 3: the shipped stand-up gets up from it on ours (since the transfer-start tuning, not from start 5)
    first = sim_bench.rollout({"standup_back": motion}, "standup_back", RealStart("back", 3))
    again = sim_bench.rollout({"standup_back": motion}, "standup_back", RealStart("back", 3))
    assert first.time_s is not None and again.time_s is not None
    assert abs(first.lying_up_z - again.lying_up_z) < 0.1


def test_the_worker_answers_json_lines():
    library = default_library(0)
    request = RolloutRequest({"standup_front": library.get("standup_front")}, "standup_front",
                             RealStart("front", 1), world="sim")
    process = subprocess.run([sys.executable, "-m", "motion_studio.realserver.standup_pool", "--worker"],
                             input=request.to_json() + "\n" + json.dumps({"bad": 1}) + "\n", capture_output=True,
                             text=True, cwd=ROOT, timeout=120)
    answers = [json.loads(line) for line in process.stdout.splitlines()]
    assert process.returncode == 0 and len(answers) == 2
    assert answers[0]["ok"] and StandUpOutcome(**answers[0]["outcome"]).time_s is not None
    assert not answers[1]["ok"] and "KeyError" in answers[1]["error"]


class _StandInPool:
    """Answers every real rollout at once: none stands; the robot got 0.3 of its weight onto its feet."""

    def __init__(self) -> None:
        self.requests: list[RolloutRequest] = []

    def run(self, requests):
        self.requests += requests
        return [StandUpOutcome(None, 0.2, 0.5, 0.0, 0, 0.3, 0.0, 1.0) for _ in requests]


def test_the_evaluator_sends_one_batch_per_generation_and_adds_our_simulator():
    from motion_studio.tune_standup import Start, evaluate

    pool = _StandInPool()
    params = load_standup_params()["standup_back"]
    starts = real_starts("back", 3, noise=True)
    ours = (Start(None, 30.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),)
    evaluator = RealEvaluator("standup_back", starts, pool, mujoco_starts=ours, sim_weight=0.5)
    results = evaluator.evaluate([params, params])
    assert len(pool.requests) == 2 * 3 and all(r.world == "real" for r in pool.requests)
    real_loss = rollout_loss(pool.run(pool.requests[:1])[0], 6.0, 0.0)
    mujoco = evaluate("standup_back", params, ours)
    assert results[0]["loss"] == pytest.approx(real_loss + 0.5 * mujoco["loss"])
    assert results[0]["times_s"] == [None] * 3 and results[0]["mujoco"]["times_s"] == mujoco["times_s"]
    # noisy starts play different motions
    assert len({dumps_xml(r.motions["standup_back"]) for r in pool.requests[:3]}) == 3


def test_the_stand_up_tuner_offers_the_real_backends(capsys):
    from motion_studio import tune_standup
    from motion_studio.realserver.standup_backend import make_evaluator

    with pytest.raises(SystemExit):
        tune_standup.main(["standup_back", "--help"])
    assert "--backend {mujoco,real,both}" in capsys.readouterr().out
    with pytest.raises(ValueError, match="unknown backend 'ray'"):
        make_evaluator("standup_back", "ray", 2, 1, False, 1, 6.0, 0.0)
