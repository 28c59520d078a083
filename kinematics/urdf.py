"""URDF export of the Nao spec: for PlaCo (its RobotWrapper reads URDF only) and for other tools.

URDF puts a link's frame on the axis of the joint that moves it, so each link frame here sits at its
hinge anchor, not at the body centre; the body centre is the inertial/visual origin. The sites of the
MJCF (camera, imu, soles, hands) are massless fixed links at the same places, and those are the frames
that FK/IK address, so every library agrees on them.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from kinematics.inertia import principal_inertia
from kinematics.mjcf import site_offsets
from kinematics.spec import BodySpec, RobotSpec, robot_spec


def _num(values: np.ndarray | tuple[float, ...] | list[float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def link_origins_m(spec: RobotSpec) -> dict[str, np.ndarray]:
    """Each link's frame origin in the torso frame at zero pose: the hinge anchor (torso: its centre)."""
    origins = {"torso": np.zeros(3)}
    for joint in spec.joints:
        origins[joint.child] = np.asarray(spec.body_position_m(joint.child)) + np.asarray(joint.anchor_in_child_m)
    for body in spec.bodies:  # bodies without a hinge (none in the Nao today) would sit at their centre
        origins.setdefault(body.name, np.asarray(spec.body_position_m(body.name)))
    return origins


def _geometry(parent: ET.Element, body: BodySpec) -> None:
    geometry = ET.SubElement(parent, "geometry")
    if body.shape.kind == "box":
        ET.SubElement(geometry, "box", size=_num(body.shape.size))
    elif body.shape.kind == "sphere":
        ET.SubElement(geometry, "sphere", radius=repr(body.shape.size[0]))
    else:  # URDF has no capsule; the neck is shown as a cylinder of the full length
        radius, length = body.shape.size
        ET.SubElement(geometry, "cylinder", radius=repr(radius), length=repr(length + 2 * radius))


def robot_urdf_xml(robot_type: int = 0) -> str:
    """URDF text of one Nao type; joints named by wire perceptor names, limits and effort/velocity from the spec."""
    spec = robot_spec(robot_type)
    origins = link_origins_m(spec)
    root = ET.Element("robot", name=f"nao_type{robot_type}")
    joints_by_child = {j.child: j for j in spec.joints}
    for body in spec.bodies:
        link = ET.SubElement(root, "link", name=body.name)
        centre = np.asarray(spec.body_position_m(body.name)) - origins[body.name]
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "origin", xyz=_num(centre), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=repr(body.mass_kg))
        ixx, iyy, izz = principal_inertia(body.shape, body.mass_kg)
        ET.SubElement(inertial, "inertia", ixx=repr(ixx), ixy="0", ixz="0", iyy=repr(iyy), iyz="0", izz=repr(izz))
        for kind in ("visual",) + (("collision",) if body.collider else ()):
            element = ET.SubElement(link, kind)
            ET.SubElement(element, "origin", xyz=_num(centre), rpy="0 0 0")
            _geometry(element, body)
        if body.parent:
            joint = joints_by_child[body.name]
            element = ET.SubElement(root, "joint", name=joint.perceptor, type="revolute")
            ET.SubElement(element, "parent", link=body.parent)
            ET.SubElement(element, "child", link=body.name)
            ET.SubElement(element, "origin", xyz=_num(origins[body.name] - origins[body.parent]), rpy="0 0 0")
            ET.SubElement(element, "axis", xyz=_num(joint.axis))
            ET.SubElement(element, "limit", lower=repr(joint.min_rad), upper=repr(joint.max_rad),
                          effort=repr(joint.max_torque_nm), velocity=repr(joint.max_speed_rad_s))
    for site, (body_name, pos) in site_offsets(spec).items():
        ET.SubElement(root, "link", name=site)
        element = ET.SubElement(root, "joint", name=f"{site}_fixed", type="fixed")
        ET.SubElement(element, "parent", link=body_name)
        ET.SubElement(element, "child", link=site)
        offset = np.asarray(spec.body_position_m(body_name)) + np.asarray(pos) - origins[body_name]
        ET.SubElement(element, "origin", xyz=_num(offset), rpy="0 0 0")
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_robot_urdf(path: str | Path, robot_type: int = 0) -> Path:
    """Write the URDF of one Nao type; a directory gets ``robot.urdf`` inside (PlaCo's convention)."""
    path = Path(path)
    if path.is_dir():
        path = path / "robot.urdf"
    path.write_text(robot_urdf_xml(robot_type))
    return path
