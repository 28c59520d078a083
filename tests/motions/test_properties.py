"""Round trips as properties: any motion written and read back is the same motion (both formats)."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from kinematics import robot_spec
from motions import JointTarget, Keyframe, Motion, dumps_webots, dumps_xml, loads_webots, loads_xml
from tests.motions.conftest import assert_same_motion

JOINTS = robot_spec(4).joints
# XML-safe names, including the characters that must be escaped; no whitespace (finalize text is stripped).
XML_NAME = st.text(alphabet="abcXYZ019_-.&<>\"'é", min_size=1, max_size=8)
POSE_NAME = st.text(alphabet="abcXYZ019_-.*# ", min_size=1, max_size=8)
COMMENT = st.text(alphabet="abc xyz\n:.=", max_size=30).filter(lambda c: not c.endswith("-"))


@st.composite
def xml_motions(draw: st.DrawFn) -> Motion:
    names = draw(st.lists(XML_NAME, min_size=1, max_size=5, unique=True))
    maybe_phase = st.one_of(st.none(), st.sampled_from(names), XML_NAME)
    keyframes = []
    for name in names:
        chosen = draw(st.lists(st.sampled_from(JOINTS), max_size=6, unique_by=lambda j: j.perceptor))
        targets = {j.perceptor: JointTarget(draw(st.floats(j.min_rad, j.max_rad)),
                                            draw(st.one_of(st.none(), XML_NAME))) for j in chosen}
        keyframes.append(Keyframe(
            name, draw(st.integers(1, 100_000)) / 1000.0, targets, next=draw(maybe_phase),
            finalize=draw(maybe_phase), is_final=draw(st.sampled_from([None, True, False])),
            skip_if_flag=draw(st.one_of(st.none(), XML_NAME)), set_flag_true=draw(st.one_of(st.none(), XML_NAME)),
            set_flag_false=draw(st.one_of(st.none(), XML_NAME))))
    constants = draw(st.dictionaries(XML_NAME, st.floats(allow_nan=False, allow_infinity=False), max_size=3))
    return Motion(draw(XML_NAME), keyframes, source_format="xml", first_phase=draw(st.sampled_from(names)),
                  constants=constants, header_comments=tuple(draw(st.lists(COMMENT, max_size=2))))


@st.composite
def webots_motions(draw: st.DrawFn) -> Motion:
    columns = draw(st.lists(st.sampled_from(JOINTS), min_size=1, max_size=len(JOINTS),
                            unique_by=lambda j: j.perceptor))
    # Radian values of any size a motion can hold; tiny magnitudes only make very long positional text.
    value = st.one_of(st.none(), st.floats(-10.0, 10.0).filter(lambda x: x == 0.0 or abs(x) >= 1e-12))
    keyframes = []
    for index in range(draw(st.integers(1, 6))):
        step_ms = draw(st.integers(0 if index == 0 else 1, 100_000))
        targets = {j.perceptor: JointTarget(draw(value)) for j in columns}
        keyframes.append(Keyframe(draw(POSE_NAME), step_ms / 1000.0, targets))
    return Motion(draw(XML_NAME), keyframes, source_format="webots",
                  joint_order=tuple(j.perceptor for j in columns))


@settings(max_examples=200, deadline=None)
@given(xml_motions())
def test_xml_round_trip(motion):
    text = dumps_xml(motion)
    back = loads_xml(text)
    assert_same_motion(back, motion)
    assert dumps_xml(back) == text  # writing what was read changes nothing


@settings(max_examples=200, deadline=None)
@given(webots_motions())
def test_webots_round_trip(motion):
    text = dumps_webots(motion)
    back = loads_webots(text, name=motion.name)
    assert back == motion  # Webots values are radians in the file: exact
    assert dumps_webots(back) == text


@settings(max_examples=100, deadline=None)
@given(xml_motions())
def test_mirroring_twice_is_identity(motion):
    assert motion.mirrored().mirrored() == motion


@settings(max_examples=100, deadline=None)
@given(webots_motions(), st.floats(-1.0, 2.0))
def test_pose_at_stays_between_neighbouring_keyframes(motion, fraction):
    t_s = fraction * max(motion.duration_s, 1e-3)
    pose = motion.pose_at(t_s)
    times = motion.keyframe_times_s()
    for wire, angle in pose.items():
        if angle is None:
            continue
        defined = [k.angle_rad(wire) for k in motion.keyframes if k.angle_rad(wire) is not None]
        assert min(defined) - 1e-12 <= angle <= max(defined) + 1e-12
    if t_s >= times[-1]:
        assert pose == {w: motion.keyframes[-1].angle_rad(w) for w in motion.joints()}


def test_tiny_webots_value_round_trips_exactly():
    keyframes = [Keyframe("a", 0.0, {"hj1": JointTarget(5e-324)}), Keyframe("b", 0.1, {"hj1": JointTarget(-1e-300)})]
    motion = Motion("m", keyframes, source_format="webots", joint_order=("hj1",))
    assert loads_webots(dumps_webots(motion), name="m") == motion
    assert "e" not in dumps_webots(motion).split("\n", 1)[1]


def test_xml_degree_text_is_exact_where_a_decimal_reaches_the_float():
    for degrees in (46, -7.5, 0.1, 33.333, 100, -130):
        text = dumps_xml(Motion("m", [Keyframe("p", 0.1, {"llj4": JointTarget(math.radians(degrees))})]))
        assert f'end="{degrees:g}"' in text
