"""Conversion between the formats, and the errors for what Webots cannot express."""

from __future__ import annotations

import logging

import pytest

from motions import (ConversionError, JointTarget, Keyframe, Motion, dumps, loads, loads_webots, loads_xml,
                     to_webots, to_xml)
from tests.motions.conftest import assert_same_motion


def test_linear_xml_chain_to_webots(fixture_text):
    motion = loads_xml(fixture_text("walk_cycle.xml"))
    webots = to_webots(motion)
    assert webots.source_format == "webots"
    assert webots.keyframe_times_s() == pytest.approx([0.08, 0.16, 0.28])
    # Unlisted joints hold their previous target (XML gives them velocity 0); never-listed ones are '*'.
    assert dumps(webots) == (
        "#WEBOTS_MOTION,V1.0,LHipPitch,LKneePitch,LAnklePitch,RHipPitch,RKneePitch\n"
        "00:00:080,lift,-0.8028514559173916,1.0471975511965976,-0.5235987755982988,*,*\n"
        "00:00:160,swing,-0.8028514559173916,1.0471975511965976,-0.5235987755982988,-1.1344640137963142,"
        "1.3962634015954636\n"
        "00:00:280,land,-0.8901179185171081,1.0471975511965976,-0.5235987755982988,-0.8901179185171081,"
        "1.0471975511965976\n")


def test_xml_to_webots_to_xml_keeps_targets_and_durations(fixture_text):
    motion = loads_xml(fixture_text("walk_cycle.xml"))
    back = to_xml(loads(dumps(motion, "webots")), name=motion.name)
    assert [k.duration_s for k in back.keyframes] == [k.duration_s for k in motion.keyframes]
    for original, converted in zip(motion.keyframes, back.keyframes):
        for wire, target in original.targets.items():
            assert converted.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=1e-15)
    assert [k.next for k in back.keyframes] == ["swing", "land", None]


def test_cycle_flags_and_finalize_phases_are_refused_each_with_its_option(fixture_text):
    motion = loads_xml(fixture_text("bob_demo.xml"))
    with pytest.raises(ConversionError) as info:
        to_webots(motion)
    assert info.value.field == "next" and "unroll_cycle=True" in str(info.value)
    assert "bob_down -> bob_up -> bob_down" in str(info.value)
    with pytest.raises(ConversionError) as info:
        to_webots(motion, unroll_cycle=True)
    assert "'bob_rest'" in str(info.value) and "drop_unreachable=True" in str(info.value)
    with pytest.raises(ConversionError) as info:
        to_webots(motion, unroll_cycle=True, drop_unreachable=True)
    assert info.value.field == "skipIfFlag" and "drop_dynamic=True" in str(info.value)
    webots = to_webots(motion, unroll_cycle=True, drop_unreachable=True, drop_dynamic=True)
    assert [k.name for k in webots.keyframes] == ["bob_down", "bob_up"]
    assert webots.keyframes[1].targets["hj1"] == JointTarget(0.0)  # computed -> its 'end' fallback, held
    assert not any(k.uses_phase_features() for k in webots.keyframes)


def test_computed_values_are_refused():
    text = ('<robot><low_skills><low_skill name="m" firstPhase="p"/></low_skills><phases><phase name="p">'
            '<effectors><he1 end="0" computed="headAngle1"/></effectors><duration>40</duration></phase>'
            "</phases></robot>")
    with pytest.raises(ConversionError) as info:
        to_webots(loads_xml(text))
    assert info.value.field == "computed"


def test_dumps_converts_with_options(fixture_text):
    motion = loads_xml(fixture_text("bob_demo.xml"))
    with pytest.raises(ConversionError):
        dumps(motion, "webots")
    text = dumps(motion, "webots", unroll_cycle=True, drop_unreachable=True, drop_dynamic=True)
    assert text.startswith("#WEBOTS_MOTION,V1.0,HeadYaw,LShoulderRoll,")


def test_webots_to_xml(fixture_text):
    motion = loads_webots(fixture_text("reference_6b.motion"), "reference_6b.motion")
    xml = to_xml(motion)
    assert xml.source_format == "xml" and xml.first_phase == "Pose1" and xml.name == "reference_6b"
    # The pose at time 0 gets one server cycle; later phases keep the time between poses.
    assert [k.duration_s for k in xml.keyframes] == [0.02, 0.4, 0.4]
    assert [k.next for k in xml.keyframes] == ["Pose2", "Pose3", None]
    assert all("raj1" not in k.targets for k in xml.keyframes)  # '*' -> joint left out of the phase
    assert xml.keyframes[0].targets["laj1"] == JointTarget(-1.5)
    assert_same_motion(loads(dumps(xml)), xml)
    assert "<duration>20</duration>" in dumps(motion, "xml")


def test_webots_to_xml_makes_phase_names_unique():
    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw\n100,P,0.1\n200,P,0.2\n300,P_2,0.3\n")
    assert [k.name for k in to_xml(motion).keyframes] == ["P", "P_2", "P_2_2"]


def test_fractional_milliseconds_need_rounding(caplog):
    motion = Motion("m", [Keyframe("a", 0.0806, {"hj1": JointTarget(0.1)})], source_format="webots")
    with pytest.raises(ConversionError) as info:
        to_xml(motion)
    assert info.value.field == "duration" and "round_durations=True" in str(info.value)
    with caplog.at_level(logging.WARNING, logger="motions.convert"):
        rounded = to_xml(motion, round_durations=True)
    assert rounded.keyframes[0].duration_s == 0.081
    assert "0.400 ms" in caplog.text


def test_code_built_motion_without_phase_features_passes_to_webots():
    motion = Motion("m", [Keyframe("a", 0.1, {"hj1": JointTarget(0.1)})])
    assert dumps(motion, "webots") == "#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:100,a,0.1\n"
    assert dumps(motion, "xml").count("<phase ") == 1
