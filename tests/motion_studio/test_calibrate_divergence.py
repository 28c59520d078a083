"""motion-studio calibrate --divergence: where an open-loop replay leaves its real recording, joint by joint."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from motion_studio.calibration.agreement import Replay
from motion_studio.calibration.divergence import cycle_table, divergence, divergence_table, frozen_episodes
from motion_studio.realserver.fixtures import read_fixture
from motion_studio.realserver.replay import ReplayStates, replay_states

FIXTURES = Path(__file__).parents[1] / "sim" / "fixtures"
WALK = FIXTURES / "real_0.7.3_skill_walk_forward.jsonl.gz"
STANDUP_FRONT = FIXTURES / "real_0.7.3_skill_standup_front.jsonl.gz"


def _as_recorded(trace, bump_deg: float = 0.0, joint: str = "llj3", from_cycle: int = 0) -> Replay:  # noqa: ANN001
    """``trace`` against itself, with ``joint``'s HJ reading moved by ``bump_deg`` from ``from_cycle`` on."""
    def bumped(index: int, message: bytes) -> bytes:
        if index < from_cycle or not bump_deg:
            return message
        return re.sub(rb"\(HJ \(n " + joint.encode() + rb"\) \(ax (-?[0-9.]+)\)\)",
                      lambda m: b"(HJ (n %s) (ax %.2f))" % (joint.encode(), float(m.group(1)) + bump_deg), message)

    messages = [bumped(i, m) for i, m in enumerate(trace.received)]
    return Replay(trace, ReplayStates(dict(trace.truth), messages, 0, 0))


def test_a_replay_that_is_the_recording_never_diverges() -> None:
    trace = read_fixture(WALK)
    found = divergence(_as_recorded(trace))
    assert all(j.first_cycle is None and j.max_abs_deg == 0.0 for j in found.joints)
    pose = found.pose
    assert (pose.position_cycle, pose.height_cycle, pose.up_cycle, pose.heading_cycle, pose.parted_cycle) == (
        None, None, None, None, None)
    assert len(found.cycles) == len(trace.received) - trace.skill_cycle
    assert {c.sensor for c in found.contacts} == {"lf", "rf"}
    assert all(c.first_cycle is None for c in found.contacts)


def test_a_foot_that_touches_on_one_side_only_is_counted_from_its_cycle() -> None:
    trace = read_fixture(WALK)
    start = trace.skill_cycle + 20
    replay = _as_recorded(trace)
    lifted = [re.sub(rb"\(FRP \(n rf\)[^()]*\([^()]*\)[^()]*\([^()]*\)\)", b"", m) if i >= start else m
              for i, m in enumerate(replay.states.messages)]
    found = divergence(Replay(trace, ReplayStates(dict(trace.truth), lifted, 0, 0)))
    right = next(c for c in found.contacts if c.sensor == "rf")
    touching_real = [i for i in found.cycles if i >= start and right.real_force_n.get(i, 0.0) > 1.0]
    assert len(touching_real) > 50 and touching_real[0] == start   # the robot stands, then walks
    assert right.differing_cycles == touching_real
    assert all(c.first_cycle is None for c in found.contacts if c.sensor != "rf")


def test_one_joint_off_by_more_than_the_threshold_is_named_first_at_its_cycle() -> None:
    trace = read_fixture(WALK)
    start = trace.skill_cycle + 30
    found = divergence(_as_recorded(trace, bump_deg=1.5, joint="rlj4", from_cycle=start), threshold_deg=1.0)
    first, *others = found.joints
    assert (first.joint, first.first_cycle) == ("rlj4", start)
    assert first.max_abs_deg == pytest.approx(1.5, abs=0.01)
    assert all(j.first_cycle is None for j in others)
    # under the threshold it is seen but not counted
    found = divergence(_as_recorded(trace, bump_deg=0.5, joint="rlj4", from_cycle=start), threshold_deg=1.0)
    assert all(j.first_cycle is None for j in found.joints)


def test_the_real_forward_walk_replayed_here_leaves_it_at_the_left_hip_pitch() -> None:
    """The measured drift of our open-loop walk (sim.physics_params, "Walking feet land harder"): the left hip pitch
    is the first joint past 1 deg, about 1 deg further at every left landing, and ours falls where the real robot
    walks on."""
    trace = read_fixture(WALK)
    found = divergence(Replay(trace, replay_states(trace)))
    first = found.joints[0]
    assert first.joint == "llj3"
    at_3_s = first.error_deg[trace.skill_cycle + 150]
    assert at_3_s < -5.0, at_3_s
    assert all(abs(j.error_deg[trace.skill_cycle + 150]) < 2.0 for j in found.joints[1:])
    assert found.pose.real_fall_cycle is None and found.pose.ours_fall_cycle is not None
    # before any joint leaves the real one, our feet stay loaded where the real ones have lifted off
    lift_off = min(c.first_cycle for c in found.contacts if c.first_cycle is not None)
    assert lift_off < first.first_cycle
    late = next(c for c in found.contacts if c.first_cycle == lift_off)
    assert late.ours_force_n[lift_off] > 5.0 and late.real_force_n.get(lift_off, 0.0) < 1.0
    assert "llj3" in divergence_table(found).splitlines()[5]


def test_the_command_prints_the_table_and_writes_the_plot(tmp_path: Path) -> None:
    run = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--only", "skill_walk_forward",
                          "--divergence", "--out", str(tmp_path), "--cycles", "2.26:2.30", "--joints", "llj3"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "llj3" in run.stdout and "skill_walk_forward_simcmds" in run.stdout
    # the cycle table: 3 rows of the real walk's flight before the left landing, the landing's 127.6 N
    rows = [line for line in run.stdout.splitlines() if re.match(r"\s+1(59|60|61) \|", line)]
    assert len(rows) == 6 and "127.6 /" in rows[2], rows   # the trace and its simcmds twin, 3 cycles each
    assert (tmp_path / "divergence_skill_walk_forward.png").stat().st_size > 10_000
    refused = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--divergence"],
                             capture_output=True, text=True, timeout=120)
    assert refused.returncode == 2
    assert refused.stderr.strip().count("\n") == 0 and "--only" in refused.stderr
    for bad in (["--cycles", "2.6"], ["--cycles", "3:2"], ["--cycles", "a:b"]):
        refused = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--only", "skill_walk_forward",
                                  "--divergence", *bad], capture_output=True, text=True, timeout=120)
        assert refused.returncode == 2 and "--cycles" in refused.stderr, bad
        assert refused.stderr.strip().count("\n") == 0
    without = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--only", "skill_walk_forward",
                              "--cycles", "1:2"], capture_output=True, text=True, timeout=120)
    assert without.returncode == 2 and "--divergence" in without.stderr
    with_fit = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--only", "skill_stand",
                               "--divergence", "--generations", "2"], capture_output=True, text=True, timeout=120)
    assert with_fit.returncode == 2 and "--generations" in with_fit.stderr
    assert with_fit.stderr.strip().count("\n") == 0


@pytest.mark.parametrize("cycles_apart, parted", [(10, False), (30, True)])
def test_the_robots_part_only_after_half_a_second_apart(cycles_apart: int, parted: bool) -> None:
    """A fall that lands a few cycles earlier on one server is not a parting; half a second of one robot down and
    the other up is, from its first cycle."""
    from dataclasses import replace

    trace = read_fixture(WALK)
    start = trace.skill_cycle + 40
    ours = {i: (replace(t, up_z=0.1) if start <= i < start + cycles_apart else t) for i, t in trace.truth.items()}
    messages = list(trace.received)
    found = divergence(Replay(trace, ReplayStates(ours, messages, 0, 0)))
    assert found.pose.parted_cycle == (start if parted else None)
    assert found.pose.ours_fall_cycle == start and found.pose.real_fall_cycle is None
    assert found.cycles[-1] == (start if parted else len(trace.received) - 1)


def test_the_cycle_table_shows_the_real_walks_flight_before_each_left_landing() -> None:
    """Against itself every row has the same value on both sides; the real forward walk has a cycle with both feet off
    the ground before each left landing (no FRP at all on the left, -0.4 N on the right): its torso drops 5.2 mm."""
    trace = read_fixture(WALK)
    replay = _as_recorded(trace)
    found = divergence(replay)
    table = cycle_table(found, replay, 2.2, 2.6, joints=("llj3", "rlj3"))
    rows = table.splitlines()[2:]
    assert len(rows) == 21
    for row in rows:
        cells = row.split(" | ")[2:]
        assert all(len({side.strip() for side in cell.split(" / ")}) == 1 for cell in cells), row
    flight = next(row for row in rows if row.split(" | ")[1].strip() == "2.28").split(" | ")
    assert float(flight[3].split(" / ")[0]) < -5.0            # the torso's drop [mm]
    assert flight[4].split(" / ")[0].strip() == "-"           # the left foot: no contact at all
    assert float(flight[5].split(" / ")[0]) < 1.0             # the right foot has lifted too
    landing = next(row for row in rows if row.split(" | ")[1].strip() == "2.30").split(" | ")
    assert float(landing[4].split(" / ")[0]) > 120.0
    with pytest.raises(ValueError, match="no joint xx9"):
        cycle_table(found, replay, 2.2, 2.6, joints=("xx9",))
    with pytest.raises(ValueError, match="ends before"):
        cycle_table(found, replay, 2.6, 2.2)


def test_a_referee_freeze_of_the_real_robot_is_found_and_ours_misses_it() -> None:
    """The real front stand-up's recording: from 3.26 s after the skill's start both arms and legs stood still for a
    second while commanded on (a self-collision foul, SimSpark freezes for 1 s). Replayed here open loop, our referee
    calls no foul, ours moves on and falls back (sim/rules/self_collision.py finds no overlap even with the real
    joint angles). A walk never freezes."""
    trace = read_fixture(STANDUP_FRONT)
    found = divergence(Replay(trace, replay_states(trace)))
    (real,) = [e for e in found.frozen if e.side == "real"]
    assert (real.first_cycle - trace.skill_cycle) * 0.02 == pytest.approx(3.26, abs=0.03)
    assert 48 <= real.last_cycle - real.first_cycle + 1 <= 52       # 1 s of cycles
    assert {"laj1", "raj1", "llj3", "rlj3"} <= set(real.joints)
    assert not [e for e in found.frozen if e.side == "ours"]
    assert "real at 3.2" in divergence_table(found)
    walk = read_fixture(WALK)
    assert frozen_episodes(_as_recorded(walk), "real", list(range(walk.skill_cycle, len(walk.received)))) == []
