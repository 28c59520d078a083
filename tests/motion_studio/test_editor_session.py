"""The editor's core without a browser: session edits, undo/redo, mirror, reorder, IK handles, saving."""

import math
from pathlib import Path

import numpy as np
import pytest

import motions
from motion_studio.editor import EditorError, EditorSession
from motion_studio.editor.api import EditorTab, Workspace
from motion_studio.editor.scene import BufferedWindow

# A hand-written XML phase motion: a crouch, a left-leg lift and a lowering that cycles back to the crouch.
TEST_XML = """<?xml version="1.0" encoding="UTF-8"?>
<!-- editor test motion, written by hand -->
<robot>
\t<low_skills>
\t\t<low_skill name="editor_test" firstPhase="crouch" />
\t</low_skills>

\t<phases>
\t\t<phase name="crouch" next="lift">
\t\t\t<effectors>
\t\t\t\t<lle3 end="30" />
\t\t\t\t<lle4 end="-60" />
\t\t\t\t<lle5 end="30" />
\t\t\t\t<rle3 end="30" />
\t\t\t\t<rle4 end="-60" />
\t\t\t\t<rle5 end="30" />
\t\t\t</effectors>
\t\t\t<duration>400</duration>
\t\t</phase>
\t\t<phase name="lift" next="lower">
\t\t\t<effectors>
\t\t\t\t<lae1 end="-80" />
\t\t\t\t<lle3 end="45" />
\t\t\t\t<lle4 end="-90" />
\t\t\t</effectors>
\t\t\t<duration>300</duration>
\t\t</phase>
\t\t<phase name="lower" next="crouch" isFinal="true">
\t\t\t<effectors>
\t\t\t\t<lle3 end="30" />
\t\t\t\t<lle4 end="-60" />
\t\t\t</effectors>
\t\t\t<duration>300</duration>
\t\t\t<finalize>lower</finalize>
\t\t</phase>
\t</phases>
</robot>
"""

TEST_WEBOTS = """#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll,RShoulderPitch,RShoulderRoll
00:00:000,Pose1,1.5,0.1,1.5,-0.1
00:00:400,Pose2,0,0.3,1.5,-0.1
00:00:800,Pose3,-1.2,0.1,*,*
"""


@pytest.fixture
def xml_file(tmp_path: Path) -> Path:
    path = tmp_path / "editor_test.xml"
    path.write_text(TEST_XML)
    return path


@pytest.fixture
def webots_file(tmp_path: Path) -> Path:
    path = tmp_path / "arms.motion"
    path.write_text(TEST_WEBOTS)
    return path


def deg(session: EditorSession, index: int, joint: str) -> float:
    return round(math.degrees(session.keyframe_pose(index)[joint]), 6)


# ------------------------------------------------------------------------------------------------ undo/redo
def test_a_slider_drag_is_one_undo_step_and_undo_back_to_saved_is_clean(xml_file):
    session = EditorSession.open(xml_file)
    assert not session.dirty and not session.can_undo
    for value in (31.0, 33.5, 35.5):  # one drag: same gesture key
        session.set_joint(0, "llj3", math.radians(value), merge_key="drag-1")
    session.set_joint(0, "lle4", math.radians(-70), merge_key="drag-2")  # effector names work too
    assert deg(session, 0, "llj3") == 35.5 and deg(session, 0, "llj4") == -70
    assert session.dirty
    session.undo()
    assert deg(session, 0, "llj3") == 35.5 and deg(session, 0, "llj4") == -60
    session.undo()
    assert deg(session, 0, "llj3") == 30 and not session.dirty and not session.can_undo
    session.redo()
    assert deg(session, 0, "llj3") == 35.5 and session.dirty
    session.redo()
    assert deg(session, 0, "llj4") == -70 and not session.can_redo
    session.undo()
    session.set_joint(1, "hj1", 0.2)  # a new edit drops the redo branch
    assert not session.can_redo
    with pytest.raises(EditorError, match="nothing to redo"):
        session.redo()


def test_unlisted_joints_hold_and_setting_one_lists_it_in_canonical_order(xml_file):
    session = EditorSession.open(xml_file)
    assert deg(session, 1, "rlj3") == 30  # held from the crouch
    assert "rlj3" not in session.listed_joints(1)
    session.set_joint(1, "rlj3", math.radians(40))
    assert list(session.motion.keyframes[1].targets) == ["laj1", "llj3", "llj4", "rlj3"]
    session.clear_joint(1, "rlj3")
    assert deg(session, 1, "rlj3") == 30 and "rlj3" not in session.listed_joints(1)


def test_bad_edits_are_refused_without_changing_anything(xml_file):
    session = EditorSession.open(xml_file)
    before = motions.dumps(session.motion)
    with pytest.raises(EditorError, match="outside its limits"):
        session.set_joint(0, "llj4", math.radians(5))  # LKneePitch stops at 1 deg
    with pytest.raises(EditorError, match="llj9"):
        session.set_joint(0, "llj9", 0.1)
    with pytest.raises(EditorError, match="finite"):
        session.set_joint(0, "llj3", float("nan"))
    with pytest.raises(EditorError, match="index"):
        session.set_joint(7, "llj3", 0.1)
    with pytest.raises(EditorError, match="at least 1 ms"):
        session.set_duration(1, 0.0)
    with pytest.raises(EditorError, match="already used"):
        session.rename(1, "crouch")
    assert motions.dumps(session.motion) == before and not session.can_undo and not session.dirty


# ------------------------------------------------------------------------------------------------ mirror
def test_mirror_keyframe_moves_targets_to_the_other_side_and_twice_gives_it_back(xml_file):
    session = EditorSession.open(xml_file)
    original = session.motion.keyframes[1].targets.copy()
    session.mirror_keyframe(1)
    mirrored = {name: round(math.degrees(t.angle_rad), 6) for name, t in session.motion.keyframes[1].targets.items()}
    # Pitch joints keep their sign (REFERENCE §2.2 axes along x), sides swap.
    assert mirrored == {"raj1": -80, "rlj3": 45, "rlj4": -90}
    assert deg(session, 1, "llj3") == 30  # the left leg now holds the crouch
    session.mirror_keyframe(1)
    assert session.motion.keyframes[1].targets == original


def test_mirror_of_roll_joints_flips_the_sign_and_mirror_motion_keeps_the_file_header(xml_file, tmp_path):
    session = EditorSession.open(xml_file)
    session.set_joint(0, "llj2", math.radians(10))   # LHipRoll +10 -> RHipRoll -10
    session.mirror_motion()
    assert deg(session, 0, "rlj2") == -10 and deg(session, 0, "llj2") == 0
    session.save_as(tmp_path / "mirrored.xml")
    text = (tmp_path / "mirrored.xml").read_text()
    assert text.startswith('<?xml version="1.0" encoding="UTF-8"?>\n<!-- editor test motion, written by hand -->')
    assert '<rle2 end="-10" />' in text


# ------------------------------------------------------------------------------------------------ reorder
def test_reorder_add_duplicate_delete_keep_a_linear_xml_chain_playing_in_list_order(xml_file, tmp_path):
    session = EditorSession.open(xml_file)
    session.move_keyframe(2, 0)  # lower, crouch, lift; the cycle back to the start follows the new start
    motion = session.motion
    assert [k.name for k in motion.keyframes] == ["lower", "crouch", "lift"]
    assert motion.first_phase == "lower"
    assert [k.next for k in motion.keyframes] == ["crouch", "lift", "lower"]
    assert session.keyframe_times_s() == pytest.approx([0.3, 0.7, 1.0])
    index = session.duplicate_keyframe(1)
    assert index == 2 and motion.keyframes[2].name == "crouch2"
    assert motion.keyframes[2].targets == motion.keyframes[1].targets
    added = session.add_keyframe(0)
    assert added == 1 and motion.keyframes[1].targets == {} and motion.keyframes[1].duration_s == 0.5
    assert [k.name for k in motion.keyframes] == ["lower", "lower2", "crouch", "crouch2", "lift"]
    assert [k.next for k in motion.keyframes] == ["lower2", "crouch", "crouch2", "lift", "lower"]
    session.delete_keyframe(0)
    assert motion.first_phase == "lower2" and motion.keyframes[-1].next == "lower2"
    assert session.selected == 0
    # The result is a valid file that reads back the same.
    session.save_as(tmp_path / "reordered.xml")
    again = motions.load(tmp_path / "reordered.xml")
    assert [k.name for k in again.keyframes] == [k.name for k in motion.keyframes]
    assert [k.next for k in again.play_order()] == ["crouch", "crouch2", "lift", "lower2"]
    for _ in range(3):
        session.undo()
    assert [k.name for k in session.motion.keyframes] == ["lower", "crouch", "lift"]
    session.undo()
    # Back to the first file's content, which is not what the session's file (reordered.xml) now holds.
    assert [k.name for k in session.motion.keyframes] == ["crouch", "lift", "lower"] and session.dirty


def test_reorder_of_webots_poses_moves_durations_and_keeps_time_zero_first(webots_file):
    session = EditorSession.open(webots_file)
    assert session.keyframe_times_s() == pytest.approx([0.0, 0.4, 0.8])
    session.move_keyframe(0, 2)  # the time-0 pose cannot stay at duration 0 once it is not first
    assert [k.name for k in session.motion.keyframes] == ["Pose2", "Pose3", "Pose1"]
    assert session.keyframe_times_s() == pytest.approx([0.4, 0.8, 1.3])
    text = motions.dumps(session.motion)
    assert text.splitlines()[1:] == ["00:00:400,Pose2,0,0.3,1.5,-0.1", "00:00:800,Pose3,-1.2,0.1,*,*",
                                     "00:01:300,Pose1,1.5,0.1,1.5,-0.1"]
    with pytest.raises(EditorError, match="XML"):
        session.set_links(0, "Pose3", None)
    session.add_keyframe(1)  # repeats Pose3 as it is: its '*' stays '*' (not commanded)
    assert motions.dumps(session.motion).splitlines()[3] == "00:01:300,Pose4,-1.2,0.1,*,*"


def test_a_new_file_starts_at_the_zero_pose_and_is_written_on_the_first_save(tmp_path):
    path = tmp_path / "new_kick.motion"
    session = EditorSession.open(path)
    assert session.dirty and session.format == "webots" and not path.exists()
    assert set(session.keyframe_pose(0).values()) == {0.0}
    session.add_keyframe()
    session.set_joint(1, "raj1", math.radians(-45))
    assert session.save() is None
    saved = motions.load(path)
    assert [k.name for k in saved.keyframes] == ["Pose1", "Pose2"]
    assert saved.keyframes[1].angle_rad("raj1") == pytest.approx(math.radians(-45), abs=1e-4)
    assert not session.dirty
    with pytest.raises(EditorError, match="extension"):
        EditorSession.open(tmp_path / "notes.txt")


# ------------------------------------------------------------------------------------------------ files
def test_a_file_that_does_not_parse_opens_nothing_and_names_its_line(tmp_path):
    path = tmp_path / "broken.xml"
    path.write_text(TEST_XML.replace('<lle4 end="-90" />', '<lle4 end="-9O" />'))
    with pytest.raises(motions.MotionFormatError) as caught:
        EditorSession.open(path)
    assert caught.value.line == 24 and caught.value.field == "end"


def test_two_sessions_on_one_file_last_save_wins_with_a_warning(xml_file):
    first, second = EditorSession.open(xml_file), EditorSession.open(xml_file)
    first.set_joint(0, "llj3", math.radians(20))
    second.set_joint(0, "rlj3", math.radians(25))
    assert first.save() is None
    warning = second.save()
    assert warning is not None and "changed on disk" in warning and "last save wins" in warning
    text = xml_file.read_text()
    assert '<rle3 end="25" />' in text and '<lle3 end="30" />' in text  # the second version, whole
    assert second.save() is None  # its own save is no conflict
    assert not list(xml_file.parent.glob(".*.tmp"))  # no temporary files left


def test_save_as_converts_and_refuses_to_overwrite_silently(xml_file, tmp_path):
    session = EditorSession.open(xml_file)
    target = tmp_path / "editor_test.motion"
    with pytest.raises(motions.ConversionError, match="unroll_cycle"):
        session.save_as(target)  # the XML cycles back to the crouch: Webots cannot loop
    assert not target.exists()
    session.save_as(target, lossy=True)
    assert session.format == "webots" and session.path == target and not session.dirty
    assert motions.load(target).keyframes[1].angle_rad("llj3") == pytest.approx(math.radians(45))
    other = tmp_path / "other.xml"
    other.write_text(TEST_XML)
    with pytest.raises(EditorError, match="exists"):
        session.save_as(other)
    assert session.save_as(other, overwrite=True) is None and motions.load(other).source_format == "xml"


# ------------------------------------------------------------------------------------------------ IK handles
@pytest.fixture
def tab(xml_file) -> EditorTab:
    workspace = Workspace(xml_file)
    return workspace.open_tab(BufferedWindow(), lambda event: None)


def test_ik_handle_moves_the_foot_and_keeps_the_other_handles(tab):
    state = tab.handle({"op": "select", "index": 0})["state"]
    lfoot = np.array(state["handles"]["lfoot"]["position_m"])
    target = lfoot + [0.0, 0.01, 0.02]
    reply = tab.handle({"op": "ik", "index": 0, "handle": "lfoot", "position_m": target.tolist()})
    assert reply["ok"], reply
    assert set(reply["changed"]) <= {"llj1", "llj2", "llj3", "llj4", "llj5", "llj6"}
    after = reply["state"]["handles"]
    assert np.allclose(after["lfoot"]["position_m"], target, atol=1.5e-3)
    for other in ("rfoot", "torso", "lhand", "rhand"):
        assert np.allclose(after[other]["position_m"], state["handles"][other]["position_m"], atol=1.5e-3), other
    assert tab.session.can_undo


def test_an_unreachable_ik_target_reports_the_error_and_leaves_the_pose(tab):
    state = tab.handle({"op": "select", "index": 0})["state"]
    before = motions.dumps(tab.session.motion)
    lfoot = state["handles"]["lfoot"]["position_m"]
    reply = tab.handle({"op": "ik", "index": 0, "handle": "lfoot", "position_m": [lfoot[0], lfoot[1], 0.6]})
    assert not reply["ok"]
    assert reply["error"]["kind"] == "IKError" and reply["error"]["task"].startswith("lfoot")
    assert "lfoot" in reply["error"]["message"] and reply["error"]["residual"] > 0.1
    assert motions.dumps(tab.session.motion) == before
    assert not tab.session.can_undo and not tab.session.dirty
    assert reply["state"]["pose_deg"] == state["pose_deg"]
    # The scene got the handles back at the unchanged pose.
    assert tab.window.flush() is not None


def test_balance_reports_the_com_over_the_support_polygon(tab):
    state = tab.handle({"op": "select", "index": 0})["state"]
    assert state["balance"]["inside"] and state["balance"]["margin_m"] > 0.02
    # Leaning the standing crouch far back with both ankles puts the CoM behind the heels.
    for joint in ("llj5", "rlj5"):
        tab.handle({"op": "set_joint", "index": 0, "joint": joint, "angle_deg": -45})
    for joint in ("llj3", "rlj3"):
        tab.handle({"op": "set_joint", "index": 0, "joint": joint, "angle_deg": -25})
    state = tab.handle({"op": "state"})["state"]
    assert not state["balance"]["inside"] and state["balance"]["margin_m"] < 0


def test_requests_with_bad_values_answer_with_the_field_and_change_nothing(tab):
    for request, field in (({"op": "set_joint", "index": 0, "joint": "llj3", "angle_deg": "x"}, "angle_deg"),
                           ({"op": "set_joint", "index": 0, "joint": "llj3", "angle_deg": 200}, "angle"),
                           ({"op": "ik", "handle": "nose", "position_m": [0, 0, 0]}, "handle"),
                           ({"op": "move", "index": 0, "to": "last"}, "to"),
                           ({"op": "fly"}, "op")):
        reply = tab.handle(request)
        assert not reply["ok"] and reply["error"]["field"] == field, (request, reply)
    assert not tab.session.dirty
