"""The self-collision rule (REFERENCE §4.5, foul type 7): overlapping box colliders of one robot freeze joints.

The overlap test is the server's BoxCollider::CheckCollisions, reproduced on purpose with its quirk: the
15 separating-axis candidates are not normalised and the 0.04 m tolerance is added to the projection of
the centre offset, so a cross-product axis of two (nearly) parallel box axes always "separates". In
practice a pair is reported only when the boxes are turned against each other about every axis.

Measured against the real server (2026-11-29): in the real front stand-up's recording
(tests/sim/fixtures/real_0.7.3_skill_standup_front.jsonl.gz) both arms and both legs stood still for 1.02 s from
3.26 s after the skill's start while commanded on (``motion-studio calibrate --only skill_standup_front
--divergence`` reports it): a self-collision foul of each lower arm with its leg. Replayed here open loop no foul is
called; with the real joint angles put on our robot at that cycle the lower arm overlaps its shank by more than the
tolerance on 14 of the 15 axes and falls 2.0 mm short on the cross axis of the two boxes' x axes. So the rule sits
at its edge there, and a few millimetres of pose (ODE's joint drift, a degree at the hip) decide it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from kinematics.spec import robot_spec

#: Body pose: centre [m] and row-major 3x3 rotation (columns = body x, y, z axes in the world).
Pose = tuple[tuple[float, float, float], tuple[float, ...]]

_ONES3 = np.ones(3)
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
    a, b = axes_a[:, :, None, :], axes_b[:, None, :, :]
    cross = np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                      a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                      a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1).reshape(-1, 9, 3)
    planes = np.concatenate([axes_a, axes_b, cross], axis=1)  # (P, 15, 3)
    reach = (np.abs(planes @ ra) @ half_a[:, :, None])[..., 0] + (np.abs(planes @ rb) @ half_b[:, :, None])[..., 0]
    along = np.abs((planes @ offset[:, :, None])[..., 0])
    return ~np.any(along + tolerance_m > reach, axis=1)


def _turned_about_every_axis(ra: np.ndarray, rb: np.ndarray, half_sum: np.ndarray, tolerance_m: float) -> np.ndarray:
    """False for pairs the server's test surely separates because two of their axes are nearly parallel.

    The cross axis L = a_i × b_j of box axes a_i, b_j has |L|² = 1 - (a_i · b_j)², and the boxes' reach along
    it is at most |L| times the sum of all six half sizes; once that is below the tolerance, L separates
    whatever the offset. The test here keeps a factor of 2 to that bound, so it never drops a pair the full
    test would report. Boxes joined by a hinge share its axis, so this drops most near pairs (measured with
    22 robots: 159 of 178) before the 15-axis test.
    """
    cosines = (np.swapaxes(ra, 1, 2) @ rb).reshape(-1, 9)     # a_i · b_j
    limit = 1.0 - (0.5 * tolerance_m / half_sum) ** 2           # |L| < tolerance / (2 half_sum)
    return (cosines * cosines).max(axis=1) <= limit


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


class BodyPoseArrays(Mapping):  # type: ignore[type-arg]
    """Body poses backed by shared arrays (a read-only Mapping name -> (centre, row-major rotation)).

    positions: (N, 3) [m] and rotations: (N, 9) row-major, shared by every robot of a world (MuJoCo's
    ``xpos``/``xmat``); rows: body name -> row. The rule gathers all robots' boxes in one indexing step.
    """

    def __init__(self, rows: Mapping[str, int], positions: np.ndarray, rotations: np.ndarray) -> None:
        self.rows = rows
        self.positions = positions
        self.rotations = rotations

    def __getitem__(self, name: str) -> Pose:
        i = self.rows[name]
        return tuple(self.positions[i]), tuple(self.rotations[i])  # type: ignore[return-value]

    def __iter__(self):
        return iter(self.rows)

    def __len__(self) -> int:
        return len(self.rows)


def _box_arrays(robots: Sequence[tuple[int, Mapping[str, Pose]]], members: list[int],
                robot_type: int) -> tuple[list[int], np.ndarray, np.ndarray]:
    """Box centres (R, B, 3) and rotations (R, B, 3, 3) of same-type robots; robots lacking a box are left out."""
    boxes = box_colliders(robot_type)
    shared: list[int] = []
    rows: list[list[int]] = []
    base = None
    others: list[int] = []
    for index in members:
        poses = robots[index][1]
        if isinstance(poses, BodyPoseArrays) and (base is None or poses.positions is base[0]) and all(
                box.body in poses.rows for box in boxes):
            base = base or (poses.positions, poses.rotations)
            shared.append(index)
            rows.append([poses.rows[box.body] for box in boxes])
        else:
            others.append(index)
    centres, rotations, kept = [], [], []
    if shared:
        assert base is not None
        idx = np.array(rows, dtype=np.intp)
        centres.append(base[0][idx])
        rotations.append(base[1][idx].reshape(len(shared), len(boxes), 3, 3))
        kept.extend(shared)
    for index in others:
        poses = robots[index][1]
        if any(box.body not in poses for box in boxes):
            continue
        centres.append(np.array([[poses[box.body][0] for box in boxes]], dtype=float))
        rotations.append(np.array([[poses[box.body][1] for box in boxes]], dtype=float).reshape(1, -1, 3, 3))
        kept.append(index)
    if not kept:
        return [], np.zeros((0, len(boxes), 3)), np.zeros((0, len(boxes), 3, 3))
    return kept, np.concatenate(centres), np.concatenate(rotations)


def colliding_pairs_many(robots: Sequence[tuple[int, Mapping[str, Pose]]], tolerance_m: float,
                         batch: SharedPoseBatch | None = None) -> list[list[tuple[BoxColliderSpec, BoxColliderSpec]]]:
    """Overlapping box pairs of several robots (robot type, body poses), vectorised.

    Boxes whose bounding spheres are apart are skipped first: disjoint boxes have a separating unit axis,
    and the server's shorter (unnormalised) axes only separate more easily, so the result is unchanged.
    Robots whose poses are `BodyPoseArrays` over one pair of arrays (the simulator's) are tested together
    in one batch, whatever their types (``batch`` keeps its index from call to call); any others per type.
    """
    result: list[list[tuple[BoxColliderSpec, BoxColliderSpec]]] = [[] for _ in robots]
    batch = (batch or SharedPoseBatch()).select(robots)
    if batch is not None:
        positions, rotations = batch.arrays
        offset = positions[batch.second] - positions[batch.first]   # (N, 3) over every pair of every robot
        # The bounding-sphere test only skips pairs, so its summation order does not matter: a matrix product.
        near = np.flatnonzero((offset * offset) @ _ONES3 <= batch.reach_squared)
        if near.size:
            ra, rb = rotations[batch.first[near]].reshape(-1, 3, 3), rotations[batch.second[near]].reshape(-1, 3, 3)
            turned = np.flatnonzero(_turned_about_every_axis(ra, rb, batch.half_sum[near], tolerance_m))
            if turned.size:
                hits = _overlaps(ra[turned], rb[turned], batch.half_first[near[turned]],
                                 batch.half_second[near[turned]], offset[near[turned]], tolerance_m)
                for p in near[turned[hits]].tolist():
                    result[batch.robot[p]].append(batch.boxes[p])
    by_type: dict[int, list[int]] = {}
    for index, (robot_type, _) in enumerate(robots):
        if batch is None or index not in batch.members:
            by_type.setdefault(robot_type, []).append(index)
    for robot_type, members in by_type.items():
        kept, centres, rotations = _box_arrays(robots, members, robot_type)
        if not kept:
            continue
        boxes, first, second, half, reach = _pair_table(robot_type)
        offset = centres[:, second] - centres[:, first]  # (R, P, 3)
        near_robot, near_pair = np.nonzero(np.einsum("rpc,rpc->rp", offset, offset) <= reach * reach)
        if near_robot.size == 0:
            continue
        i, j = first[near_pair], second[near_pair]
        hits = _overlaps(rotations[near_robot, i], rotations[near_robot, j], half[i], half[j],
                         offset[near_robot, near_pair], tolerance_m)
        for r, a, b in zip(near_robot[hits], i[hits], j[hits]):
            result[kept[r]].append((boxes[a], boxes[b]))
    return result


class SharedPoseBatch:
    """Every box pair of the robots whose poses are `BodyPoseArrays` over the same arrays, as flat index
    arrays into those arrays (rows = bodies), rebuilt only when the robots (types, row maps) change."""

    def __init__(self) -> None:
        self._key: list[object] = []
        self.members: set[int] = set()
        self.arrays: tuple[np.ndarray, np.ndarray] = (np.zeros((0, 3)), np.zeros((0, 9)))

    def select(self, robots: Sequence[tuple[int, Mapping[str, Pose]]]) -> SharedPoseBatch | None:
        """Index the batchable robots of this call (or reuse the last index); None when there are none."""
        poses = [p for _, p in robots]
        base = next((p for p in poses if isinstance(p, BodyPoseArrays)), None)
        if base is None:
            return None
        # The key holds the robots' row maps themselves (identity compared, kept alive by the key).
        key: list[object] = [robot_type for robot_type, _ in robots]
        key += [p.rows if isinstance(p, BodyPoseArrays) and p.positions is base.positions else None for p in poses]
        if len(key) != len(self._key) or any(a is not b and a != b for a, b in zip(key, self._key)):
            self._index(robots, base)
            self._key = key
        self.arrays = (base.positions, base.rotations.reshape(-1, 9))
        return self if self.members else None

    def _index(self, robots: Sequence[tuple[int, Mapping[str, Pose]]], base: BodyPoseArrays) -> None:
        first, second, half_first, half_second, reach, owner, boxes = [], [], [], [], [], [], []
        self.members = set()
        for index, (robot_type, poses) in enumerate(robots):
            table = box_colliders(robot_type)
            if not (isinstance(poses, BodyPoseArrays) and poses.positions is base.positions
                    and all(box.body in poses.rows for box in table)):
                continue
            self.members.add(index)
            specs, a, b, half, reach_sum = _pair_table(robot_type)
            rows = np.array([poses.rows[box.body] for box in specs], dtype=np.intp)
            first.append(rows[a])
            second.append(rows[b])
            half_first.append(half[a])
            half_second.append(half[b])
            reach.append(reach_sum * reach_sum)
            owner += [index] * a.size
            boxes += [(specs[i], specs[j]) for i, j in zip(a.tolist(), b.tolist())]
        join = (lambda parts, empty: np.concatenate(parts) if parts else empty)
        self.first = join(first, np.zeros(0, dtype=np.intp))
        self.second = join(second, np.zeros(0, dtype=np.intp))
        self.half_first = join(half_first, np.zeros((0, 3)))
        self.half_second = join(half_second, np.zeros((0, 3)))
        self.half_sum = self.half_first.sum(axis=1) + self.half_second.sum(axis=1)
        self.reach_squared = join(reach, np.zeros(0))
        self.robot = owner
        self.boxes = boxes


def colliding_pairs(robot_type: int, poses: Mapping[str, Pose], tolerance_m: float) -> list[tuple[
        BoxColliderSpec, BoxColliderSpec]]:
    """Pairs of one robot's box colliders that overlap (exempt pairs skipped)."""
    return colliding_pairs_many([(robot_type, poses)], tolerance_m)[0]


class SelfCollisionRule:
    """Freeze bookkeeping: a joint frozen at t is not frozen again before t + frozen + thaw time.

    Args:
        tolerance_m, frozen_time_s, thaw_time_s: REFERENCE §4.5 (0.04 m, 1.0 s, 2.0 s).
    """

    def __init__(self, tolerance_m: float, frozen_time_s: float, thaw_time_s: float) -> None:
        self.tolerance_m = tolerance_m
        self.immune_s = frozen_time_s + thaw_time_s
        self.last_frozen: dict[tuple[str, int], dict[str, float]] = {}
        self._batch = SharedPoseBatch()   # the pair index of the simulator's robots, kept between cycles

    def reset(self) -> None:
        """Game paused: forget every freeze (the server re-enables the joints)."""
        self.last_frozen.clear()

    def check_all(self, robots: Sequence[tuple[str, int, int, Mapping[str, Pose]]],
                  game_time_s: float) -> list[tuple[str, int, list[str]]]:
        """(side, unum, effectors to freeze now) for each robot with a new self-collision foul.

        Args:
            robots: (side, unum, robot type, body poses) per robot.
            game_time_s: game time (freeze and immunity are timed on it, as in the server).
        """
        pairs_of = colliding_pairs_many([(robot_type, poses) for _, _, robot_type, poses in robots],
                                        self.tolerance_m, self._batch)
        out = []
        for (side, unum, _, _), pairs in zip(robots, pairs_of):
            if not pairs:
                continue
            frozen = self.last_frozen.setdefault((side, unum), {})
            to_freeze: list[str] = []
            for a, b in pairs:
                for effector in a.freeze_effectors + b.freeze_effectors:
                    last = frozen.get(effector)
                    if last is None or game_time_s - last > self.immune_s:
                        frozen[effector] = game_time_s
                        to_freeze.append(effector)
            if to_freeze:
                out.append((side, unum, to_freeze))
        return out
