"""The symbolic Nao (kinematics.symbolic): every body and site pose and the CoM of each robot type agree
with Pinocchio within 1e-9 at random joint angles, and the functions differentiate."""

from __future__ import annotations

import casadi
import numpy as np
import pytest

from kinematics.errors import SpecError
from kinematics.fk import NaoKinematics
from kinematics.spec import ROBOT_TYPES
from kinematics.symbolic import pinocchio_max_diff_m, symbolic_nao


def test_the_symbolic_nao_has_every_body_and_the_soles_and_hands():
    symbolic, pinocchio = symbolic_nao(0), NaoKinematics(0)
    frames = [name for name in symbolic.frames if name in pinocchio._frame_ids]
    assert len(frames) >= len(pinocchio.spec.bodies) + 4
    assert {"lsole", "rsole", "lhand", "rhand"} <= set(frames)


@pytest.mark.parametrize("robot_type", ROBOT_TYPES)
def test_the_symbolic_nao_agrees_with_pinocchio(robot_type):
    assert pinocchio_max_diff_m(robot_type) <= 1e-9


def test_the_sole_height_differentiates_like_a_finite_difference():
    nao = symbolic_nao(0)
    q = casadi.SX.sym("q", len(nao.joint_names))
    height = nao.pose("lsole")(q)[0][2]
    gradient = casadi.Function("gradient", [q], [casadi.gradient(height, q)])
    q0 = np.full(len(nao.joint_names), 0.1)
    step = 1e-6
    knee = nao.joint_names.index("llj4")
    bumped = q0.copy()
    bumped[knee] += step
    numeric = (float(nao.pose("lsole")(bumped)[0][2]) - float(nao.pose("lsole")(q0)[0][2])) / step
    assert float(gradient(q0)[knee]) == pytest.approx(numeric, rel=1e-4)
    assert abs(numeric) > 1e-3  # the knee does move the sole


def test_an_unknown_frame_lists_the_known_ones():
    with pytest.raises(SpecError, match="unknown frame 'toe'.*lsole"):
        symbolic_nao(0).pose("toe")
