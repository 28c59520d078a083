"""`motion-studio play --start`: stand-ups are played from lying, judged by whether the robot got up."""

from __future__ import annotations

from pathlib import Path

import motions
from motion_studio.play import default_start, play_motion

FILES = Path(__file__).resolve().parents[2] / "motions" / "files"


def test_default_start_lies_down_for_standups_only():
    assert default_start(Path("motions/files/standup_back.xml")) == "back"
    assert default_start(Path("type4/standup_front.xml")) == "front"
    assert default_start(Path("roll_to_back.xml")) == "standing"
    assert default_start(Path("walk_forward.xml")) == "standing"


def test_standup_back_gets_up_from_lying_and_standing_still_does_not():
    standup = play_motion(motions.load(FILES / "standup_back.xml"), start="back")
    assert standup.start == "back"
    assert standup.torso_height_m[0] < 0.15  # it really started on the ground
    assert not standup.fell and standup.torso_height_m[-1] > 0.25
    lying_still = play_motion(motions.load(FILES / "stand.xml"), start="back")
    assert lying_still.fell  # a motion that does not get up is judged down
