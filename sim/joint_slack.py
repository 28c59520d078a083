"""ODE's joint drift, emulated where the robots' legs meet the ball (issue 12: "ODE's joints give").

Why: SimSpark steps ODE once per 20 ms cycle (``dWorldStep``; the world ERP is never set, so ODE's 0.2).
ODE's joints are constraint rows solved at the velocity level with the Jacobians of the step's start; then
every body moves along its new velocity in a straight line. A body turning on a lever therefore leaves the
arc its joints allow by the chord error, about ½ r ω² h² outward per step, and the ERP takes back a fifth of
what has gathered at each step, so about 2.5 r ω² h² stays. The real monitor shows it: walking, both feet
hang 3.3-3.5 mm (median) below where the robot's own joint angles put them, 18.6 mm at the kick's strike,
0.2 mm standing (``motion-studio real joint-slack``). MuJoCo's joints are generalized coordinates and never
separate, so a foot swinging down meets the ball and the ground where the joint angles say, millimetres
higher than the real one (see ``sim.physics_params``, "Joints give").

Model, per tracked body b (any but the torso, whose free joint both engines integrate in a straight line; the
world tracks the legs), per cycle of one 20 ms step:

    a_b = p_b(q_k) + h · J_b(q_k) q̇_{k+1}     where ODE's straight-line update puts the body
    e_b = a_b − p_b(q_{k+1})                    the chord error of this step (MuJoCo: on the arc)
    d_b ← (1 − ERP) · d_b + e_b                 ODE's correction: a fifth per step

and the geoms `bind` is given are moved by their body's d_b (through ``geom_pos`` in the body's frame; their
``geom_sameframe`` is turned off so that MuJoCo reads it). `sim.world.World` gives the legs' ball-side twins:
the ground keeps the joints' geometry, since the real stance foot sinks by its drift while the torso keeps its
height (see ``sim.physics_params``, "Joints give"). Inertia stays where the joints put it, and the torso takes
none of the error (ODE shares each joint's correction between its two bodies by mass): what is modelled is the
displacement the monitor measures, a body against the torso and the joint angles. Orientation errors are left
out. Nothing is fitted: h and ERP are ODE's. One step per cycle (``substeps`` 1, the default) is ODE's case; with
sub-steps the drift is computed over the cycle's last one only.
"""

from __future__ import annotations

import mujoco
import numpy as np

from sim.rows import row_index

#: ODE's default world ERP, which SimSpark keeps (spark/plugin/odeimps/odeworld.cpp sets it only on request).
ODE_WORLD_ERP = 0.2
#: A larger error in one step is not a drift but a jump (a beam, a state restored by the blow-up guard): that
#: body's drift starts again from zero [m]. ODE's per-step error at the fastest joint speed (6.14 rad/s on a
#: 0.3 m lever) is about 2 mm.
JUMP_M = 0.02
# Index orders for a cross product without numpy.cross's overhead on small arrays.
# w x r = (w_y r_z - w_z r_y, w_z r_x - w_x r_z, w_x r_y - w_y r_x): both products' factors in one gather each
# (columns of [angular, linear] and of r), so the cross product costs one multiply instead of four gathers and two.
_W_PAIRS, _R_PAIRS = np.array([1, 2, 0, 2, 0, 1]), np.array([2, 0, 1, 1, 2, 0])


class JointSlack:
    """The drift of the tracked bodies from where their joint angles put them, applied to the geoms given to
    `bind`; see the module docstring.

    Call `bind` after each model (re)compile, `predict` right after the cycle's last ``mj_step`` (poses and
    ``cdof`` are the step's start, ``qvel`` its end; it overwrites ``cvel``), `settle` after the poses are brought
    to the step's end (``mj_kinematics``). `forget` zeroes one robot's drift (beams, restored states).
    """

    def __init__(self, erp: float = ODE_WORLD_ERP) -> None:
        self.erp = erp
        self.bodies = np.zeros(0, dtype=np.intp)
        self.drift_m = np.zeros((0, 3))
        self._ahead = np.zeros((0, 3))
        self._owner_roots = np.zeros(0, dtype=np.intp)
        self._row_of_body = np.zeros(1, dtype=np.intp)

    def bind(self, model: mujoco.MjModel, robot_bodies: list[tuple[int, np.ndarray]], geoms: np.ndarray) -> None:
        """Index the tracked bodies of each robot: (torso body id, ids of all its bodies) per robot, and the geoms
        moved by their body's drift."""
        bodies, roots, owners = [], [], []
        for torso, ids in robot_bodies:
            for body in ids.tolist():
                if body != torso:
                    bodies.append(body)
                    roots.append(int(model.body_rootid[body]))
                    owners.append(torso)
        self.bodies = np.array(bodies, dtype=np.intp)
        self._roots = np.array(roots, dtype=np.intp)
        self._owner_roots = np.array(owners, dtype=np.intp)
        self.drift_m = np.zeros((len(bodies), 3))
        self._ahead = np.zeros((len(bodies), 3))
        row_of = {body: row for row, body in enumerate(bodies)}
        self._row_of_body = np.full(model.nbody + 1, len(bodies), dtype=np.intp)   # untracked: the zero row
        self._row_of_body[self.bodies] = np.arange(len(bodies))
        geoms = [int(g) for g in geoms if int(model.geom_bodyid[g]) in row_of]
        self._geoms = np.array(geoms, dtype=np.intp)
        self._geom_rows = np.array([row_of[int(model.geom_bodyid[g])] for g in geoms], dtype=np.intp)
        self._nominal = model.geom_pos[self._geoms].copy()
        model.geom_sameframe[self._geoms] = 0
        # Flat indices of the rows read every cycle (``sim.rows.row_index``).
        self._cvel_rows, self._xpos_rows = row_index(self.bodies, 6), row_index(self.bodies, 3)
        self._com_rows = row_index(self._roots, 3)
        self._geom_xmat_rows = row_index(self.bodies[self._geom_rows], 9)
        self._one_geom_per_body = bool(np.array_equal(self._geom_rows, np.arange(len(bodies))))

    def predict(self, model: mujoco.MjModel, data: mujoco.MjData, timestep_s: float) -> None:
        """Where ODE's straight-line update would put each body: its start pose plus h times its velocity (the
        start's Jacobian, the end's joint velocities: ``mj_comVel`` from the step's ``cdof`` and the new ``qvel``;
        nothing reads ``cvel`` again before the next step recomputes it)."""
        if self.bodies.size == 0:
            return
        mujoco.mj_comVel(model, data)
        spatial = data.cvel.reshape(-1).take(self._cvel_rows).reshape(-1, 6)   # [angular, linear] at the tree's com
        position = data.xpos.reshape(-1).take(self._xpos_rows).reshape(-1, 3)
        lever = position - data.subtree_com.reshape(-1).take(self._com_rows).reshape(-1, 3)
        products = spatial.take(_W_PAIRS, axis=1) * lever.take(_R_PAIRS, axis=1)
        linear = spatial[:, 3:] + products[:, :3] - products[:, 3:]   # + w x r
        self._ahead = position + timestep_s * linear

    def settle(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Add this step's chord error to the drift, take back ERP of it, move the geoms by what stays."""
        if self.bodies.size == 0:
            return
        error = self._ahead - data.xpos.reshape(-1).take(self._xpos_rows).reshape(-1, 3)
        # (a ufunc reduce: ndarray.max's Python wrapper cost 1 % of a 1-robot cycle)
        if np.maximum.reduce(np.abs(error), axis=None) > JUMP_M:   # rare: a beam or a restored state
            jumped = (error * error).sum(axis=1) > JUMP_M * JUMP_M
            error[jumped] = 0.0
            self.drift_m[jumped] = 0.0
        self.drift_m *= 1.0 - self.erp
        self.drift_m += error
        if self._geoms.size:
            rotation = data.xmat.reshape(-1).take(self._geom_xmat_rows).reshape(-1, 3, 3)
            drift = self.drift_m if self._one_geom_per_body else self.drift_m[self._geom_rows]
            local = (drift[:, None, :] @ rotation)[:, 0]   # dᵀ R = (Rᵀ d)ᵀ: the drift in the body's frame
            model.geom_pos[self._geoms] = self._nominal + local

    def forget(self, model: mujoco.MjModel, torso_body: int) -> None:
        """Zero the drift of one robot's bodies (it was beamed or its state restored)."""
        if self.bodies.size == 0:
            return
        rows = self._owner_roots == torso_body
        self.drift_m[rows] = 0.0
        geoms = rows[self._geom_rows]
        model.geom_pos[self._geoms[geoms]] = self._nominal[geoms]

    def centres(self, data: mujoco.MjData) -> np.ndarray:
        """Every body's centre [m, (nbody, 3)] where ODE would have it: ``xpos`` plus each tracked body's drift
        (what the real monitor shows)."""
        out = data.xpos.copy()
        if self.bodies.size:
            out[self.bodies] += self.drift_m
        return out

    def rows_of(self, bodies: np.ndarray) -> np.ndarray:
        """Rows of ``drift_m`` that hold these tracked bodies' drift (for a caller that reads them every step).

        Raises:
            ValueError: a body that is not tracked.
        """
        rows = self._row_of_body[np.asarray(bodies, dtype=np.intp)]
        if np.any(rows == len(self.bodies)):
            raise ValueError(f"bodies not tracked by the joint drift: {np.asarray(bodies)[rows == len(self.bodies)]}")
        return rows

    def drift_of(self, bodies: np.ndarray) -> np.ndarray:
        """The drift of each body [m, world frame; (n, 3)]: where ODE would have it, less where its joints put
        it; zero for the torso and any body not tracked."""
        padded = np.vstack([self.drift_m, np.zeros((1, 3))])
        return padded[self._row_of_body[np.asarray(bodies, dtype=np.intp)]]
