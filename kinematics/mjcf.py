"""Generates the MJCF of the Nao from the spec: the one model text that MuJoCo and Pinocchio both load.

Body frames sit at the SimSpark body centres, axis-aligned with the torso at zero pose, so MuJoCo body
poses equal SimSpark ObjectState poses; hinges sit at the rsg anchors. Inertials are explicit (uniform
density of each shape), so no library recomputes them from geoms differently. The text is written here
with full double precision (``repr``), because ``MjSpec.to_xml`` rounds to 6 significant digits and the
type 3/4 offsets have 9; ``mujoco.MjSpec.from_string`` turns it into the MjSpec that sim/ builds on.
"""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING

from kinematics.inertia import principal_inertia
from kinematics.spec import BodySpec, RobotSpec, Shape, robot_spec

if TYPE_CHECKING:
    import mujoco

CAMERA_SITE = "camera"
TORSO_SITE = "imu"
STANDING_TORSO_HEIGHT_M = 0.385  # type 0/2/4 torso centre above the sole at zero pose (REFERENCE §2.1)


def site_offsets(spec: RobotSpec) -> dict[str, tuple[str, tuple[float, float, float]]]:
    """Site name -> (body, position in the body frame in m): camera, IMU, sole centres, hand tips."""
    foot_half_height = spec.body("lfoot").shape.size[2] / 2.0
    hand_half_length = spec.body("llowerarm").shape.size[1] / 2.0
    return {
        CAMERA_SITE: ("head", (0.0, 0.0, 0.0)),
        TORSO_SITE: ("torso", (0.0, 0.0, 0.0)),
        "lsole": ("lfoot", (0.0, 0.0, -foot_half_height)),
        "rsole": ("rfoot", (0.0, 0.0, -foot_half_height)),
        "lhand": ("llowerarm", (0.0, hand_half_length, 0.0)),
        "rhand": ("rlowerarm", (0.0, hand_half_length, 0.0)),
    }


def collider_body_pairs(spec: RobotSpec) -> list[tuple[str, str]]:
    """Pairs of collider bodies of one robot; SimSpark disables collisions between a robot's own parts."""
    colliders = [b.name for b in spec.bodies if b.collider]
    return list(itertools.combinations(colliders, 2))


def _num(values: tuple[float, ...] | list[float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def _geom_attributes(shape: Shape) -> dict[str, str]:
    """MuJoCo sizes are half extents for boxes and half lengths for capsules."""
    if shape.kind == "box":
        return {"type": "box", "size": _num([s / 2.0 for s in shape.size])}
    if shape.kind == "sphere":
        return {"type": "sphere", "size": _num([shape.size[0]])}
    if shape.kind == "capsule":
        return {"type": "capsule", "size": _num([shape.size[0], shape.size[1] / 2.0])}
    raise ValueError(f"unknown shape kind {shape.kind!r}")


def _body_element(parent: ET.Element, body: BodySpec, pos: tuple[float, float, float]) -> ET.Element:
    element = ET.SubElement(parent, "body", name=body.name, pos=_num(pos))
    ET.SubElement(element, "inertial", pos="0 0 0", mass=repr(body.mass_kg),
                  diaginertia=_num(principal_inertia(body.shape, body.mass_kg)))
    return element


def robot_mjcf_xml(robot_type: int = 0, free: bool = True,
                   torso_pos_m: tuple[float, float, float] | None = None,
                   floor: bool = False) -> str:
    """The MJCF text of one Nao (names: bodies and sites as the spec, hinges by wire name, free joint ``root``).

    Collider geoms: group 0, contype = conaffinity = 1. Collider-less bodies get display geoms in group 1
    with no contacts. Own parts never collide (pairwise ``exclude``), as in SimSpark.

    Args:
        robot_type: 0-4.
        free: give the torso a free joint (False: torso welded to the world, e.g. for previews).
        torso_pos_m: torso centre in the world at zero pose; None = standing on z = 0 (0, 0, 0.385 for type 0).
        floor: add a ground plane at z = 0.
    """
    spec = robot_spec(robot_type)
    if torso_pos_m is None:
        torso_pos_m = (0.0, 0.0, -spec.sole_z_m)
    root = ET.Element("mujoco", model=f"nao_type{robot_type}")
    ET.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true")
    worldbody = ET.SubElement(root, "worldbody")
    if floor:
        ET.SubElement(worldbody, "geom", name="floor", type="plane", size="5 5 0.1")
    elements: dict[str, ET.Element] = {}
    joints_by_child = {j.child: j for j in spec.joints}
    sites_by_body: dict[str, list[tuple[str, tuple[float, float, float]]]] = {}
    for site, (body_name, pos) in site_offsets(spec).items():
        sites_by_body.setdefault(body_name, []).append((site, pos))
    for body in spec.bodies:
        if body.parent:
            element = _body_element(elements[body.parent], body, body.offset_m)
        else:
            element = _body_element(worldbody, body, torso_pos_m)
            if free:
                ET.SubElement(element, "freejoint", name="root")
        joint = joints_by_child.get(body.name)
        if joint is not None:
            ET.SubElement(element, "joint", name=joint.perceptor, type="hinge", pos=_num(joint.anchor_in_child_m),
                          axis=_num(joint.axis), range=_num((joint.min_rad, joint.max_rad)))
        contact = {"contype": "1", "conaffinity": "1", "group": "0"} if body.collider else \
            {"contype": "0", "conaffinity": "0", "group": "1"}
        ET.SubElement(element, "geom", name=body.name, mass="0", **_geom_attributes(body.shape), **contact)
        for site, pos in sites_by_body.get(body.name, []):
            ET.SubElement(element, "site", name=site, pos=_num(pos), size="0.005")
        elements[body.name] = element
    contact = ET.SubElement(root, "contact")
    for first, second in collider_body_pairs(spec):
        ET.SubElement(contact, "exclude", body1=first, body2=second)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def build_robot_mjspec(robot_type: int = 0, free: bool = True, floor: bool = False) -> "mujoco.MjSpec":
    """The MjSpec of one Nao, parsed from :func:`robot_mjcf_xml` (sim/ attaches these into its world).

    MuJoCo is imported here only: the agent generates the same text for Pinocchio without MuJoCo.
    """
    import mujoco

    return mujoco.MjSpec.from_string(robot_mjcf_xml(robot_type, free=free, floor=floor))


def write_robot_mjcf(path: str | Path, robot_type: int = 0, free: bool = True) -> Path:
    """Write the MJCF of one Nao to ``path`` and return the path."""
    path = Path(path)
    path.write_text(robot_mjcf_xml(robot_type, free=free))
    return path
