"""The motion model: time axis, interpolation, XML phase graph, mirror, validation."""

from __future__ import annotations

import math

import pytest

from motions import JointTarget, Keyframe, Motion, MotionFormatError, loads_webots, loads_xml, mirror_table


def _deg(pose: dict[str, float | None]) -> dict[str, float | None]:
    return {k: None if v is None else round(math.degrees(v), 9) for k, v in pose.items()}


# ----------------------------------------------------------------------------------------------- time axis
def test_times_and_duration(fixture_text):
    motion = loads_xml(fixture_text("walk_cycle.xml"))
    assert motion.keyframe_times_s() == pytest.approx([0.08, 0.16, 0.28])
    assert motion.duration_s == pytest.approx(0.28)


def test_webots_interpolation(fixture_text):
    motion = loads_webots(fixture_text("reference_6b.motion"))
    assert motion.source_format == "webots"
    mid = motion.pose_at(0.2)
    assert mid["laj1"] == pytest.approx(-0.75) and mid["laj2"] == pytest.approx(0.2)
    assert mid["raj1"] is None  # '*' at either end: not commanded
    assert motion.pose_at(-1.0)["laj1"] == -1.5  # before the first pose its values apply
    assert motion.pose_at(5.0)["laj1"] == pytest.approx(1.2)  # after the last pose its values stay
    assert motion.pose_at(0.4)["laj1"] == pytest.approx(0.0)


def test_webots_first_pose_later_than_zero_holds_before_its_time():
    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:400,A,0.4\n00:00:800,B,0.8\n")
    assert motion.keyframes[0].duration_s == 0.4
    assert motion.pose_at(0.1) == {"hj1": 0.4}
    assert motion.pose_at(0.6)["hj1"] == pytest.approx(0.6)
    assert motion.pose_at(0.2, start_pose={"hj1": 0.0})["hj1"] == pytest.approx(0.2)


def test_xml_interpolation_holds_unlisted_joints(fixture_text):
    motion = loads_xml(fixture_text("walk_cycle.xml"))
    pose = _deg(motion.pose_at(0.12))  # half-way through 'swing', which lists only rle3 and rle4
    assert pose["llj3"] == pytest.approx(46) and pose["llj5"] == pytest.approx(30)  # held from 'lift'
    assert pose["rlj3"] is None  # never commanded before: the start is unknown
    with_start = _deg(motion.pose_at(0.12, start_pose={"rlj3": 0.0}))
    assert with_start["rlj3"] == pytest.approx(32.5)
    assert _deg(motion.pose_at(0.04, start_pose={"llj3": 0.0}))["llj3"] == pytest.approx(23)
    assert _deg(motion.pose_at(0.04))["llj3"] == pytest.approx(46)
    assert motion.pose_at(0.12, hold_unlisted=False)["llj3"] is None


# --------------------------------------------------------------------------------------------- phase graph
def test_successor_follows_next_and_finalize(fixture_text):
    motion = loads_xml(fixture_text("bob_demo.xml"))
    assert motion.successor("bob_down", requested_same_motion=True).name == "bob_up"
    assert motion.successor("bob_up", requested_same_motion=True).name == "bob_down"  # cycle
    assert motion.successor("bob_up", requested_same_motion=False).name == "bob_rest"  # finalize
    assert motion.successor("bob_down", requested_same_motion=False).name == "bob_up"  # no finalize: next
    assert motion.successor("bob_rest", requested_same_motion=False) is None  # finalize itself: end here
    assert motion.successor("bob_rest", requested_same_motion=True) is None  # no next: end
    assert motion.start_phase().name == "bob_down"
    assert [k.name for k in motion.play_order()] == ["bob_down", "bob_up"]


def test_phase_lookup_errors(fixture_text):
    motion = loads_xml(fixture_text("bob_demo.xml"), "bob_demo.xml")
    with pytest.raises(MotionFormatError) as info:
        motion.phase("nope")
    assert info.value.field == "phase" and "bob_down" in str(info.value)
    assert motion.find_phase("nope") is None


def test_start_phase_defaults_to_first_keyframe():
    motion = Motion("m", [Keyframe("a", 0.1), Keyframe("b", 0.1)])
    assert motion.start_phase().name == "a"
    assert [k.name for k in motion.play_order()] == ["a"]


def test_time_scaled(fixture_text):
    motion = loads_xml(fixture_text("walk_cycle.xml"))
    slow = motion.time_scaled(1.35)
    assert slow.duration_s == pytest.approx(0.28 * 1.35)
    assert motion.duration_s == pytest.approx(0.28)
    with pytest.raises(ValueError):
        motion.time_scaled(0.0)


# ----------------------------------------------------------------------------------------------- mirror
def test_mirror_signs_follow_the_axes():
    table = mirror_table()
    keep = {"hj2", "laj1", "raj1", "llj1", "rlj1", "llj3", "rlj3", "llj4", "rlj4", "llj5", "rlj5", "llj7", "rlj7"}
    for wire, (other, sign) in table.items():
        assert sign == (1 if wire in keep else -1), wire
        assert table[other] == (wire, sign)
    assert table["hj1"] == ("hj1", -1) and table["llj2"] == ("rlj2", -1) and table["laj1"] == ("raj1", 1)


def test_mirror_of_a_known_asymmetric_pose():
    targets = {"hj1": 20, "hj2": 10, "laj1": -90, "laj2": 30, "laj3": -90, "laj4": -45,
               "llj1": -30, "llj2": 10, "llj3": 40, "llj4": -60, "llj5": 25, "llj6": 5}
    motion = Motion("m", [Keyframe("p", 0.2, {k: JointTarget.from_deg(v) for k, v in targets.items()})])
    mirrored = motion.mirrored()
    got = {k: round(t.angle_deg, 9) for k, t in mirrored.keyframes[0].targets.items()}
    assert got == {"hj1": -20, "hj2": 10, "raj1": -90, "raj2": -30, "raj3": 90, "raj4": 45,
                   "rlj1": -30, "rlj2": -10, "rlj3": 40, "rlj4": -60, "rlj5": 25, "rlj6": -5}
    mirrored.validate()  # the mirror image of a pose within the limits is within the limits


def test_symmetric_walk_stance_is_its_own_mirror_image():
    # REFERENCE §7.2 stance: hip roll R +7 / L -7, ankle roll R -7 / L +7, both arms down.
    stance = {"lle2": -7, "rle2": 7, "lle6": 7, "rle6": -7, "lle3": 46, "rle3": 46, "lae1": -90, "rae1": -90}
    text = ('<robot><low_skills><low_skill name="s" firstPhase="s"/></low_skills><phases><phase name="s">'
            "<effectors>" + "".join(f'<{k} end="{v}"/>' for k, v in stance.items()) +
            "</effectors><duration>400</duration></phase></phases></robot>")
    motion = loads_xml(text)
    assert motion.mirrored() == motion


@pytest.mark.parametrize("name", ["bob_demo.xml", "walk_cycle.xml", "raise_left_arm.motion", "reference_6b.motion"])
def test_mirroring_twice_is_identity(fixture_text, name):
    from motions import loads

    motion = loads(fixture_text(name))
    assert motion.mirrored() != motion
    assert motion.mirrored().mirrored() == motion


# ----------------------------------------------------------------------------------------------- validation
def _single_phase(effector: str) -> str:
    return ('<robot>\n<low_skills><low_skill name="m" firstPhase="p"/></low_skills>\n<phases>\n<phase name="p">\n'
            f"<effectors>\n{effector}\n</effectors>\n<duration>100</duration>\n</phase>\n</phases>\n</robot>\n")


def test_validate_reports_angle_beyond_limit_with_location():
    motion = loads_xml(_single_phase('<lle3 end="130"/>'), "kick.xml")
    with pytest.raises(MotionFormatError) as info:
        motion.validate()
    error = info.value
    assert (error.path, error.line, error.field) == ("kick.xml", 6, "lle3")
    assert "130 deg is outside the joint range [-25, 100] deg" in str(error)


def test_validate_limits_on_the_edge_pass():
    loads_xml(_single_phase('<lle3 end="100"/><lle4 end="-130"/>')).validate()


def test_validate_webots_names_the_column():
    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw,LKneePitch\n0,A,0,-0.5\n", "k.motion")
    with pytest.raises(MotionFormatError) as info:
        motion.validate()  # LKneePitch -0.5 real = +28.6 deg SimSpark, beyond the 1 deg stop
    assert (info.value.line, info.value.field) == (2, "LKneePitch")


def test_validate_robot_type_decides_the_toes():
    motion = loads_xml(_single_phase('<lle7 end="10"/>'))
    motion.validate(robot_type=4)
    with pytest.raises(MotionFormatError) as info:
        motion.validate(robot_type=0)
    assert info.value.field == "llj7"


@pytest.mark.parametrize(("keyframes", "field"), [
    ([], "keyframes"),
    ([Keyframe("a", 0.1), Keyframe("b", 0.0)], "duration"),
    ([Keyframe("a", -0.1)], "duration"),
    ([Keyframe("a", math.nan)], "duration"),
    ([Keyframe("a", 0.1, {"LHipPitch": JointTarget(0.1)})], "LHipPitch"),
    ([Keyframe("a", 0.1, {"zz9": JointTarget(0.1)})], "zz9"),
    ([Keyframe("a", 0.1, {"llj3": JointTarget(math.inf)})], "llj3"),
])
def test_validate_code_built_motions(keyframes, field):
    with pytest.raises(MotionFormatError) as info:
        Motion("m", keyframes).validate()
    assert info.value.field == field and info.value.path is None


def test_validate_first_pose_may_take_no_time():
    Motion("m", [Keyframe("a", 0.0), Keyframe("b", 0.1)]).validate()
