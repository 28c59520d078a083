"""Our simulator against the real rcssserver3d 0.7.3 on the shipped motions (tests/sim/fixtures/real_0.7.3_skill_*).

Each trace was recorded by tools/real_skill_check.py: our agent played a motion on the real server (sync mode,
PlayOn after a trainer move; motions of the git revision in the trace's meta line) and the monitor's full states
gave the torso pose per cycle. Here the recorded joint commands are replayed open loop on our simulator (same
connection, the same trainer commands at the same cycle, the full referee) and the outcome must agree with the
real one: the turn the robot made, how far it walked, the torso height, the leg joint angles, a fall or none.
Open loop, joint errors add up (the real motors lag at foot impacts where ours do not), so each check uses the
horizon over which the replay is meaningful. The bounds are the measured agreement plus a margin (figures beside
each); a change of contact, friction or motors that breaks the agreement fails here. The two xfail tests are
measured disagreements (see their reasons); they turn into failures (strict) once the simulator agrees.
``walk_forward_simcmds`` is the other way round: the commands our agent gave on our simulator, sent to the real
server (``tools/real_skill_check.py --replay-sim``), where our simulator's knee jumps and the real one does not.
"""

from __future__ import annotations

import gzip
import json
import math
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from agent.protocol.sense import parse_sense
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from sim.rules.trainer import apply_trainer_message
from tests.sim.scripted import Scripted

FIXTURES = Path(__file__).parent / "fixtures"
LEG_JOINTS = tuple(f"{side}lj{n}" for side in "lr" for n in range(1, 7))


@dataclass
class Pose:
    """Torso pose of one cycle: position [m], up-axis z, heading [deg]."""

    torso_m: tuple[float, float, float]
    up_z: float
    heading_deg: float


@dataclass
class Replay:
    meta: dict
    real: dict[int, Pose]
    ours: dict[int, Pose]
    real_joints: dict[int, dict[str, float]]
    our_joints: dict[int, dict[str, float]]
    real_messages: list[bytes]
    our_messages: list[bytes]

    @property
    def skill_cycles(self) -> range:
        """Cycles of the skill phase with a real pose."""
        start = self.meta["skill_cycle"]
        return range(start, max(self.real) + 1)


@cache
def replay(case: str) -> Replay:
    """The recorded commands of ``case`` replayed on our simulator; poses and joint angles of both by cycle."""
    rows = [json.loads(line) for line in gzip.open(FIXTURES / f"real_0.7.3_skill_{case}.jsonl.gz", "rt")]
    meta = next(r for r in rows if r["k"] == "meta")
    replies = {int(r["i"]): str(r["msg"]).encode() for r in rows if r["k"] == "send"}
    received = [str(r["msg"]).encode() for r in rows if r["k"] == "recv"]
    real = {int(r["i"]): Pose(tuple(r["torso"]), r["up_z"], r["heading_deg"]) for r in rows if r["k"] == "truth"}
    agent = Scripted({i: m for i, m in replies.items() if i >= 0}, scene=replies[-1])
    engine = SimEngine(seed=0)  # the full referee: PlayOn rules and self-collision fouls, as the real server
    host = InProcessHost(engine)
    key = host.add(agent)
    world = engine.world
    ours: dict[int, Pose] = {}
    while len(agent.received) < len(received):
        count = len(agent.received)
        host.run(1)
        if len(agent.received) == count:
            continue
        index = len(agent.received) - 1
        # The engine delivers the message made at the end of the previous step, then steps: the world now
        # holds the state that message index + 1 will report (the real truth of cycle i is the state of
        # message i: the monitor frame with its game time).
        rotation = world.torso_rotation(key)
        ours[index + 1] = Pose(tuple(world.torso_position(key).tolist()), float(rotation[2, 2]),
                               world.heading_deg(key))
        if index == meta["move_cycle"]:
            # the trainer commands (move, ball, PlayOn) went out with the answer to this message: applied
            # before the next step, as that answer (REFERENCE 3.9)
            for command in meta["trainer"]:
                apply_trainer_message(command, engine.referee, world)
    real_joints = {i: parse_sense(m).joints for i, m in enumerate(received)}
    our_joints = {i: parse_sense(m).joints for i, m in enumerate(agent.received)}
    return Replay(meta, real, ours, real_joints, our_joints, received, agent.received)


def turned_deg(poses: dict[int, Pose], cycles: range) -> float:
    """Heading change summed cycle by cycle (unwrapped) [deg]."""
    headings = [poses[i].heading_deg for i in cycles if i in poses]
    return float(sum((b - a + 180.0) % 360.0 - 180.0 for a, b in zip(headings, headings[1:])))


def displacement_m(poses: dict[int, Pose], cycles: range) -> tuple[float, float]:
    """(forward, left) of the last pose in the frame of the first [m]."""
    first, last = poses[cycles[0]], poses[cycles[-1]]
    c, s = math.cos(math.radians(first.heading_deg)), math.sin(math.radians(first.heading_deg))
    dx, dy = last.torso_m[0] - first.torso_m[0], last.torso_m[1] - first.torso_m[1]
    return c * dx + s * dy, -s * dx + c * dy


def joint_rms_deg(run: Replay, cycles: range) -> float:
    errors = [run.our_joints[i][name] - run.real_joints[i][name] for i in cycles for name in LEG_JOINTS]
    return float(np.sqrt(np.mean(np.square(errors))))


def window(run: Replay, cycles: int) -> range:
    """The first ``cycles`` cycles of the skill phase."""
    start = run.meta["skill_cycle"]
    return range(start, start + cycles)


def mean_height_m(poses: dict[int, Pose], cycles: range) -> float:
    return float(np.mean([poses[i].torso_m[2] for i in cycles]))


def upright(poses: dict[int, Pose], cycles: range) -> bool:
    """No cycle meets REFERENCE 8.1's fall criterion (up-axis z < 0.6 or torso below 0.25 m)."""
    return all(poses[i].up_z >= 0.6 and poses[i].torso_m[2] >= 0.25 for i in cycles)


def test_stand_height_and_stillness() -> None:
    run = replay("stand")
    cycles = window(run, 200)
    # measured: torso 0.5 mm higher here (ODE lets a loaded foot sink ~1 mm, ours ~0.4 mm), moves 1 mm apart
    assert abs(mean_height_m(run.ours, cycles) - mean_height_m(run.real, cycles)) < 0.0015
    assert run.ours[cycles[-1]].torso_m[2] == pytest.approx(run.real[cycles[-1]].torso_m[2], abs=0.0015)
    assert math.dist(displacement_m(run.ours, cycles), displacement_m(run.real, cycles)) < 0.005
    assert joint_rms_deg(run, cycles) < 0.3  # measured 0.04


@pytest.mark.parametrize("case", ["turn_left", "turn_right"])
def test_turn_motions_turn_as_on_the_real_server(case: str) -> None:
    run = replay(case)
    cycles = window(run, 250)  # 10.9 turn motions
    real, ours = turned_deg(run.real, cycles), turned_deg(run.ours, cycles)
    # measured: real 360.0 deg, ours 377.6 (+4.9 %: 39.5 deg a motion here, 37.9 there)
    assert abs(real) > 300.0
    assert abs(ours - real) <= 0.08 * abs(real) + 2.0
    assert upright(run.ours, cycles)
    assert math.dist(displacement_m(run.ours, cycles), displacement_m(run.real, cycles)) < 0.03  # 0.004
    assert abs(mean_height_m(run.ours, cycles) - mean_height_m(run.real, cycles)) < 0.0015  # 0.4 mm
    assert joint_rms_deg(run, cycles) < 0.5  # measured 0.20


def test_turn_by_90_degrees_turns_as_on_the_real_server() -> None:
    run = replay("turn_by_90")
    cycles = window(run, 150)
    real, ours = turned_deg(run.real, cycles), turned_deg(run.ours, cycles)
    # measured: real 87.8 deg in three motions at a gain below 1, ours 94.9 (+8 %)
    assert 80.0 < real < 95.0
    assert abs(ours - real) <= 0.08 * abs(real) + 2.0
    assert upright(run.ours, cycles)
    assert joint_rms_deg(run, cycles) < 0.3  # measured 0.04


def test_walk_forward_first_three_seconds_as_on_the_real_server() -> None:
    run = replay("walk_forward")
    cycles = window(run, 150)
    real, ours = displacement_m(run.real, cycles), displacement_m(run.ours, cycles)
    # measured: real 1.272 m forward, ours 1.357 (+6.7 %); heading 0.05 vs 1.85 deg; torso 1.1 mm lower here
    assert real[0] > 1.0
    assert ours[0] == pytest.approx(real[0], rel=0.12)
    assert abs(ours[1] - real[1]) < 0.1
    assert abs(turned_deg(run.ours, cycles) - turned_deg(run.real, cycles)) < 5.0
    assert abs(mean_height_m(run.ours, cycles) - mean_height_m(run.real, cycles)) < 0.003
    assert upright(run.ours, cycles)
    assert joint_rms_deg(run, cycles) < 2.5  # measured 1.33 (the real hips lag ~1.1 deg at each foot impact)


@pytest.mark.parametrize("case, cycles, along, across", [("walk_backward", 600, 0, 1), ("walk_left", 600, 1, 0),
                                                        ("walk_right", 600, 1, 0)])
def test_other_walks_cover_the_real_distance(case: str, cycles: int, along: int, across: int) -> None:
    run = replay(case)
    window_cycles = window(run, cycles)
    real, ours = displacement_m(run.real, window_cycles), displacement_m(run.ours, window_cycles)
    # measured (12 s: 10 s walking, 2 s stopping): backward -2.892 / -2.962 m, left 2.572 / 2.634,
    # right -2.549 / -2.656 (ours 2.4-4.2 % further); across 0.01-0.15 m apart
    assert abs(real[along]) > 2.0
    assert ours[along] == pytest.approx(real[along], rel=0.07)
    assert abs(ours[across] - real[across]) < 0.25
    assert upright(run.ours, window_cycles)
    assert abs(mean_height_m(run.ours, window_cycles) - mean_height_m(run.real, window_cycles)) < 0.0015
    # headings drift apart over 12 s (up to 24 deg); over the first 5 s they stay within 6 deg
    first = window(run, 250)
    assert abs(turned_deg(run.ours, first) - turned_deg(run.real, first)) < 8.0
    assert joint_rms_deg(run, window_cycles) < 2.5  # measured 0.8-1.5


@pytest.mark.parametrize("case", ["standup_back", "standup_front"])
def test_scripted_fall_lands_as_on_the_real_server(case: str) -> None:
    run = replay(case)
    cycles = window(run, 100)  # the scripted fall (tools/real_skill_check.FALL_SCRIPT) and the stand-up's start
    fallen = [next(i for i in cycles if poses[i].up_z < 0.6 or poses[i].torso_m[2] < 0.25)
              for poses in (run.real, run.ours)]
    assert abs(fallen[1] - fallen[0]) <= 2  # measured: 1 cycle apart
    # measured: lying torso height 0.2377 / 0.2342 m (back), 0.1676 / 0.1650 (front) over the window
    assert abs(mean_height_m(run.ours, cycles) - mean_height_m(run.real, cycles)) < 0.008
    assert joint_rms_deg(run, cycles) < 2.0  # measured 0.95, 1.37


def test_same_commands_same_leg_up_to_the_first_step() -> None:
    run = replay("walk_forward_simcmds")
    cycles = window(run, 34)  # standstill, the walk's start and first step
    assert joint_rms_deg(run, cycles) < 0.2  # measured 0.05
    assert upright(run.ours, cycles)


@pytest.mark.xfail(strict=True, reason="measured disagreement (sim bug): with the same commands, our left knee "
                   "moves +33 deg and the hip pitch -14 deg in the one step from skill cycle 33 to 34 (knee "
                   "commanded +6.14 rad/s = +7.0 deg a step; the real knee moves +7.0) as the swing foot lands; "
                   "our robot then falls at 1.6 s, the real one walks on until the later (reactive) commands")
def test_same_commands_same_knee_at_the_first_landing() -> None:
    run = replay("walk_forward_simcmds")
    step = run.meta["skill_cycle"] + 34
    for name in ("llj3", "llj4"):
        assert run.our_joints[step][name] == pytest.approx(run.real_joints[step][name], abs=1.0)


@pytest.mark.xfail(strict=True, reason="measured disagreement: open loop, our robot falls during the 12th turn "
                   "motion (a hip yaw-pitch joint, rlj1, is back-driven by ~28 deg in a few cycles, which ODE's "
                   "motor never allows); the real robot turns 607 deg upright")
def test_sixteen_turn_motions_stay_upright() -> None:
    run = replay("turn_left")
    assert upright(run.ours, window(run, 400))


@pytest.mark.xfail(strict=True, reason="measured disagreement: open loop, our robot falls after ~4 s of the real "
                   "walk's commands (joint errors from the foot impacts add up; the blow-up guard fires during "
                   "the fall); the real robot walks 5.3 m in 12 s upright")
def test_twelve_seconds_of_the_real_walk_stay_upright() -> None:
    run = replay("walk_forward")
    assert upright(run.ours, window(run, 600))
