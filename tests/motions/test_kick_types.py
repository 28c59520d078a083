"""Kicks of the robot types with longer legs (motions.authoring.kick_types): the shipped type files equal the
generator's output, the ball spot follows the type's stance, per-type overrides are checked, and on our simulator
type 1's own kick sends the ball where type 0's grazed it."""

from __future__ import annotations

import math

import pytest

from agent.motion import default_library
from motion_studio.kick_rollout import Placement, run_kick
from motions import load
from motions.authoring.common import FILES_DIR
from motions.authoring.kick import kick_params
from motions.authoring.kick_types import TYPES_WITH_OWN_KICKS, type_kicks, write_type_kick_files


@pytest.mark.parametrize("robot_type", TYPES_WITH_OWN_KICKS)
def test_shipped_type_kicks_match_the_generator(tmp_path, robot_type):
    for path in write_type_kick_files(robot_type, out_root=tmp_path):
        fresh, shipped = load(path), load(FILES_DIR / f"type{robot_type}" / path.name)
        assert [k.name for k in fresh.keyframes] == [k.name for k in shipped.keyframes]
        assert fresh.constants == shipped.constants
        for a, b in zip(fresh.keyframes, shipped.keyframes):
            for wire, target in a.targets.items():
                assert b.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.05)), \
                    (path.name, a.name, wire)


def test_the_longer_legs_kick_from_their_own_spot():
    type0, type1 = default_library(0).get("kick"), default_library(1).get("kick")
    assert type1.constants != type0.constants  # the ball spot follows type 1's stance
    assert default_library(1).get("kick_left").constants["ball_left_m"] == -type1.constants["ball_left_m"]
    assert default_library(3).get("kick").constants == type0.constants  # type 3 keeps the type-0 kick


def test_an_unknown_override_key_names_the_file_and_section(tmp_path):
    overrides = tmp_path / "kick_type1.toml"
    overrides.write_text("[kick]\ncom_forward = 0.03\n")
    with pytest.raises(ValueError, match=r"kick_type1.toml \[kick\]: unknown keys \['com_forward'\]"):
        type_kicks(1, overrides_path=overrides)


def test_an_override_moves_the_kick(tmp_path):
    overrides = tmp_path / "kick_type1.toml"
    side_m = kick_params("kick").ball_side_m + 0.01
    overrides.write_text(f"[common]\nprovenance = \"a test\"\nball_side_m = {side_m}\n")
    moved, shipped = type_kicks(1, overrides_path=overrides)["kick"], default_library(1).get("kick")
    assert moved.constants["ball_left_m"] == pytest.approx(shipped.constants["ball_left_m"] - 0.01, abs=1e-4)


@pytest.mark.parametrize("offset_m", [-0.02, 0.0, 0.02])
def test_type_1_kicks_3m_from_its_spot_without_falling(offset_m):
    """With the type-0 kick file type 1 moved the ball 1.1-1.2 m from its spot on ours (0.36 m on the real
    server); its own kick goes 4.1 m here (3.86 m real)."""
    run = run_kick(default_library(1), "kick", Placement(offset_m), robot_type=1, max_s=8.0)
    assert run.distance_m >= 3.0 and abs(run.direction_error_deg) < 15.0 and not run.fell, run.figures()
