"""XML phase format: byte-exact round trips, typed values of REFERENCE §6a, errors with path/line/field."""

from __future__ import annotations

import dataclasses
import logging
import math

import pytest

from motions import JointTarget, MotionFormatError, dumps_xml, loads_xml
from tests.motions.conftest import without_sources

CANONICAL = ["bob_demo.xml", "walk_cycle.xml"]


@pytest.mark.parametrize("name", CANONICAL)
def test_canonical_file_round_trips_byte_exact(fixture_text, name):
    text = fixture_text(name)
    assert dumps_xml(loads_xml(text, name)) == text


@pytest.mark.parametrize("name", CANONICAL)
def test_writer_produces_canonical_layout_without_source_details(fixture_text, name):
    # With every remembered text and layout detail dropped, the writer alone must give the same bytes.
    text = fixture_text(name)
    assert dumps_xml(without_sources(loads_xml(text, name))) == text


def test_reference_example_typed_values(fixture_text):
    motion = loads_xml(fixture_text("reference_6a.xml"), "reference_6a.xml")
    assert motion.name == "bob_demo"
    assert motion.source_format == "xml"
    assert motion.first_phase == "bob_down"
    assert [k.name for k in motion.keyframes] == ["bob_down", "bob_up", "bob_rest"]
    down, up, rest = motion.keyframes
    # Effector names in the file, wire names inside, file order kept.
    assert list(down.targets) == ["llj3", "llj4", "llj5", "rlj3", "rlj4", "rlj5", "hj1"]
    assert down.targets["llj3"] == JointTarget(math.radians(40))
    assert down.targets["llj4"].angle_rad == pytest.approx(-80 * math.pi / 180, abs=1e-15)
    assert down.targets["hj1"] == JointTarget(0.0, "headAngle1")
    assert down.duration_s == 0.3
    assert (down.next, down.finalize, down.is_final, down.skip_if_flag) == ("bob_up", None, None, "crouched")
    assert (up.next, up.finalize, up.is_final, up.set_flag_false) == ("bob_down", "bob_rest", True, "crouched")
    assert up.set_flag_true is None
    assert rest.targets == {}
    assert (rest.next, rest.finalize, rest.is_final, rest.duration_s) == (None, "bob_rest", True, 0.2)
    assert motion.constants == {}
    assert motion.source.warnings == ()


def test_reference_example_keeps_values_when_rewritten(fixture_text):
    # Not canonical (spaces, several effectors per line, a comment): the layout changes, the motion does not.
    motion = loads_xml(fixture_text("reference_6a.xml"), "a.xml")
    again = loads_xml(dumps_xml(motion), "b.xml")
    assert again == motion


def test_canonical_fixture_constants_and_comment(fixture_text):
    motion = loads_xml(fixture_text("bob_demo.xml"), "bob_demo.xml")
    assert motion.constants == {"crouch_depth": 40.0, "rise_depth": -7.5}
    assert motion.header_comments[0].startswith(" bob_demo: made-up")
    assert motion.keyframes[2].is_final is False
    assert motion.keyframes[2].set_flag_true == "resting"


def test_original_number_text_is_kept_until_the_value_changes():
    text = ('<robot><low_skills><low_skill name="m" firstPhase="p"/></low_skills><phases>'
            '<phase name="p"><effectors><lle3 end="-7.50"/><lle4 end="+12"/></effectors>'
            '<duration>0100</duration></phase></phases></robot>')
    motion = loads_xml(text)
    out = dumps_xml(motion)
    assert 'end="-7.50"' in out and 'end="+12"' in out and "<duration>0100</duration>" in out
    keyframe = motion.keyframes[0]
    keyframe.targets["llj3"] = JointTarget.from_deg(-8.0)
    keyframe.duration_s = 0.2
    out = dumps_xml(motion)
    assert 'end="-8"' in out and 'end="+12"' in out and "<duration>200</duration>" in out


def test_layout_details_of_foreign_files_are_kept():
    text = ('<?xml version="1.0" encoding="UTF-8"?>\r\n<robot xsi:noNamespaceSchemaLocation="moves.xsd">\r\n'
            '\t<low_skills>\r\n\t\t<low_skill name="m" firstPhase="p" />\r\n\t</low_skills>\r\n\r\n\t<phases>\r\n'
            '\t\t<phase next="p" name="p" isFinal="true">\r\n\t\t\t<effectors />\r\n\t\t\t<duration>20</duration>\r\n'
            '\t\t</phase>\r\n\t</phases>\r\n</robot>')
    # CRLF, no final newline, root attribute, attribute order next-before-name: all written back as read.
    assert dumps_xml(loads_xml(text)) == text


def test_special_characters_are_escaped():
    text = ('<robot><low_skills><low_skill name="a&amp;b &quot;q&quot;" firstPhase="x&lt;y"/></low_skills>'
            '<phases><phase name="x&lt;y" next="x&lt;y"><effectors/><duration>20</duration>'
            '<finalize>x&lt;y</finalize></phase></phases></robot>')
    motion = loads_xml(text)
    assert motion.name == 'a&b "q"' and motion.first_phase == "x<y"
    assert loads_xml(dumps_xml(motion)) == motion


def test_unknown_next_is_a_warning_and_ends_the_motion(caplog):
    text = ('<robot><low_skills><low_skill name="m" firstPhase="p"/></low_skills><phases>\n'
            '<phase name="p" next="nowhere"><effectors/><duration>20</duration></phase></phases></robot>')
    with caplog.at_level(logging.WARNING, logger="motions.xml_phase"):
        motion = loads_xml(text, "m.xml")
    assert motion.successor("p", requested_same_motion=True) is None
    assert len(motion.source.warnings) == 1 and "m.xml:2" in motion.source.warnings[0]
    assert "nowhere" in caplog.text


# ----------------------------------------------------------------------------------------------- errors
def _phase_file(effector_line: str = '<lle3 end="40"/>', duration: str = "300", first: str = "p",
                phase_attributes: str = "") -> str:
    return ("<robot>\n"
            "  <low_skills>\n"
            f'    <low_skill name="m" firstPhase="{first}"/>\n'
            "  </low_skills>\n"
            "  <phases>\n"
            f'    <phase name="p"{phase_attributes}>\n'
            "      <effectors>\n"
            f"        {effector_line}\n"
            "      </effectors>\n"
            f"      <duration>{duration}</duration>\n"
            "    </phase>\n"
            "  </phases>\n"
            "</robot>\n")


def _error(text: str) -> MotionFormatError:
    with pytest.raises(MotionFormatError) as info:
        loads_xml(text, "walk.xml")
    return info.value


def test_bad_number_names_path_line_field():
    error = _error(_phase_file('<lle3 end="abc"/>'))
    assert (error.path, error.line, error.field) == ("walk.xml", 8, "end")
    assert str(error) == ("walk.xml:8: field 'end' of <lle3>: expected a number or arithmetic over the constants, "
                          "got 'abc' (unknown constant 'abc' (constants: none declared))")


@pytest.mark.parametrize("bad", ["nan", "inf", "1_0", "", "0x10", "4 6"])
def test_number_syntax_is_strict(bad):
    error = _error(_phase_file(f'<lle3 end="{bad}"/>'))
    assert (error.line, error.field) == (8, "end")


def test_unknown_effector():
    error = _error(_phase_file('<lle9 end="4"/>'))
    assert (error.path, error.line, error.field) == ("walk.xml", 8, "lle9")
    assert "unknown effector <lle9>" in str(error)


def test_missing_first_phase_attribute():
    text = _phase_file().replace(' firstPhase="p"', "")
    error = _error(text)
    assert (error.path, error.line, error.field) == ("walk.xml", 3, "firstPhase")


def test_missing_low_skill():
    text = _phase_file().replace('    <low_skill name="m" firstPhase="p"/>\n', "")
    error = _error(text)
    assert (error.line, error.field) == (2, "low_skill")


def test_first_phase_naming_no_phase():
    error = _error(_phase_file(first="nowhere"))
    assert (error.path, error.line, error.field) == ("walk.xml", 3, "firstPhase")
    assert "'nowhere' names no phase" in str(error)


def test_a_phase_name_used_twice_takes_the_later_phase_with_a_warning():
    """FIIT's loader keeps phases in a map by name, so the later definition is the one its agent plays."""
    text = _phase_file().replace("  </phases>", '    <phase name="p"><effectors/><duration>1</duration></phase>\n'
                                 "  </phases>")
    motion = loads_xml(text, "walk.xml")
    assert [k.name for k in motion.keyframes] == ["p"]
    assert motion.keyframes[0].targets == {} and motion.keyframes[0].duration_s == pytest.approx(0.001)
    assert motion.source.warnings == ("walk.xml:12: phase name 'p' is already used on line 6: this later phase "
                                      "replaces it",)


@pytest.mark.parametrize(("duration", "message"), [
    ("-300", "must not be negative"), ("80.5", "whole number"), ("abc", "a number of milliseconds or arithmetic"),
    ("2*40.25", "whole number"),
])
def test_bad_durations(duration, message):
    error = _error(_phase_file(duration=duration))
    assert (error.line, error.field) == (10, "duration")
    assert message in str(error)


def test_bad_is_final():
    error = _error(_phase_file(phase_attributes=' isFinal="yes"'))
    assert (error.line, error.field) == (6, "isFinal")


def test_a_zero_duration_plays_as_one_cycle_with_a_warning():
    motion = loads_xml(_phase_file(duration="0"), "walk.xml")
    assert motion.keyframes[0].duration_s == pytest.approx(0.020)
    assert motion.source.warnings == ("walk.xml:10: phase 'p': duration 0 ms is played as one cycle (20 ms), as "
                                      "FIIT's loader plays it",)


def test_an_unknown_phase_attribute_is_a_warning_and_is_written_back():
    motion = loads_xml(_phase_file(phase_attributes=' opposite="q"'), "walk.xml")
    assert motion.keyframes[0].name == "p"
    assert "walk.xml:6: attribute opposite='q' of <phase> is not in the format" in motion.source.warnings[0]
    assert '<phase name="p" opposite="q">' in dumps_xml(motion)


def test_an_effector_listed_twice_takes_the_later_value_with_a_warning():
    """The agent sends both commands in one message and the server applies the later one."""
    motion = loads_xml(_phase_file('<lle3 end="40"/><lle4 end="-20"/>\n<lle3 end="41"/>'), "walk.xml")
    assert list(motion.keyframes[0].targets) == ["llj4", "llj3"]
    assert motion.keyframes[0].targets["llj3"].angle_rad == pytest.approx(math.radians(41.0))
    assert motion.source.warnings == ("walk.xml:9: <lle3> is listed twice in phase 'p' (first on line 8): the "
                                      "later one counts",)


def test_not_well_formed_xml_gives_line():
    error = _error(_phase_file().replace("</effectors>", "</effector>"))
    assert (error.path, error.line) == ("walk.xml", 9)
    assert "not well-formed XML" in str(error) and "mismatched tag" in str(error)


def test_doctype_is_refused():
    text = '<!DOCTYPE robot [<!ENTITY a "aaaa">]>\n' + _phase_file()
    error = _error(text)
    assert error.field == "DOCTYPE"


def test_unexpected_element_and_text():
    error = _error(_phase_file().replace("<phases>", "<phases>\n<foo/>"))
    assert (error.line, error.field) == (6, "foo")
    error = _error(_phase_file().replace("<effectors>", "<effectors>stray"))
    assert (error.line, error.field) == (7, "effectors")


def test_writer_rejects_fractional_milliseconds():
    motion = loads_xml(_phase_file())
    motion.keyframes[0] = dataclasses.replace(motion.keyframes[0], duration_s=0.0805)
    with pytest.raises(MotionFormatError) as info:
        dumps_xml(motion)
    assert info.value.field == "duration"


def test_motion_read_from_webots_is_written_with_the_canonical_xml_layout():
    from motions import loads_webots

    motion = loads_webots("#WEBOTS_MOTION,V1.0,HeadYaw\r\n00:00:100,a,0.5\r\n")
    motion.keyframes[0].next = None
    text = dumps_xml(dataclasses.replace(motion, first_phase="a"))
    assert text.startswith('<?xml version="1.0" encoding="UTF-8"?>\n<robot>\n') and "\r" not in text
