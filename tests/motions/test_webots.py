"""Webots .motion files: byte-exact round trips, typed values of REFERENCE §6b, errors with path/line/field."""

from __future__ import annotations

import dataclasses
import logging
import math

import pytest

from motions import JointTarget, MotionFormatError, dumps_webots, loads_webots
from motions.webots import format_time_ms, parse_time_ms
from tests.motions.conftest import without_sources

CANONICAL = ["raise_left_arm.motion"]


@pytest.mark.parametrize("name", CANONICAL)
def test_canonical_file_round_trips_byte_exact(fixture_text, name):
    text = fixture_text(name)
    assert dumps_webots(loads_webots(text, name)) == text


@pytest.mark.parametrize("name", CANONICAL)
def test_writer_produces_canonical_layout_without_source_details(fixture_text, name):
    text = fixture_text(name)
    assert dumps_webots(without_sources(loads_webots(text, name))) == text


def test_reference_example_round_trips_byte_exact(fixture_text):
    # "1.50" and "0.00" are not how the writer formats new values, but unchanged values keep their text.
    text = fixture_text("reference_6b.motion")
    assert dumps_webots(loads_webots(text)) == text


def test_reference_example_typed_values(fixture_text):
    motion = loads_webots(fixture_text("reference_6b.motion"), "fixtures/reference_6b.motion")
    assert motion.name == "reference_6b"
    assert motion.source_format == "webots"
    assert motion.joint_order == ("laj1", "laj2", "raj1")
    assert [k.name for k in motion.keyframes] == ["Pose1", "Pose2", "Pose3"]
    # First pose at time 0: duration 0; later durations are the time since the previous pose.
    assert [k.duration_s for k in motion.keyframes] == [0.0, 0.4, 0.4]
    assert motion.keyframe_times_s() == pytest.approx([0.0, 0.4, 0.8])
    pose1, pose2, pose3 = motion.keyframes
    # ShoulderPitch is a pitch joint: SimSpark sign = -(real Nao sign); ShoulderRoll keeps its sign.
    assert pose1.targets == {"laj1": JointTarget(-1.5), "laj2": JointTarget(0.1), "raj1": JointTarget(None)}
    assert pose2.targets["laj1"] == JointTarget(-0.0) and pose2.targets["laj2"] == JointTarget(0.3)
    assert pose3.targets["laj1"] == JointTarget(1.2)
    assert all(k.targets["raj1"].angle_rad is None for k in motion.keyframes)
    assert all(k.next is None and k.is_final is None for k in motion.keyframes)


def test_thesis_era_two_line_header_is_read_and_written_as_one_line():
    text = ("#WEBOTS_MOTION,V1.0\r\nLHipPitch,LKneePitch\r\n00:00:000,Pose1,-0.525,1.05\r\n"
            "00:00:040,Pose2,-0.5,1\r\n")
    motion = loads_webots(text, "TurnLeft40.motion")
    assert motion.joint_order == ("llj3", "llj4")
    assert motion.keyframes[0].targets["llj3"].angle_rad == 0.525
    assert motion.keyframes[1].targets["llj4"].angle_rad == -1.0
    assert dumps_webots(motion) == ("#WEBOTS_MOTION,V1.0,LHipPitch,LKneePitch\r\n00:00:000,Pose1,-0.525,1.05\r\n"
                                    "00:00:040,Pose2,-0.5,1\r\n")


@pytest.mark.parametrize(("token", "ms"), [("400", 400), ("2:5", 2005), ("1:02:120", 62120), ("00:00:000", 0),
                                           ("0:75:0", 75000)])
def test_time_formats(token, ms):
    assert parse_time_ms(token) == ms


@pytest.mark.parametrize("token", ["", "1:", ":5", "1::2", "1:2:3:4", "-5", "1.5", "# c", "0x10"])
def test_bad_time_tokens(token):
    assert parse_time_ms(token) is None


def test_time_writing():
    assert format_time_ms(400) == "00:00:400"
    assert format_time_ms(62120) == "01:02:120"


def test_short_time_forms_are_kept_until_changed():
    text = "#WEBOTS_MOTION,V1.0,HeadYaw\n400,A,0.1\n1:0,B,0.2\n"
    motion = loads_webots(text)
    assert motion.keyframe_times_s() == pytest.approx([0.4, 1.0])
    assert dumps_webots(motion) == text
    motion.keyframes[1].duration_s = 0.7
    assert dumps_webots(motion) == "#WEBOTS_MOTION,V1.0,HeadYaw\n400,A,0.1\n00:01:100,B,0.2\n"


def test_empty_fields_collapse_and_first_empty_line_ends_the_file(caplog):
    text = "#WEBOTS_MOTION,V1.0,HeadYaw,,HeadPitch\n100,A,,0.1,0.2\n\n200,B,junk\n"
    with caplog.at_level(logging.WARNING, logger="motions.webots"):
        motion = loads_webots(text, "m.motion")
    assert [k.name for k in motion.keyframes] == ["A"]
    assert motion.keyframes[0].targets == {"hj1": JointTarget(0.1), "hj2": JointTarget(-0.2)}
    assert "ignored" in caplog.text


def test_unknown_joint_column_is_a_warning_and_kept_for_round_trip(caplog):
    text = "#WEBOTS_MOTION,V1.0,HeadYaw,LWristYaw,HeadPitch\n00:00:100,A,0.1,0.7,*\n00:00:200,B,0.2,*,0.3\n"
    with caplog.at_level(logging.WARNING, logger="motions.webots"):
        motion = loads_webots(text, "m.motion")
    assert "LWristYaw" in caplog.text and len(motion.source.warnings) == 1
    assert motion.joint_order == ("hj1", "hj2")
    assert set(motion.keyframes[0].targets) == {"hj1", "hj2"}
    assert dumps_webots(motion) == text


def test_missing_joint_in_a_keyframe_is_written_as_undefined():
    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0.1,0.2\n")
    del motion.keyframes[0].targets["hj2"]
    motion.keyframes[0].targets["hj1"] = JointTarget(0.25)
    assert dumps_webots(motion) == "#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0.25,*\n"


def test_writer_refuses_phase_features():
    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0.1\n")
    motion.keyframes[0] = dataclasses.replace(motion.keyframes[0], next="A")
    with pytest.raises(MotionFormatError) as info:
        dumps_webots(motion)
    assert info.value.field == "next"


def test_writer_refuses_commas_in_pose_names():
    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0.1\n")
    motion.keyframes[0].name = "a,b"
    with pytest.raises(MotionFormatError) as info:
        dumps_webots(motion)
    assert info.value.field == "pose name"


# ----------------------------------------------------------------------------------------------- errors
HEADER = "#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll,RShoulderPitch\n"


def _error(text: str) -> MotionFormatError:
    with pytest.raises(MotionFormatError) as info:
        loads_webots(text, "arm.motion")
    return info.value


def test_decreasing_time():
    error = _error(HEADER + "00:00:400,A,1,0.1,*\n00:00:300,B,1,0.1,*\n")
    assert (error.path, error.line, error.field) == ("arm.motion", 3, "time")
    assert "strictly increase" in str(error)


def test_equal_time():
    error = _error(HEADER + "00:00:400,A,1,0.1,*\n400,B,1,0.1,*\n")
    assert (error.line, error.field) == (3, "time")


def test_too_few_values():
    error = _error(HEADER + "00:00:000,A,1,0.1,*\n00:00:400,B,1,0.1\n")
    assert (error.path, error.line, error.field) == ("arm.motion", 3, "RShoulderPitch")
    assert "expected 3 values, got 2" in str(error)


def test_too_many_values():
    error = _error(HEADER + "00:00:000,A,1,0.1,*,7\n")
    assert (error.path, error.line, error.field) == ("arm.motion", 2, "values")
    assert "'7'" in str(error)


def test_missing_pose_name():
    error = _error(HEADER + "00:00:000\n")
    assert (error.line, error.field) == (2, "pose name")


def test_bad_value():
    error = _error(HEADER + "00:00:000,A,1,abc,*\n")
    assert (error.path, error.line, error.field) == ("arm.motion", 2, "LShoulderRoll")
    assert str(error) == "arm.motion:2: field 'LShoulderRoll' of pose 'A': expected a number or '*', got 'abc'"


@pytest.mark.parametrize("first_line", ["#WEBOTS_MOTION", "WEBOTS_MOTION,V1.0,HeadYaw", "#WEBOTS,V1.0,HeadYaw",
                                        "", "HeadYaw,HeadPitch"])
def test_bad_header(first_line):
    error = _error(first_line + "\n00:00:000,A,1\n")
    assert error.path == "arm.motion" and error.line == 1
    assert error.field in ("header", "version")


def test_unsupported_version():
    error = _error("#WEBOTS_MOTION,V2.0,HeadYaw\n00:00:000,A,1\n")
    assert (error.line, error.field) == (1, "version")
    assert "V1.0 and V1.1 are read" in str(error)


def test_a_v1_1_header_with_the_names_on_its_own_line_is_an_error():
    error = _error("#WEBOTS_MOTION,V1.1,HeadYaw\n00:00:000,A,1\n")
    assert (error.line, error.field) == (1, "version")
    assert "line 2" in str(error)


def test_comment_line_after_header():
    error = _error(HEADER + "# raise the left arm\n00:00:000,A,1,0.1,*\n")
    assert (error.path, error.line, error.field) == ("arm.motion", 2, "time")
    assert "no comments" in str(error)


def test_duplicate_joint_column():
    error = _error("#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n0,A,1,2\n")
    assert (error.line, error.field) == (1, "HeadYaw")


def test_no_poses():
    error = _error(HEADER)
    assert error.field == "time" and error.line == 2


def test_overlong_line():
    error = _error(HEADER + "00:00:000,A," + "1" * 4100 + ",0.1,*\n")
    assert (error.line, error.field) == (2, "line")


def test_sign_conversion_is_its_own_inverse_for_every_joint():
    from kinematics import NAO_NAMES

    header = "#WEBOTS_MOTION,V1.0," + ",".join(NAO_NAMES) + "\n"
    values = ",".join(f"{0.01 * (i + 1):g}" for i in range(len(NAO_NAMES)))
    text = header + "00:00:020,P," + values + "\n"
    motion = loads_webots(text)
    pitch = {name for name in NAO_NAMES if "Pitch" in name and name != "LHipYawPitch" and name != "RHipYawPitch"}
    for i, name in enumerate(NAO_NAMES):
        wire = motion.joint_order[i]
        expected = -0.01 * (i + 1) if name in pitch else 0.01 * (i + 1)
        assert math.isclose(motion.keyframes[0].targets[wire].angle_rad, expected), name
    assert dumps_webots(motion) == text
