"""Motion files as other tools write them: a UTF-8 byte-order mark and CRLF line ends (Windows editors),
no newline at the end, in both formats."""

import math

import pytest

import motions
from motions.errors import MotionFormatError

WEBOTS = ("#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch,LShoulderPitch\r\n"
          "00:00:000,Pose1,0,0,1.5\r\n"
          "00:00:500,Pose2,0.2,*,1.2\r\n")
XML = ('<?xml version="1.0" encoding="UTF-8"?>\r\n<robot>\r\n'
       '<low_skills><low_skill name="a" firstPhase="p"/></low_skills>\r\n'
       '<phases><phase name="p"><effectors><he1 end="10"/></effectors><duration>200</duration></phase></phases>'
       '</robot>')


@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
def test_a_webots_file_from_windows_reads_like_the_plain_one(tmp_path, bom):
    path = tmp_path / "Wave.motion"
    path.write_bytes(bom + WEBOTS.encode())
    motion = motions.load(path)
    assert [k.name for k in motion.keyframes] == ["Pose1", "Pose2"]
    assert motion.keyframes[1].duration_s == pytest.approx(0.5)
    assert motion.keyframes[1].targets["hj1"].angle_rad == pytest.approx(0.2)
    assert motion.keyframes[1].targets["hj2"].angle_rad is None  # "*": the joint is not commanded


@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
def test_an_xml_file_from_windows_reads_like_the_plain_one(tmp_path, bom):
    path = tmp_path / "nod.xml"
    path.write_bytes(bom + XML.encode())
    motion = motions.load(path)
    assert motion.keyframes[0].targets["hj1"].angle_rad == pytest.approx(math.radians(10.0))
    assert motion.keyframes[0].duration_s == pytest.approx(0.2)


def test_a_mark_in_the_middle_of_a_file_is_still_an_error(tmp_path):
    path = tmp_path / "bad.motion"
    path.write_bytes(WEBOTS.replace("Pose2", "\ufeffPose2").encode() + b"00:00:600,Pose3,x,0,0\n")
    with pytest.raises(MotionFormatError) as error:
        motions.load(path)
    assert ":4" in str(error.value) or "line 4" in str(error.value)
