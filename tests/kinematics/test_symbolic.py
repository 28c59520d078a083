"""The symbolic Nao (kinematics.symbolic): every body and site pose and the CoM of each robot type agree
with Pinocchio within 1e-9 at random joint angles, and the functions differentiate."""

from __future__ import annotations

import casadi
import numpy as np
import pytest

from kinematics.errors import SpecError
from kinematics.fk import NaoKinematics
from kinematics.spec import ROBOT_TYPES
from kinematics.symbolic import symbolic_nao


def max_difference_m(robot_type: int, samples: int = 10, seed: int = 0) -> float:
    """Largest difference of positions [m], rotation entries and CoM between the symbolic Nao and Pinocchio."""
    rng = np.random.default_rng(seed)
    symbolic, pinocchio = symbolic_nao(robot_type), NaoKinematics(robot_type)
    frames = [name for name in symbolic.frames if name in pinocchio._frame_ids]
    assert len(frames) >= len(pinocchio.spec.bodies) + 4  # every body, the soles and hands at least
    worst = 0.0
    for _ in range(samples):
        q = np.array([rng.uniform(j.min_rad, j.max_rad) for j in pinocchio.spec.joints])
        for name in frames:
            position, rotation = symbolic.pose(name)(q)
            reference = pinocchio.frame_pose(name, q)
            worst = max(worst, float(np.max(np.abs(np.array(position).ravel() - reference.position_m))),
                        float(np.max(np.abs(np.array(rotation) - reference.rotation))))
        worst = max(worst, float(np.max(np.abs(np.array(symbolic.com(q)).ravel() - pinocchio.com(q)))))
    return worst


@pytest.mark.parametrize("robot_type", ROBOT_TYPES)
def test_the_symbolic_nao_agrees_with_pinocchio(robot_type):
    assert max_difference_m(robot_type) <= 1e-9


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
