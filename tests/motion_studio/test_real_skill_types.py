"""``motion-studio real skills --type N``: every case played by a robot of type N with that type's motions, on our
simulator as on the real server (the real server is never started in tests)."""

from __future__ import annotations

from dataclasses import replace

from motion_studio.realserver.cases import CASES, MotionSource, behavior
from motion_studio.realserver.skill_runs import meta_line, run_sim


def test_a_case_played_by_type_4_uses_type_4_s_own_stand_ups():
    case = replace(CASES["standup_back"], robot_type=4)
    inner, _ = behavior(case, MotionSource())
    shared, _ = behavior(CASES["standup_back"], MotionSource())
    # type 4 has a toe joint (REFERENCE §2.5): its controller drives 24 joints, type 0's 22
    assert len(inner.motion.joints) == len(shared.motion.joints) + 2
    # motions/files/type4/standup_back.xml: the same parameters solved for type 4's shorter foot
    assert inner.motion.library.get("standup_back") != shared.motion.library.get("standup_back")
    assert inner.motion.library.get("walk_forward") == shared.motion.library.get("walk_forward")


def test_on_our_simulator_the_case_s_robot_is_of_its_type():
    # Type 3's legs are longer than type 0's (REFERENCE §2.5): standing in the same stance, its torso is higher.
    heights = {}
    for robot_type in (0, 3):
        run = run_sim(replace(CASES["stand"], robot_type=robot_type, cycles=60), MotionSource())
        heights[robot_type] = run.truths[-2].torso_m[2]
    assert heights[3] > heights[0] + 0.01, heights


def test_the_fixture_names_a_robot_type_other_than_0():
    source = MotionSource()
    assert meta_line(replace(CASES["stand"], robot_type=2), source, "our agent", "test")["robot_type"] == 2
    assert "robot_type" not in meta_line(CASES["stand"], source, "our agent", "test")
