"""Inertia tensors of the Nao's shapes at uniform density, as SimSpark's ODE computes them (dMassSet*Total)."""

from __future__ import annotations

import math

from kinematics.spec import Shape


def principal_inertia(shape: Shape, mass_kg: float) -> tuple[float, float, float]:
    """Diagonal inertia (kg m^2) about the shape's centre, in its own axes.

    Why: SimSpark gives only masses; ODE derives the inertia from the collider shape, so the physics and
    every kinematic library must use the same formula for CoM dynamics to agree.
    """
    if shape.kind == "box":
        x, y, z = shape.size
        return (mass_kg * (y * y + z * z) / 12.0, mass_kg * (x * x + z * z) / 12.0,
                mass_kg * (x * x + y * y) / 12.0)
    if shape.kind == "sphere":
        (r,) = shape.size
        i = 0.4 * mass_kg * r * r
        return (i, i, i)
    if shape.kind == "capsule":
        r, length = shape.size
        # ODE dMassSetCapsule: cylinder plus two hemispheres sharing the density; axis along z.
        v_cyl = math.pi * r * r * length
        v_caps = 4.0 / 3.0 * math.pi * r ** 3
        m_cyl = mass_kg * v_cyl / (v_cyl + v_caps)
        m_caps = mass_kg - m_cyl
        i_axial = (0.5 * m_cyl + 0.4 * m_caps) * r * r
        i_lateral = (m_cyl * (0.25 * r * r + length * length / 12.0)
                     + m_caps * (0.4 * r * r + 0.375 * r * length + 0.25 * length * length))
        return (i_lateral, i_lateral, i_axial)
    raise ValueError(f"unknown shape kind {shape.kind!r}")
