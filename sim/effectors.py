"""Joint motors of every robot with SimSpark's hinge-effector semantics (REFERENCE §2.2), as flat arrays.

Semantics reproduced:
1. A joint command is a target angular velocity [rad/s], clamped to the joint's max speed.
2. It persists until the next command for that joint.
3. A new command is ignored while the joint angle is not strictly inside (min, max).
4. A joint frozen by the self-collision rule gets velocity 0 and ignores commands while frozen.

Physics (see `sim.physics_params`): each motor is a velocity servo of gain g split into implicit joint
damping g and an applied force g·u, so MuJoCo's ``discrete`` step solves it together with the contacts,
as ODE solves its motor rows. Normally g = kv (stiff). The 10 N·m bound is met by lowering g for the joints
that would need more (see `MotorBank.predict`); when a stiff servo turns out to have exceeded the bound
after all, `MotorBank.check` asks the caller to redo the step with the lowered gain.

Joint stops are ODE's (hingejoint.rsg: StopERP 0.8, Bounce 1, FudgeFactor 1e-5), also done here (MuJoCo's own
limits are off): a joint at or past a stop when the step starts gets a stop row, a stiff servo toward the
velocity that leaves the stop at least as fast as the joint came in (bounce 1) and at least at 0.8 x the
overshoot per step, which may only push; its motor is then a constant torque, the full bound in the
commanded direction (or into the stop for 0), 1e-5 of it when commanded away from the stop. A joint driven
into its stop therefore bounces between the stop and one step inside, so rule 3 lets every second command
through (the real fall trace: a hip at 3 rad/s into its 100 deg stop alternates 100.24 / 96.81 deg).

Stops hold in a flailing robot as ODE's do because no motor runs away in the step's solves. ODE solves each
motor (|torque| <= bound, velocity = target unless at the bound) and stop row exactly; here `check` settles
that by re-solving, and three rules keep its guesses from driving a joint through a stop: a servo on a
lowered gain whose joint is driven more than `RUNAWAY_RAD_S` past its target velocity is held braking at the
bound (the low gain braked with g |q̇ - u|, a tenth of the bound, and let coupled joints whip it on); a stop
row released and then held again stays held for the rest of the step (released and held in turn it never
settled); and the step's last solve, which `sim.world.World.step` keeps unchecked, is solved again from the
step's start when a held motor or low-gain servo ran away in it or a released row let its joint into the
stop (`RUNAWAY_RE_SOLVES`). Measured with arms and head at +-100 rad/s reversed every 1-3 or 3-14 cycles and
the legs at random velocities, the same commands over TCP to the real 0.7.3 and to ours (10 x 500 cycles per
pattern after 60 cycles standing; tests/sim/test_joint_stops.py runs the first pattern in-process): before,
the last solve often held a light joint at a constant 10 N·m whose load had gone (an elbow spun to 131-152
rad/s, a knee ended 35 deg past its stop at 31 rad/s), the blow-up guard reset the robot in 25 of 64,000
flailing cycles in-process and 2 of 10,000 over TCP, and joints ended up to 29.8 deg past a stop; now the
guard never fired (128,000 cycles) and over TCP 0.006 / 0.029 % of the joint-cycles end more than 7.5 deg
past a stop, worst 16.8 / 14.6 deg (real server: 0.008 / 0.030 %, worst 12.9 / 16.9 deg; ours before: 0.029 /
0.141 %, worst 29.8 / 21.1), arms and head within 7.0 / 12.1 deg (real 11.1 / 9.6; before 18.2 / 21.1). The
cost: motor torques over 10.5 N·m under random +-6 rad/s commands 0.07 -> 0.16 % (8 seeds, worst 17 -> 28
N·m). Of the real-trace replays, walk backward, turn, kick and stand are unchanged; the forward and side
walks and both stand-ups meet a rule 1-12 times in 550-650 cycles and still pass their tests.

All arrays hold one entry per hinge of every robot, robots in the order they were added; nothing here
loops over joints in Python.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from kinematics.spec import JointSpec
from sim.physics_params import PhysicsParams

#: REFERENCE §4.5: joints frozen by the self-collision rule stay at velocity 0 this long [s].
FREEZE_DURATION_S = 1.0
#: SimSpark's hinge stops (rcssserver3d/data/rsg/agent/nao/hingejoint.rsg): the stop row corrects this share of
#: the overshoot per step (StopERP), reflects an incoming joint velocity this much (Bounce), and a motor
#: commanded away from the stop it sits at pushes with this share of its bound (FudgeFactor, ODE's hinge motor).
STOP_ERP = 0.8
STOP_BOUNCE = 1.0
STOP_FUDGE = 1e-5
#: A stop row whose force would pull the joint into the stop by more than this is released [N·m].
_STOP_PULL_TOLERANCE_NM = 1e-6
#: Extra physics solves allowed in a step with a joint at a stop (see `MotorBank.extra_passes`).
STOP_EXTRA_PASSES = 3
#: The last solve of a step is kept unless a motor ran away in it: a held motor or a servo on a lowered gain
#: whose joint ended this far past its target velocity, or a released stop row whose joint went into the stop
#: this much faster than the row allows [rad/s]; then it is solved again, at most `RUNAWAY_RE_SOLVES` times.
RUNAWAY_RAD_S = 1.0
RUNAWAY_RE_SOLVES = 2
#: The joint-space inertia a motor's prediction divides by is at least this [kg·m²] (no division by 0). A 0-d
#: array, as `MotorBank._timestep`: numpy converts a Python float operand on every call, which costs about as
#: much as the operation itself on one robot's 22 values (same value, same results).
_MIN_INERTIA = np.array(1e-9)


@dataclass
class _Block:
    start: int
    stop: int


class MotorBank:
    """Target velocities and saturation state of all joint motors of the world.

    Args:
        params: physics parameters (servo gain, torque tolerance).
    """

    _FIELDS = ("target", "max_speed", "min_rad", "max_rad", "max_torque", "frozen_until", "gain", "bias",
               "applied", "start_velocity", "dof", "qadr")

    def __init__(self, params: PhysicsParams) -> None:
        self.params = params
        self.blocks: dict[int, _Block] = {}
        self.target = np.zeros(0)          # commanded velocity [rad/s]
        self.max_speed = np.zeros(0)       # [rad/s]
        self.min_rad = np.zeros(0)
        self.max_rad = np.zeros(0)
        self.max_torque = np.zeros(0)      # [N·m]
        self.frozen_until = np.zeros(0)    # server time until which commands are ignored [s]
        self.gain = np.zeros(0)            # servo gain of the current step [N·m·s/rad]
        self.bias = np.zeros(0)            # constant torque of a motor held at its bound this step [N·m]
        self.applied = np.zeros(0)         # motor torque of the last step [N·m]
        self.stop_torque = np.zeros(0)     # stop-row torque of the last step [N·m]
        self.start_velocity = np.zeros(0)  # joint velocity at the start of the last step [rad/s]
        self.dof = np.zeros(0, dtype=np.intp)   # qvel / dof address of each joint
        self.qadr = np.zeros(0, dtype=np.intp)  # qpos address of each joint
        self.re_solves = 0
        self.steps = 0
        self._diagonal: np.ndarray | None = None
        # Per-step constants, rebuilt by `bind_model` (never changed in place: `gain`/`bias` may share them).
        self._timestep_s = params.timestep_s
        self._timestep = np.array(self._timestep_s)   # the same as a 0-d array (see `_MIN_INERTIA`)
        self._stiff = np.zeros(0)          # every gain at kv
        self._no_bias = np.zeros(0)
        self._held_limit = np.zeros(0)     # 80 % of the bound: a saturated motor stays saturated above it
        self._check_limit = np.zeros(0)    # the bound with the re-solve tolerance
        self._least_remaining = np.zeros(0)
        self._neg_max_speed = np.zeros(0)
        self._damping_written: np.ndarray | None = None   # the gains last written to the model
        # Per step: the servo's target velocity (the command, or a stop row's) and the stop each joint is at.
        self.setpoint = np.zeros(0)        # [rad/s]
        self.stop_side = np.zeros(0, dtype=np.int8)   # +1 at/past the upper stop, -1 the lower, 0 inside
        self._at_stop = np.zeros(0, dtype=bool)
        self._any_stop = False
        self._no_reset = np.zeros(0, dtype=bool)
        self._reset = self._no_reset      # held motors made stiff again in this step (overshoot)
        self._pinned = self._no_reset     # stop rows held again after a release in this step
        self._step_start: tuple[np.ndarray, np.ndarray, np.ndarray, float] | None = None

    # ---- robots --------------------------------------------------------------------------------------
    def add_robot(self, key: int, joints: tuple[JointSpec, ...]) -> None:
        """Append the motors of one robot (targets 0)."""
        n = len(joints)
        start = self.target.size
        self.blocks[key] = _Block(start, start + n)
        extra = {
            "target": np.zeros(n), "max_speed": np.array([j.max_speed_rad_s for j in joints]),
            "min_rad": np.array([j.min_rad for j in joints]), "max_rad": np.array([j.max_rad for j in joints]),
            "max_torque": np.array([j.max_torque_nm for j in joints]), "frozen_until": np.full(n, -np.inf),
            "gain": np.full(n, self.params.motor_kv), "bias": np.zeros(n), "applied": np.zeros(n),
            "start_velocity": np.zeros(n),
            "dof": np.zeros(n, dtype=np.intp),
            "qadr": np.zeros(n, dtype=np.intp),
        }
        for name in self._FIELDS:
            setattr(self, name, np.concatenate([getattr(self, name), extra[name]]))

    def remove_robot(self, key: int) -> None:
        """Drop the motors of one robot; later robots move down."""
        block = self.blocks.pop(key)
        keep = np.r_[0:block.start, block.stop:self.target.size]
        for name in self._FIELDS:
            setattr(self, name, getattr(self, name)[keep])
        n = block.stop - block.start
        for other in self.blocks.values():
            if other.start >= block.stop:
                other.start -= n
                other.stop -= n

    def set_addresses(self, key: int, qadr: np.ndarray, dof: np.ndarray) -> None:
        """Bind a robot's motors to the model's qpos/dof addresses (after every recompile)."""
        block = self.blocks[key]
        self.qadr[block.start:block.stop] = qadr
        self.dof[block.start:block.stop] = dof

    def span(self, key: int) -> slice:
        block = self.blocks[key]
        return slice(block.start, block.stop)

    # ---- commands ------------------------------------------------------------------------------------
    def command(self, key: int, local_index: np.ndarray, value_rad_s: np.ndarray, qpos: np.ndarray,
                now_s: float) -> None:
        """Apply joint commands of one robot (rules 1-4 of the module docstring).

        Args:
            key: robot key.
            local_index: joint indices within the robot (spec order), shape (k,).
            value_rad_s: commanded velocities [rad/s], shape (k,), finite.
            qpos: the current mjData.qpos (angles are read from it).
            now_s: server time [s] (for the freeze rule).
        """
        self.command_many(self.blocks[key].start + np.asarray(local_index, dtype=np.intp), value_rad_s, qpos, now_s)

    def command_many(self, index: np.ndarray, value_rad_s: np.ndarray, qpos: np.ndarray, now_s: float) -> None:
        """Like `command` for any robots at once: ``index`` are positions in the bank (block start + local)."""
        index = np.asarray(index, dtype=np.intp)
        angle = qpos[self.qadr[index]]
        now = np.array(now_s)   # (a 0-d array operand: see `_MIN_INERTIA`)
        inside = (angle > self.min_rad[index]) & (angle < self.max_rad[index]) & (self.frozen_until[index] <= now)
        index = index[inside]
        limit = self.max_speed[index]
        self.target[index] = np.clip(np.asarray(value_rad_s, dtype=float)[inside], -limit, limit)

    def command_all(self, value_rad_s: np.ndarray, qpos: np.ndarray, now_s: float) -> None:
        """Like `command_many` with every motor of the bank commanded once, values in bank order: the same
        rules on whole arrays, without the gathers (every agent commanding every joint is the usual cycle)."""
        angle = qpos[self.qadr]
        inside = (angle > self.min_rad) & (angle < self.max_rad) & (self.frozen_until <= np.array(now_s))
        # np.clip's definition, min(max(v, -limit), limit), without its Python wrapper (twice the cost here)
        clipped = np.minimum(np.maximum(value_rad_s, self._neg_max_speed), self.max_speed)
        np.copyto(self.target, clipped, where=inside)

    def reset_robot(self, key: int) -> None:
        """Forget a robot's motor history (after a placement zeroed its velocities)."""
        span = self.span(key)
        self.applied[span] = 0.0
        self.start_velocity[span] = 0.0
        if self.stop_torque is not self._no_bias and self.stop_torque.size == self.target.size:
            self.stop_torque = self.stop_torque.copy()   # never write into the shared zeros
            self.stop_torque[span] = 0.0

    def freeze(self, key: int, local_index: np.ndarray, now_s: float) -> None:
        """Self-collision rule: velocity 0 and commands ignored for `FREEZE_DURATION_S`."""
        index = self.blocks[key].start + np.asarray(local_index, dtype=np.intp)
        self.target[index] = 0.0
        self.frozen_until[index] = now_s + FREEZE_DURATION_S

    def targets(self, key: int) -> np.ndarray:
        """The robot's current target velocities [rad/s] (a copy)."""
        return self.target[self.span(key)].copy()

    # ---- physics -------------------------------------------------------------------------------------
    def bind_model(self, model: mujoco.MjModel) -> None:
        """Cache model-dependent addresses (after every recompile)."""
        self._diagonal = model.M_rowadr[self.dof] + model.M_rownnz[self.dof] - 1  # CSR rows end at the diagonal
        self._timestep_s = model.opt.timestep
        self._timestep = np.array(self._timestep_s)
        self._stiff = np.full(self.target.size, self.params.motor_kv)
        self._no_bias = np.zeros(self.target.size)
        self._held_limit = 0.8 * self.max_torque
        self._check_limit = self.max_torque * (1.0 + self.params.motor_torque_tolerance)
        self._least_remaining = self.max_torque / self.params.motor_kv   # a capped gain stays <= kv
        self._neg_max_speed = -self.max_speed
        self._damping_written = None   # a recompiled model has the spec's damping
        self.setpoint = self.target.copy()
        self.stop_torque = self._no_bias
        self._no_reset = np.zeros(self.target.size, dtype=bool)
        self._reset = self._no_reset
        self._pinned = self._no_reset
        self.stop_side = np.zeros(self.target.size, dtype=np.int8)
        self._at_stop = np.zeros(self.target.size, dtype=bool)
        self._any_stop = False

    def predict(self, model: mujoco.MjModel, data: mujoco.MjData,
                step_start: tuple[np.ndarray, np.ndarray, np.ndarray, float]) -> None:
        """Choose each motor's servo gain for the coming step and write damping and forces.

        ``step_start`` is the caller's copy of the state the step starts from (qpos, qvel, qacc_warmstart,
        time), kept for a solve from the step's start (see `check`).

        Per joint, with I the joint-space inertia (diagonal of M: the rest of the robot held, as its motors
        hold it), e = u - q̇ and L the load the motor met in the last step (its torque minus I times the
        acceleration it saw), the torque needed to reach u in one step is L + I e / h. Within the bound the
        motor is a stiff servo (gain kv). Beyond it:

        * a joint that was within the bound gets g = τmax / |e - h (±τmax - L) / I|, so the implicit step
          I (q̇⁺ - q̇)/h = g (u - q̇⁺) - L delivers exactly the bound (ODE's saturated motor);
        * a joint that was already saturated (its load is then mostly a stop or a closed chain pushing
          back) gets the stuck joint's gain g = τmax / |e|, whose torque stays within the bound however
          the joint moves toward its target. It stays saturated while it needs 80 % of the bound.

        A low-gain servo cannot drive a joint past its target, so wrong guesses in coupled chains stay
        stable; `check` corrects the guesses that exceed the bound.

        A joint at or past a stop (angle <= min or >= max, ODE's test at the step's start) gets the stop row
        and the constant motor torque of the module docstring instead.
        """
        if self.target.size == 0:
            return
        h = self._timestep
        kv, limit = self.params.motor_kv, self.max_torque
        velocity = data.qvel[self.dof]
        inertia = np.maximum(data.M[self._diagonal], _MIN_INERTIA)
        # Without a stop row in the last step its torques are the shared zeros: adding them could only turn a
        # -0.0 into 0.0, and the sign of a zero load changes nothing below.
        pushed = self.applied if self.stop_torque is self._no_bias else self.applied + self.stop_torque
        load = pushed - inertia * (velocity - self.start_velocity) / h
        self.start_velocity = velocity
        error = self.target - velocity
        self.bias = self._no_bias
        self.setpoint = self.target
        self._reset = self._no_reset
        self._pinned = self._no_reset
        # The step's start, for a solve of its own when the last one ran away (see `check`).
        self._step_start = step_start
        needed = load + inertia * error / h
        was_capped = None   # the usual step: every servo was stiff (`_stiff` is only ever all kv), none capped
        if self.gain is not self._stiff:
            was_capped = self.gain < kv
            if self._any_stop:   # a released stop row (gain 0) was no saturated motor
                was_capped &= ~self._at_stop
        capped = np.abs(needed) > (limit if was_capped is None else np.where(was_capped, self._held_limit, limit))
        if not np.count_nonzero(capped):
            self.gain = self._stiff
        else:
            free_motion = np.abs(error - h * (np.sign(needed) * limit - load) / inertia)
            remaining = free_motion if was_capped is None else np.where(was_capped, np.abs(error), free_motion)
            self.gain = np.where(capped, limit / np.maximum(remaining, self._least_remaining), kv)
        angle = data.qpos[self.qadr]
        high, low = angle >= self.max_rad, angle <= self.min_rad
        self._at_stop = high | low
        self._any_stop = bool(np.count_nonzero(self._at_stop))
        if self._any_stop:
            self._stop_rows(high, low, angle, velocity)
        self._write(model, data)

    @property
    def extra_passes(self) -> int:
        """Solves allowed beyond `PhysicsParams.motor_active_set_passes` in this step: a joint bouncing off its
        stop jolts the motors of its chain, which then need more rounds to settle which are saturated
        (random commands flailing a robot: with 3 more, 99.9 % of the motor torques stay within 10.5 N·m)."""
        return STOP_EXTRA_PASSES if self._any_stop else 0

    def _stop_rows(self, high: np.ndarray, low: np.ndarray, angle: np.ndarray, velocity: np.ndarray) -> None:
        """ODE's hinge at a stop (dxJointLimitMotor::addLimot): the stop row as a stiff servo toward the leaving
        velocity max(StopERP x overshoot / h, Bounce x incoming speed), the motor as a constant torque."""
        at = self._at_stop
        side = np.where(high, 1, np.where(low, -1, 0)).astype(np.int8)
        past = np.where(high, angle - self.max_rad, self.min_rad - angle)           # >= 0 at a stop
        incoming = np.maximum(side * velocity, 0.0)                                   # speed into the stop
        leaving = np.maximum(STOP_ERP * past / self._timestep_s, STOP_BOUNCE * incoming)
        self.setpoint = np.where(at, -side * leaving, self.target)
        into = (high & (self.target >= 0.0)) | (low & (self.target <= 0.0))
        motor = np.where(into, side * self.max_torque, -side * STOP_FUDGE * self.max_torque)
        self.bias = np.where(at, motor, 0.0)
        self.gain = np.where(at, self.params.motor_kv, self.gain)
        self.stop_side = side

    def _write(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        if self.gain is not self._damping_written:   # all stiff again: the model holds these gains already
            model.dof_damping[self.dof] = self.gain
            self._damping_written = self.gain
        data.qfrc_applied[self.dof] = self.gain * self.setpoint + self.bias

    def check(self, model: mujoco.MjModel, data: mujoco.MjData, final: bool = False) -> bool:
        """After a step: record the motor torques; True when a motor exceeded the bound (re-solve needed).

        On a re-solve a stiff servo that exceeded the bound gets the gain of a stuck joint, τmax / |u - q̇|,
        whose torque stays within the bound while the joint moves toward its target; a joint that exceeded
        it even so (a load drove it away from its target) is held at the bound with a constant torque,
        which is ODE's saturated motor, as is a low-gain servo whose joint was driven past its target (braking).
        A stop row that pulled is released, unless it was held again after a release in this step.
        ``applied`` is the motor's torque, ``stop_torque`` the stop row's. With ``final`` the step is kept and
        False is returned, after solving it again from its start if a motor ran away in it (module docstring).
        """
        if self.target.size == 0:
            return False
        velocity, torque = self._record(data)
        if final:
            for _ in range(RUNAWAY_RE_SOLVES):
                if not self._stop_runaways(model, data, velocity):
                    break
                velocity, torque = self._record(data)
            return False
        if self.gain is self._stiff and self.bias is self._no_bias and not self._any_stop:
            # The usual step (every servo stiff, none held, no joint at a stop): of the rules below only the
            # bound can apply, so the rest is skipped while no motor exceeded it.
            if not np.count_nonzero(np.abs(torque) > self._check_limit):
                return False
        at_stop = self._at_stop
        limit = self.max_torque
        kv = self.params.motor_kv
        released = False
        if self._any_stop:
            # A stop row only pushes the joint out of its stop; one that had to pull is released (ODE's LCP
            # bounds the row's force to that side) and the step redone, with the motors' corrections below.
            pulling = at_stop & (self.gain > 0.0) & (self.stop_side * self.stop_torque > _STOP_PULL_TOLERANCE_NM)
            # and a released one whose joint then went into the stop faster than the row allows holds again
            pushing = at_stop & (self.gain == 0.0) & (self.stop_side * (velocity - self.setpoint) > 0.0)
            # for the rest of the step (released and held in turn, some never settle)
            pulling &= ~self._pinned
            if np.count_nonzero(pulling) or np.count_nonzero(pushing):
                self.gain = np.where(pulling, 0.0, np.where(pushing, kv, self.gain))
                self._pinned = self._pinned | pushing
                released = True
        # A motor held at its bound that drove its joint past the target velocity was not saturated: ODE's
        # motor would have braked there. It becomes a stiff servo again (measured against the real server:
        # a held knee pushed on to 29 rad/s where the real one moved at its commanded 6.14 rad/s).
        overshot = (self.bias != 0.0) & (self.bias * (velocity - self.target) > 0.0)
        if self._any_stop:
            overshot &= ~at_stop
        if np.count_nonzero(overshot):
            # Once stiff again; a joint that overshoots a second time in this step (the coupled joints keep
            # changing its load) gets the secant servo instead: the bound at the velocity it overshot to, less
            # toward the target.
            again = overshot & self._reset
            self._reset = self._reset | overshot
            secant = limit / np.maximum(np.abs(self.target - velocity), self._least_remaining)
            self.gain = np.where(again, secant, np.where(overshot, kv, self.gain))
            self.bias = np.where(overshot, 0.0, self.bias)
            self._write(model, data)
            return True
        # A servo on a lowered gain whose joint was driven past its target brakes with g |q̇ - u| only, where
        # ODE's motor brakes with up to its bound: held there, braking.
        low = (self.gain < kv) & (self.gain > 0.0) & (self.bias == 0.0) & ~self._reset
        driven = low & ((velocity - self.target) * (self.target - self.start_velocity) > 0.0) \
            & (np.abs(velocity - self.target) > RUNAWAY_RAD_S)
        if self._any_stop:
            driven &= ~at_stop
        if np.count_nonzero(driven):
            self.gain = np.where(driven, 0.0, self.gain)
            self.bias = np.where(driven, np.sign(self.target - velocity) * limit, self.bias)
            self._write(model, data)
            return True
        over = np.abs(torque) > self._check_limit
        if self._any_stop:   # a joint at a stop has a constant motor torque; the stop row has no bound
            over &= ~at_stop
        if not np.count_nonzero(over):
            if released:
                self._write(model, data)
            return released
        stuck = limit / np.maximum(np.abs(self.target - self.start_velocity), self._least_remaining)
        # A stuck gain only helps a joint that still has a velocity error; one at its target velocity yet
        # overloaded (two legs fighting through the ground) or already on a lowered gain is held instead.
        stiff = (self.gain >= kv) & (stuck < 0.5 * kv)
        hold = over & ~stiff
        self.gain = np.where(over & stiff, stuck, np.where(hold, 0.0, self.gain))
        self.bias = np.where(hold, np.sign(torque) * limit, self.bias)
        self._write(model, data)
        return True

    def _record(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """Motor and stop-row torques of the solve just done; returns the joint velocities and servo torques."""
        velocity = data.qvel[self.dof]
        torque = self.gain * (self.setpoint - velocity)
        if self.bias is not self._no_bias:   # (adding the shared zeros could only turn -0.0 into 0.0)
            torque += self.bias
        self.applied = torque
        if self._any_stop:   # at a stop the servo is the stop row; the motor is the constant torque
            self.applied = np.where(self._at_stop, self.bias, torque)
            self.stop_torque = torque - self.applied
        elif self.stop_torque is not self._no_bias:
            self.stop_torque = self._no_bias
        return velocity, torque

    def _stop_runaways(self, model: mujoco.MjModel, data: mujoco.MjData, velocity: np.ndarray) -> bool:
        """The step's last solve (``velocity`` its joint velocities) is kept unchecked, and in a flailing robot
        it may be the first with its set of held motors and released stop rows. If a held motor or low-gain
        servo drove its joint more than `RUNAWAY_RAD_S` past its target velocity, or a released stop row let
        its joint into the stop that much faster than the row allows, solve the step again from its start
        with those motors stiff and those rows held. Returns whether it did (``re_solves`` counts it)."""
        if self._step_start is None or (self.gain is self._stiff and not self._any_stop):
            return False   # every servo stiff and no stop row: nothing can have run away
        kv = self.params.motor_kv
        beyond = (velocity - self.target) * np.where(self.bias != 0.0, self.bias, self.target - self.start_velocity)
        runaway = (self.gain < kv) & (beyond > 0.0) & (np.abs(velocity - self.target) > RUNAWAY_RAD_S)
        if self._any_stop:
            runaway &= ~self._at_stop
            runaway |= self._at_stop & (self.gain == 0.0) \
                & (self.stop_side * (velocity - self.setpoint) > RUNAWAY_RAD_S)   # a released row: held again
        if not np.count_nonzero(runaway):
            return False
        self.gain = np.where(runaway, kv, self.gain)
        self.bias = np.where(runaway & ~self._at_stop, 0.0, self.bias)   # at a stop the bias is the motor's
        self._write(model, data)
        qpos, qvel, warmstart, time_s = self._step_start
        data.qpos[:], data.qvel[:], data.qacc_warmstart[:] = qpos, qvel, warmstart
        data.time = time_s
        mujoco.mj_step(model, data)
        self.re_solves += 1
        self.steps += 1
        return True
