"""Motion files as other RoboCup 3D teams write them, beyond REFERENCE §6's grammar.

The constructs come from the public robocup-fiit moves (FIIT's XML phase files: constants used in arithmetic,
notes on the move in ``<low_skills>``, 0 ms phases, repeated effectors and phase names, an ``opposite`` phase
attribute, move annotations) and the Webots ``V1.1`` motions the 2012 Kouretes / TUC agents shipped. The files
here are written for these tests (no third-party file is copied); each reads as those teams' own loaders read
it, with a warning naming the line wherever the reading makes a choice, and writes back unchanged.
"""

from __future__ import annotations

import json
import math

import pytest
from typer.testing import CliRunner

from motions import MotionFormatError, dumps_webots, dumps_xml, loads_webots, loads_xml
from motions.expressions import ExpressionError, evaluate

FIIT_STYLE = """<?xml version="1.0" encoding="UTF-8"?>
<robot xsi:noNamespaceSchemaLocation="moves.xsd">
	<constants>
		<constant name="crouch" value="30" />
		<constant name="crouch_ms" value="250" />
	</constants>

	<low_skills>
		<low_skill name="crouch_fiit" firstPhase="down" />
		<type>stand</type>
		<author>motion-studio tests</author>
		<description>a crouch written the FIIT way</description>
	</low_skills>

	<phases>
		<phase name="down" next="settle" opposite="down">
			<effectors>
				<lle3 end="crouch" />
				<rle3 end="crouch" />
				<lle4 end="-2*crouch" />
				<rle4 end="-2*crouch" />
				<lle5 end="crouch" />
				<rle5 end="(crouch+crouch)/2" />
			</effectors>
			<duration>2*crouch_ms</duration>
		</phase>
		<phase name="settle" next="hold">
			<effectors />
			<duration>0</duration>
		</phase>
		<phase name="hold" isFinal="true">
			<effectors />
			<duration>300</duration>
			<finalize>hold</finalize>
		</phase>
	</phases>
</robot>
"""

# The same crouch with plain numbers, REFERENCE §6a's grammar only.
PLAIN = """<robot>
  <low_skills><low_skill name="crouch" firstPhase="down"/></low_skills>
  <phases>
    <phase name="down" next="settle">
      <effectors>
        <lle3 end="30"/><rle3 end="30"/><lle4 end="-60"/><rle4 end="-60"/><lle5 end="30"/><rle5 end="30"/>
      </effectors>
      <duration>500</duration>
    </phase>
    <phase name="settle" next="hold"><effectors/><duration>20</duration></phase>
    <phase name="hold" isFinal="true"><effectors/><duration>300</duration><finalize>hold</finalize></phase>
  </phases>
</robot>
"""


def test_a_fiit_style_file_reads_as_the_plain_one_and_writes_back_byte_for_byte():
    fiit, plain = loads_xml(FIIT_STYLE, "crouch_fiit.xml"), loads_xml(PLAIN, "crouch.xml")
    assert [k.duration_s for k in fiit.keyframes] == pytest.approx([0.5, 0.02, 0.3])
    for fiit_phase, plain_phase in zip(fiit.keyframes, plain.keyframes):
        assert fiit_phase.targets == plain_phase.targets
    assert fiit.source.low_skill_notes == (("type", "stand", False), ("author", "motion-studio tests", False),
                                          ("description", "a crouch written the FIIT way", False))
    assert fiit.source.warnings == (
        "crouch_fiit.xml:16: attribute opposite='down' of <phase> is not in the format (allowed: name, next, "
        "isFinal, skipIfFlag, setFlagTrue, setFlagFalse): ignored by playback, written back",
        "crouch_fiit.xml:29: phase 'settle': duration 0 ms is played as one cycle (20 ms), as FIIT's loader plays it")
    assert dumps_xml(fiit) == FIIT_STYLE.replace("<duration>0</duration>", "<duration>20</duration>")


def test_an_edited_value_is_written_as_a_number_and_the_other_expressions_stay():
    motion = loads_xml(FIIT_STYLE, "crouch_fiit.xml")
    motion.keyframes[0].targets["llj4"] = type(motion.keyframes[0].targets["llj4"])(math.radians(-50.0))
    text = dumps_xml(motion)
    assert '<lle4 end="-50" />' in text and '<rle4 end="-2*crouch" />' in text
    assert "<duration>2*crouch_ms</duration>" in text


def test_notes_inside_the_low_skill_element_stay_inside():
    text = FIIT_STYLE.replace('firstPhase="down" />\n\t\t<type>stand</type>',
                              'firstPhase="down">\n\t\t\t<type>stand</type>\n\t\t</low_skill>')
    motion = loads_xml(text, "crouch_fiit.xml")
    assert motion.source.low_skill_notes[0] == ("type", "stand", True)
    assert dumps_xml(motion) == text.replace("<duration>0</duration>", "<duration>20</duration>")


def test_a_phase_without_effectors_holds_every_joint():
    motion = loads_xml(PLAIN.replace("<phase name=\"settle\" next=\"hold\"><effectors/>", "<phase name=\"settle\" "
                                     "next=\"hold\">"), "crouch.xml")
    assert motion.keyframes[1].targets == {} and motion.source.warnings == ()


@pytest.mark.parametrize(("end", "message"), [
    ("crouch+knee", "unknown constant 'knee' (constants: crouch, crouch_ms)"),
    ("crouch/(crouch-30)", "division by zero at character 7"),
    ("(crouch+1", "the expression ends too early"),
    ("crouch%2", "unexpected '%' at character 7"),
])
def test_a_bad_expression_names_the_line_the_field_and_what_is_wrong(end, message):
    with pytest.raises(MotionFormatError) as info:
        loads_xml(FIIT_STYLE.replace('<lle3 end="crouch" />', f'<lle3 end="{end}" />'), "crouch_fiit.xml")
    assert (info.value.line, info.value.field) == (18, "end")
    assert message in str(info.value)


def test_an_unknown_element_in_low_skills_is_still_an_error():
    with pytest.raises(MotionFormatError) as info:
        loads_xml(FIIT_STYLE.replace("<type>stand</type>", "<speed>2</speed>"), "crouch_fiit.xml")
    assert (info.value.line, info.value.field) == (10, "speed")


def test_a_fiit_move_annotation_is_refused_with_what_it_is():
    text = '<?xml version="1.0"?>\n<annotation name="kick">\n  <preconditions/>\n</annotation>\n'
    with pytest.raises(MotionFormatError) as info:
        loads_xml(text, "kick-0.xml")
    assert (info.value.line, info.value.field) == (2, "annotation")
    assert "FIIT move annotation" in str(info.value)


@pytest.mark.parametrize(("text", "value"), [
    ("30", 30.0), ("-2*crouch", -60.0), ("crouch+crouch/2", 45.0), ("(crouch+crouch)/2", 30.0), ("--crouch", 30.0),
    ("crouch_b-crouch", 1.0), (" 1e1 * 3 ", 30.0), ("1.5-.5", 1.0),
])
def test_expressions_follow_arithmetic_precedence_and_whole_names(text, value):
    assert evaluate(text, {"crouch": 30.0, "crouch_b": 31.0}) == pytest.approx(value)


def test_an_expression_is_never_handed_to_python():
    with pytest.raises(ExpressionError):
        evaluate("__import__", {})
    with pytest.raises(ExpressionError):
        evaluate("2**3", {})


V11 = ("#WEBOTS_MOTION,V1.1\r\n"
       "LShoulderPitch%LShoulderRoll%RShoulderPitch%LKneePitch\r\n"
       "play%1.5%0.1%1.5%0.0%0.5\r\n"
       "play%0.0%0.3%*%0.5%0\r\n"
       "play%-1.2%0.1%1.5%0.2%0.25\r\n")


def test_a_v1_1_webots_file_reads_with_its_pose_durations_and_0_as_two_cycles():
    motion = loads_webots(V11, "Arm.motion")
    assert [k.name for k in motion.keyframes] == ["Pose1", "Pose2", "Pose3"]
    assert [k.duration_s for k in motion.keyframes] == pytest.approx([0.5, 0.04, 0.25])
    assert motion.keyframes[1].targets["raj1"].angle_rad is None          # "*": not commanded
    assert motion.keyframes[0].targets["laj1"].angle_rad == pytest.approx(-1.5)   # pitch sign: SimSpark's
    assert motion.keyframes[2].targets["llj4"].angle_rad == pytest.approx(-0.2)   # knee pitch too
    assert motion.source.warnings == ("Arm.motion:3: 1 of 3 poses give 0 s: each played in 40 ms (the 2012 "
                                      "players' 2 cycles per pose)",)


def test_a_v1_1_file_is_written_as_v1_0_with_the_same_poses():
    motion = loads_webots(V11, "Arm.motion")
    text = dumps_webots(motion)
    assert text.splitlines()[:2] == ["#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll,RShoulderPitch,LKneePitch",
                                     "00:00:500,Pose1,1.5,0.1,1.5,0.0"]
    assert loads_webots(text, "Arm.motion") == motion


@pytest.mark.parametrize(("line", "field", "message"), [
    ("play%1.5%0.1%1.5\r\n", "values", "got 4 fields"),
    ("play%1.5%0.1%1.5%0.0%0.5%7\r\n", "values", "got 7 fields"),
    ("play%1.5%0.1%1.5%0.0%-1\r\n", "duration", "expected the pose's duration in seconds"),
    ("play%1.5%x%1.5%0.0%0.5\r\n", "LShoulderRoll", "expected a number or '*'"),
])
def test_a_bad_v1_1_pose_names_its_line_and_field(line, field, message):
    text = V11.split("\r\n", 3)
    with pytest.raises(MotionFormatError) as info:
        loads_webots("\r\n".join(text[:3]) + "\r\n" + line, "Arm.motion")
    assert (info.value.line, info.value.field) == (4, field)
    assert message in str(info.value)


def test_another_pose_state_word_is_a_warning():
    motion = loads_webots(V11.replace("play%0.0%0.3", "skip%0.0%0.3"), "Arm.motion")
    assert "Arm.motion:4: pose state 'skip' read as 'play'" in motion.source.warnings


def test_the_fiit_style_crouch_plays_on_our_simulator_as_the_plain_one(tmp_path):
    """The evaluated angles and the one-cycle phase reach the joints: both files end in the same crouch."""
    from motion_studio.cli import _register_commands, app

    _register_commands()
    heights = []
    for name, text in (("crouch_fiit.xml", FIIT_STYLE), ("crouch.xml", PLAIN)):
        path = tmp_path / name
        path.write_text(text)
        result = CliRunner().invoke(app, ["play", str(path), "--json"])
        assert result.exit_code == 0, result.output
        summary = json.loads(result.output.strip().splitlines()[-1])
        assert summary["fell"] is False
        heights.append(summary["final_torso_height_m"])
    assert 0.30 < heights[1] < 0.37
    assert heights[0] == pytest.approx(heights[1], abs=0.002)
