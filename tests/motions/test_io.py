"""load/save/loads/dumps: format by extension, by content, cross-format saves, file-level errors."""

from __future__ import annotations

import pytest

from motions import ConversionError, JointTarget, Keyframe, Motion, MotionFormatError, dumps, load, loads, save
from motions.io import detect_format
from tests.motions.conftest import FIXTURES


@pytest.mark.parametrize(("name", "fmt"), [("bob_demo.xml", "xml"), ("raise_left_arm.motion", "webots")])
def test_load_picks_format_by_extension_and_save_writes_same_bytes(tmp_path, name, fmt):
    motion = load(FIXTURES / name)
    assert motion.source_format == fmt
    assert motion.source.path == str(FIXTURES / name)
    target = tmp_path / name
    save(motion, target)
    assert target.read_bytes() == (FIXTURES / name).read_bytes()


def test_unknown_extension_is_told_by_content(tmp_path):
    for name in ("bob_demo.xml", "raise_left_arm.motion"):
        copy = tmp_path / (name + ".txt")
        copy.write_bytes((FIXTURES / name).read_bytes())
        loaded, original = load(copy), load(FIXTURES / name)
        loaded.name = original.name  # a Webots motion is named after its file stem
        assert loaded == original


def test_webots_name_comes_from_the_file_stem():
    assert load(FIXTURES / "raise_left_arm.motion").name == "raise_left_arm"
    assert loads("#WEBOTS_MOTION,V1.0,HeadYaw\n0,a,1\n", name="wave").name == "wave"


def test_save_converts_by_extension(tmp_path):
    motion = load(FIXTURES / "walk_cycle.xml")
    save(motion, tmp_path / "walk_cycle.motion")
    webots = load(tmp_path / "walk_cycle.motion")
    assert webots.source_format == "webots" and len(webots.keyframes) == 3


def test_failed_save_leaves_the_existing_file_alone(tmp_path):
    target = tmp_path / "bob.motion"
    target.write_text("keep me")
    with pytest.raises(ConversionError):
        save(load(FIXTURES / "bob_demo.xml"), target)
    assert target.read_text() == "keep me"


def test_crlf_files_stay_crlf(tmp_path):
    text = "#WEBOTS_MOTION,V1.0,HeadYaw\r\n00:00:000,a,1\r\n"
    source = tmp_path / "a.motion"
    source.write_bytes(text.encode())
    save(load(source), tmp_path / "b.motion")
    assert (tmp_path / "b.motion").read_bytes() == text.encode()


def test_not_utf8_names_the_line(tmp_path):
    path = tmp_path / "bad.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,caf\xe9,1\n")
    with pytest.raises(MotionFormatError) as info:
        load(path)
    assert info.value.line == 2 and info.value.path == str(path)


def test_content_that_is_neither_format():
    with pytest.raises(MotionFormatError) as info:
        detect_format("time,pose\n1,2\n", "x.csv")
    assert (info.value.path, info.value.line, info.value.field) == ("x.csv", 1, "format")


def test_dumps_needs_a_format_for_code_built_motions():
    motion = Motion("m", [Keyframe("a", 0.1, {"hj1": JointTarget(0.1)})])
    with pytest.raises(MotionFormatError) as info:
        dumps(motion)
    assert info.value.field == "format"
    with pytest.raises(MotionFormatError):
        dumps(motion, "bvh")
