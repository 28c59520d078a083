"""The self-collision rule (REFERENCE §4.5, foul type 7): overlapping box colliders of one robot freeze joints.

The overlap test is the server's BoxCollider::CheckCollisions, reproduced on purpose with its quirk: the
15 separating-axis candidates are not normalised and the 0.04 m tolerance is added to the projection of
the centre offset, so a cross-product axis of two (nearly) parallel box axes always "separates". In
practice a pair is reported only when the boxes are turned against each other about every axis.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from kinematics.spec import robot_spec

#: Body pose: centre [m] and row-major 3x3 rotation (columns = body x, y, z axes in the world).
Pose = tuple[tuple[float, float, float], tuple[float, ...]]

# Pairs the rsg exempts with addNotCollideWithColliderName (side prefix added per leg).
_EXEMPT_SUFFIXES = (("thigh", "torso"), ("shank", "thigh"), ("foot", "shank"), ("toe", "foot"))


@dataclass(frozen=True)
class BoxColliderSpec:
    """One box collider of the Nao: body name, full size [m], effectors frozen when it collides."""

    body: str
    size_m: tuple[float, float, float]
    freeze_effectors: tuple[str, ...]


@lru_cache(maxsize=None)
def box_colliders(robot_type: int) -> tuple[BoxColliderSpec, ...]:
    """The robot's box colliders in scene order (torso, arms, legs) with their freeze lists."""
    spec = robot_spec(robot_type)
    boxes = []
    for body in spec.bodies:
        if not body.collider or body.shape.kind != "box":
            continue
        name = body.name
        if name == "torso":
            effectors: tuple[str, ...] = ()
        elif name.endswith(("upperarm", "lowerarm")):
            effectors = tuple(f"{name[0]}ae{i}" for i in range(1, 5))
        else:
            count = 7 if robot_type == 4 else 6
            effectors = tuple(f"{name[0]}le{i}" for i in range(1, count + 1))
        boxes.append(BoxColliderSpec(name, tuple(body.shape.size), effectors))  # type: ignore[arg-type]
    return tuple(boxes)


def _exempt(a: str, b: str) -> bool:
    for child, parent in _EXEMPT_SUFFIXES:
        for x, y in ((a, b), (b, a)):
            if x.endswith(child) and (y == parent or (y.endswith(parent) and y[0] == x[0])):
                return True
    return False


def boxes_overlap(pose_a: Pose, size_a: tuple[float, ...], pose_b: Pose, size_b: tuple[float, ...],
                  tolerance_m: float) -> bool:
    """The server's box-box test: True when no candidate axis separates the boxes by the tolerance."""
    rotations = np.stack([np.asarray(pose_a[1], float).reshape(3, 3), np.asarray(pose_b[1], float).reshape(3, 3)])
    offset = np.asarray(pose_b[0], float) - np.asarray(pose_a[0], float)
    return bool(_overlaps(rotations[None, 0], rotations[None, 1], np.asarray(size_a, float)[None] / 2.0,
                          np.asarray(size_b, float)[None] / 2.0, offset[None], tolerance_m)[0])


def _overlaps(ra: np.ndarray, rb: np.ndarray, half_a: np.ndarray, half_b: np.ndarray, offset: np.ndarray,
              tolerance_m: float) -> np.ndarray:
    """Vectorised server test for P pairs: rotations (P, 3, 3), half sizes (P, 3), offsets b - a (P, 3)."""
    axes_a = np.swapaxes(ra, 1, 2)  # (P, 3 axes, 3 coords)
    axes_b = np.swapaxes(rb, 1, 2)
    cross = np.cross(axes_a[:, :, None, :], axes_b[:, None, :, :]).reshape(-1, 9, 3)
    planes = np.concatenate([axes_a, axes_b, cross], axis=1)  # (P, 15, 3)
    reach = (np.abs(np.einsum("pkc,pic->pki", planes, axes_a)) @ half_a[:, :, None])[..., 0] + \
        (np.abs(np.einsum("pkc,pic->pki", planes, axes_b)) @ half_b[:, :, None])[..., 0]
    along = np.abs(np.einsum("pkc,pc->pk", planes, offset))
    return ~np.any(along + tolerance_m > reach, axis=1)


@lru_cache(maxsize=None)
def _pair_table(robot_type: int) -> tuple[tuple[BoxColliderSpec, ...], np.ndarray, np.ndarray, np.ndarray,
                                          np.ndarray]:
    """Non-exempt pairs (i, j) of the robot's boxes, their half sizes and bounding-sphere radius sums."""
    boxes = box_colliders(robot_type)
    pairs = [(i, j) for i in range(len(boxes)) for j in range(i + 1, len(boxes))
             if not _exempt(boxes[i].body, boxes[j].body)]
    first = np.array([i for i, _ in pairs], dtype=np.intp)
    second = np.array([j for _, j in pairs], dtype=np.intp)
    half = np.array([box.size_m for box in boxes], dtype=float) / 2.0
    radius = np.linalg.norm(half, axis=1)
    return boxes, first, second, half, radius[first] + radius[second]


def colliding_pairs(robot_type: int, poses: Mapping[str, Pose], tolerance_m: float) -> list[tuple[
        BoxColliderSpec, BoxColliderSpec]]:
    """Pairs of one robot's box colliders that overlap (exempt pairs skipped).

    Boxes whose bounding spheres are apart are skipped first: disjoint boxes have a separating unit axis,
    and the server's shorter (unnormalised) axes only separate more easily, so the result is unchanged.
    """
    boxes, first, second, half, reach = _pair_table(robot_type)
    if any(box.body not in poses for box in boxes):
        return []
    centres = np.array([poses[box.body][0] for box in boxes], dtype=float)
    rotations = np.array([poses[box.body][1] for box in boxes], dtype=float).reshape(-1, 3, 3)
    offset = centres[second] - centres[first]
    near = np.nonzero(np.linalg.norm(offset, axis=1) <= reach)[0]
    if near.size == 0:
        return []
    i, j = first[near], second[near]
    hits = _overlaps(rotations[i], rotations[j], half[i], half[j], offset[near], tolerance_m)
    return [(boxes[a], boxes[b]) for a, b, hit in zip(i, j, hits) if hit]


class SelfCollisionRule:
    """Freeze bookkeeping: a joint frozen at t is not frozen again before t + frozen + thaw time.

    Args:
        tolerance_m, frozen_time_s, thaw_time_s: REFERENCE §4.5 (0.04 m, 1.0 s, 2.0 s).
    """

    def __init__(self, tolerance_m: float, frozen_time_s: float, thaw_time_s: float) -> None:
        self.tolerance_m = tolerance_m
        self.immune_s = frozen_time_s + thaw_time_s
        self.last_frozen: dict[tuple[str, int], dict[str, float]] = {}

    def reset(self) -> None:
        """Game paused: forget every freeze (the server re-enables the joints)."""
        self.last_frozen.clear()

    def check(self, side: str, unum: int, robot_type: int, poses: Mapping[str, Pose],
              game_time_s: float) -> list[str]:
        """Effectors to freeze now for this robot (empty: no new self-collision foul)."""
        frozen = self.last_frozen.setdefault((side, unum), {})
        to_freeze: list[str] = []
        for a, b in colliding_pairs(robot_type, poses, self.tolerance_m):
            for effector in a.freeze_effectors + b.freeze_effectors:
                last = frozen.get(effector)
                if last is None or game_time_s - last > self.immune_s:
                    frozen[effector] = game_time_s
                    to_freeze.append(effector)
        return to_freeze
