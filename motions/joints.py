"""Joint tables the motion formats need: every hinge of any robot type, looked up by the name each format uses.

XML phase files name joints by effector (``lle3``), Webots files by conventional Nao name (``LHipPitch``), the
model by wire perceptor name (``llj3``). The readers accept the hinges of every robot type (type 4 adds the
toes ``llj7``/``rlj7``); whether a motion fits one robot type is checked by ``Motion.validate(robot_type)``.
"""

from __future__ import annotations

from collections.abc import Iterable

from kinematics import JointSpec, robot_spec

# Robot type 4 has the 22 common hinges plus the toes, in the canonical order (toes after each ankle roll).
_ALL_JOINTS: tuple[JointSpec, ...] = robot_spec(4).joints
_BY_WIRE: dict[str, JointSpec] = {j.perceptor: j for j in _ALL_JOINTS}
_BY_EFFECTOR: dict[str, JointSpec] = {j.effector: j for j in _ALL_JOINTS}
_BY_NAO: dict[str, JointSpec] = {j.nao_name: j for j in _ALL_JOINTS}

CANONICAL_JOINT_ORDER: tuple[str, ...] = tuple(j.perceptor for j in _ALL_JOINTS)
"""Wire names of every known hinge in canonical order; writers use it when a motion gives no order."""


def joint_by_wire(name: str) -> JointSpec | None:
    """The hinge whose wire perceptor name is ``name`` (``llj3``), None if there is none."""
    return _BY_WIRE.get(name)


def joint_by_effector(name: str) -> JointSpec | None:
    """The hinge whose effector name is ``name`` (``lle3``), as XML phase files name joints; None if none."""
    return _BY_EFFECTOR.get(name)


def joint_by_nao_name(name: str) -> JointSpec | None:
    """The hinge whose conventional Nao name is ``name`` (``LHipPitch``), as Webots files name joints."""
    return _BY_NAO.get(name)


def known_effector_names() -> tuple[str, ...]:
    """Effector names in canonical order, for error messages that list what is allowed."""
    return tuple(j.effector for j in _ALL_JOINTS)


def canonical_sorted(wire_names: Iterable[str]) -> list[str]:
    """Known wire names in canonical order (head, left arm, left leg, right leg, right arm); unknown last."""
    rank = {name: i for i, name in enumerate(CANONICAL_JOINT_ORDER)}
    return sorted(set(wire_names), key=lambda n: (rank.get(n, len(rank)), n))
