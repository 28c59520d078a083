"""3x3 rotations and 3-vectors as plain float tuples: for the per-cycle hot path, where numpy's per-call
overhead on tiny matrices costs more than the arithmetic (measured ~5x on the camera-height chain)."""

from __future__ import annotations

import math

Vector = tuple[float, float, float]
Matrix = tuple[Vector, Vector, Vector]
IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def rotation(axis: Vector, angle_rad: float) -> Matrix:
    """Rodrigues: right-handed rotation by ``angle_rad`` about the unit ``axis``."""
    x, y, z = axis
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    t = 1.0 - c
    return ((t * x * x + c, t * x * y - s * z, t * x * z + s * y),
            (t * x * y + s * z, t * y * y + c, t * y * z - s * x),
            (t * x * z - s * y, t * y * z + s * x, t * z * z + c))


def matmul(a: Matrix, b: Matrix) -> Matrix:
    """a · b."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    (b00, b01, b02), (b10, b11, b12), (b20, b21, b22) = b
    return ((a00 * b00 + a01 * b10 + a02 * b20, a00 * b01 + a01 * b11 + a02 * b21, a00 * b02 + a01 * b12 + a02 * b22),
            (a10 * b00 + a11 * b10 + a12 * b20, a10 * b01 + a11 * b11 + a12 * b21, a10 * b02 + a11 * b12 + a12 * b22),
            (a20 * b00 + a21 * b10 + a22 * b20, a20 * b01 + a21 * b11 + a22 * b21, a20 * b02 + a21 * b12 + a22 * b22))


def apply(m: Matrix, v: Vector) -> Vector:
    """m · v."""
    x, y, z = v
    return (m[0][0] * x + m[0][1] * y + m[0][2] * z,
            m[1][0] * x + m[1][1] * y + m[1][2] * z,
            m[2][0] * x + m[2][1] * y + m[2][2] * z)


def transpose(m: Matrix) -> Matrix:
    """mᵀ (the inverse of a rotation)."""
    return ((m[0][0], m[1][0], m[2][0]), (m[0][1], m[1][1], m[2][1]), (m[0][2], m[1][2], m[2][2]))


def cross(a: Vector, b: Vector) -> Vector:
    """a × b."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def orthonormalize(m: Matrix) -> Matrix:
    """The nearest-enough rotation to ``m`` (Gram-Schmidt on the rows), to stop integration drift."""
    r0, r1 = m[0], m[1]
    n0 = math.sqrt(r0[0] ** 2 + r0[1] ** 2 + r0[2] ** 2)
    r0 = (r0[0] / n0, r0[1] / n0, r0[2] / n0)
    d = r0[0] * r1[0] + r0[1] * r1[1] + r0[2] * r1[2]
    r1 = (r1[0] - d * r0[0], r1[1] - d * r0[1], r1[2] - d * r0[2])
    n1 = math.sqrt(r1[0] ** 2 + r1[1] ** 2 + r1[2] ** 2)
    r1 = (r1[0] / n1, r1[1] / n1, r1[2] / n1)
    return (r0, r1, cross(r0, r1))
