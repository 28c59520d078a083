"""Physics settings that make MuJoCo behave like SimSpark's ODE world (REFERENCE §2.4), with the measurements.

Why these choices (numbers measured on this machine with `benchmarks/bench_sim.py` and the probes in
tests/sim/test_world_physics.py; MuJoCo 4.0.0):

* **One 20 ms step per cycle, integrator ``discrete``.** SimSpark does one ODE ``dWorldStep`` of 0.02 s per
  cycle. MuJoCo's ``discrete`` integrator solves constraints and the implicit damping update in one
  velocity-level step (like ODE), and a robot with every joint held stands still at any timestep:
  torso z constant to 0.1 mm over 10 s at h = 20, 10 and 5 ms. ``implicitfast`` (the usual choice) makes
  the same robot rock and hop at every timestep tried (h = 2, 5, 10 ms: feet airborne in 10-25 % of steps,
  tilt up to 7°), because the contact impedance is computed from the light foot's inertia while the feet
  are in fact welded to the whole robot by the stiff motors; at h = 20 ms it falls over. Cost: 1 robot
  0.05 ms per cycle, 22 robots 0.66 ms per cycle (raw MuJoCo, wave-commanded joints).
* **Joint motors = implicit joint damping + a constant force.** ODE's hinge motor is a velocity constraint
  with a force bound (10 N·m). Here the servo force kv·(u - q̇) is split into joint damping kv (integrated
  implicitly by ``discrete``, inside the tree factorisation, so it costs nothing) and an applied force
  kv·u. With kv = 1e4 N·m·s/rad a commanded 1.0 rad/s gives 57.30 °/s and the steady error under the full
  10 N·m load is 1e-3 rad/s (0.06 °/s). MuJoCo's ``velocity`` actuator does the same 3x slower (its gain
  is an off-diagonal metric term) and its ``forcerange`` clamp is decided on the explicit force kv·(u - q̇),
  which saturates every light joint at once and overshoots by ~100 rad/s in one step. So the 10 N·m bound
  is enforced by an active set (see `sim.effectors.MotorBank`): a joint whose servo force would exceed the
  bound gets damping 0 and a constant ±10 N·m instead, and the step is redone when the guess was wrong.
* **Contacts.** μ = ∞ in SimSpark (slip only through soft ERP/CFM); here Coulomb friction μ = 2 with
  pyramidal cones (cheaper than elliptic at the same stand quality), condim 3, default solref/solimp
  (the ``refsafe`` rule of ``discrete`` stiffens rows that the step cannot resolve). A standing robot's feet
  do not slide (< 0.01 mm in 10 s).
* **Ball.** Free-joint damping gives exactly SimSpark's linear drag 0.01 N·s/m and angular drag 5e-5. ODE's
  bounce (restitution 0.8 above 0.8 m/s) has no stable MuJoCo equivalent at a 20 ms step (a restitutive
  spring must be softer than the step, so the ball would sink centimetres into the ground), so
  `sim.world.World` adds the rebound after the step: for each ball contact approaching faster than 0.8 m/s
  the ball gets +0.8·|v_n| along the normal.
* **Drag on robots.** SimSpark applies F = -0.01 v and τ = -0.01 ω to every body. The robot's whole-body
  part is applied as free-joint damping of the torso (N_bodies × 0.01 on the linear dofs, N_bodies × 0.01
  on the angular dofs), which is exact for a rigid translation and ignores the drag of limbs swinging
  relative to the torso (at most 0.06 N·m at full joint speed, against 10 N·m motors).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace


@dataclass(frozen=True)
class PhysicsParams:
    """Numbers of the MuJoCo world; see the module docstring for why each has its value."""

    cycle_s: float = 0.02
    """Simulated time per agent cycle [s] (REFERENCE §1)."""
    substeps: int = 1
    """MuJoCo steps per cycle; timestep = cycle_s / substeps."""
    gravity_m_s2: float = 9.81
    """Gravity magnitude [m/s²] (REFERENCE §2.4)."""
    motor_kv: float = 1.0e5
    """Servo gain of the joint motors [N·m·s/rad]: steady velocity error = load / kv."""
    motor_max_torque_nm: float = 10.0
    """Motor force bound (FMax, REFERENCE §2.2) [N·m]; the per-joint value in the spec wins."""
    motor_active_set_passes: int = 3
    """At most this many physics solves per step to settle which motors are saturated."""
    motor_torque_tolerance: float = 0.05
    """A servo force up to (1 + tolerance) x the bound is accepted without a re-solve."""
    friction: float = 2.0
    """Coulomb friction coefficient of every contact (SimSpark: unbounded, see the docstring)."""
    contact_condim: int = 3
    """Contact dimensionality (3 = normal + 2 tangential)."""
    contact_solref: tuple[float, float] = (0.02, 1.0)
    """solref of every contact (time constant [s], damping ratio)."""
    contact_solimp: tuple[float, float, float, float, float] = (0.2, 0.3, 0.001, 0.5, 2.0)
    """solimp of every contact: soft enough that a loaded foot sinks ~0.5 mm, as ODE's 1 mm surface layer
    lets it (calibrated on the real 0.7.3 traces, see the module docstring)."""
    cone: str = "elliptic"
    """Friction cone: "elliptic" or "pyramidal"."""
    ball_solref: tuple[float, float] = (0.02, 1.0)
    """solref of the ball's contacts (MuJoCo's default)."""
    ball_solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
    """solimp of the ball's contacts: stiff (MuJoCo's default), so the light ball neither sinks into the
    ground nor rolls out early; it wins the parameter mix of every ball contact."""
    ball_restitution: float = 0.8
    """Ball bounce (REFERENCE §2.4)."""
    ball_min_bounce_speed_m_s: float = 0.8
    """Normal approach speed above which the ball bounces [m/s]."""
    ball_linear_drag_n_s_m: float = 0.01
    """Ball linear drag [N·s/m]."""
    ball_angular_drag_nm_s: float = 5e-5
    """Ball angular drag [N·m·s/rad]."""
    body_linear_drag_n_s_m: float = 0.01
    """Drag per robot body [N·s/m] (REFERENCE §2.1)."""
    body_angular_drag_nm_s: float = 0.01
    """Angular drag per robot body [N·m·s/rad]."""
    joint_limit_solref: tuple[float, float] = (0.02, 1.0)
    """solref of the joint stops (StopERP 0.8 / StopCFM 1e-8 in SimSpark: hard)."""
    joint_limit_solimp: tuple[float, float, float, float, float] = (0.99, 0.999, 0.001, 0.5, 2.0)
    """solimp of the joint stops."""
    solver_iterations: int = 50
    """Main solver iterations (Newton)."""
    extra_flags: dict[str, bool] = field(default_factory=dict)
    """Reserved for experiments (benchmarks toggle MuJoCo flags by name)."""

    @property
    def timestep_s(self) -> float:
        return self.cycle_s / self.substeps


def default_physics_params(**overrides: object) -> PhysicsParams:
    """The default parameters, with named overrides (e.g. ``default_physics_params(substeps=4)``).

    Raises:
        TypeError: an override names no field (the message lists the fields).
    """
    base = PhysicsParams()
    unknown = set(overrides) - set(PhysicsParams.__dataclass_fields__)
    if unknown:
        raise TypeError(f"unknown physics parameter(s) {sorted(unknown)}; known: "
                        f"{sorted(PhysicsParams.__dataclass_fields__)}")
    return replace(base, **overrides)  # type: ignore[arg-type]
