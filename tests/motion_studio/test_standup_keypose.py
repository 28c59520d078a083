"""The stand-up key pose NLP (motion_studio.standup_keypose) against the authoring SagittalSolver."""

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from motion_studio.standup_keypose import crouch_arms_rad, section_keyposes, solve_keypose
from motions.authoring.standup import SagittalSolver

ARMS = crouch_arms_rad(-60.0, 8.0)


@pytest.fixture(scope="module")
def solver():
    return SagittalSolver()


@pytest.mark.parametrize("pitch_deg, height_m, com_forward_m", [(30.0, 0.27, 0.02), (28.233, 0.301, 0.024),
                                                                (23.49, 0.298, 0.013), (15.0, 0.31, -0.01)])
def test_matched_pose_agrees_with_sagittal_solver(solver, pitch_deg, height_m, com_forward_m):
    ipopt = solve_keypose(pitch_deg, height_m, com_forward_m, ARMS)
    reference = solver.com_over_soles(pitch_deg, height_m, com_forward_m, ARMS)
    mine = ipopt.angles_rad()
    assert set(mine) >= {"llj3", "llj4", "llj5", "rlj3", "rlj4", "rlj5"}
    worst_deg = max(abs(math.degrees(mine.get(k, 0.0) - v)) for k, v in reference.items())
    assert worst_deg < 0.1
    assert np.max(np.abs(solver.kinematics.com(mine) - solver.kinematics.com(reference))) < 1e-3
    # the symbolic margin is Pinocchio's support-polygon margin
    assert ipopt.margin_m == pytest.approx(solver.com_margin_m(mine, pitch_deg), abs=1e-6)
    assert ipopt.height_m == pytest.approx(height_m, abs=1e-7) and ipopt.pitch_deg == pytest.approx(pitch_deg)


def test_max_margin_pose_beats_authored_crouch_within_bounds(solver):
    authored = solver.com_over_soles(30.0, 0.27, 0.03, ARMS)
    best = solve_keypose((20.0, 30.0), (0.26, 0.29), None, ARMS)
    assert 20.0 - 1e-6 <= best.pitch_deg <= 30.0 + 1e-6 and 0.26 - 1e-6 <= best.height_m <= 0.29 + 1e-6
    pinocchio_margin = solver.com_margin_m(best.angles_rad(), best.pitch_deg)
    assert pinocchio_margin == pytest.approx(best.margin_m, abs=1e-6)
    assert pinocchio_margin >= solver.com_margin_m(authored, 30.0) + 0.02  # authored: CoM 3 cm forward
    # the feet are flat at that lean: the sagittal solver reproduces the pose from its lean, height and CoM
    again = solver.com_over_soles(best.pitch_deg, best.height_m, best.com_forward_m, ARMS)
    assert max(abs(math.degrees(best.angles_rad()[k] - v)) for k, v in again.items()) < 0.1


def test_reference_pose_breaks_ties():
    near_a = solve_keypose((15.0, 35.0), (0.26, 0.31), None, ARMS, reference_deg=(85.0, -75.0, 25.0))
    near_b = solve_keypose((15.0, 35.0), (0.26, 0.31), None, ARMS, reference_deg=(60.0, -125.0, 65.0))
    assert near_a.margin_m == pytest.approx(near_b.margin_m, abs=1e-5)
    assert near_a.angles_deg["llj4"] > near_b.angles_deg["llj4"] + 10.0  # each stays near its reference


@pytest.mark.parametrize("kwargs, words", [({"pitch_deg": (40.0, 30.0)}, "pitch_deg"),
                                          ({"height_m": (0.3, float("nan"))}, "height_m"),
                                          ({"com_forward_m": float("nan")}, "com_forward_m"),
                                          ({"arms_rad": {"nope": 0.0}}, "nope"),
                                          ({"height_m": 0.6, "com_forward_m": 0.0}, "IPOPT")])
def test_bad_input_one_line_error(kwargs, words):
    with pytest.raises(ValueError, match=words) as error:
        solve_keypose(**kwargs)
    assert "\n" not in str(error.value)


def test_section_and_cli():
    authored, best = section_keyposes("standup_front")
    assert best.margin_m >= authored.margin_m
    from motion_studio.cli import _register_commands, app

    _register_commands()
    result = CliRunner().invoke(app, ["keypose", "standup_back", "--json"])
    assert result.exit_code == 0, result.output
    assert '"max_margin"' in result.output and '"llj4"' in result.output
    bad = CliRunner().invoke(app, ["keypose", "nope"])
    assert bad.exit_code != 0 and "unknown stand-up section" in bad.output
