"""The default self-localization: an extended Kalman filter on the torso pose (x, y, heading), team frame.

* Predict, every cycle: heading += the gyro's yaw change (from the orientation filter); position += the
  motion controller's odometry when it gives one (none exists yet: then process noise alone covers walking,
  ``default_config()['walk_speed_m_s']``).
* Correct, every vision frame: each flag/goal post gives a range (ground distance from the camera point)
  and a bearing, each field-line end point a distance to its matched model line; sequential scalar updates
  (the noises are independent), each behind a Mahalanobis gate.
* Widen the covariance where the triangulation disagrees beyond 3 sigma (innovation-based process noise,
  for motion the model did not see).
* Start and restart from the seed's triangulation (:mod:`agent.localization.triangulation`): at the first
  frame with 2 landmarks, and whenever triangulation disagrees with the filter for ``reset_frames`` frames in
  a row (a beam, a referee move, a fall that turned the robot).

Why an EKF and not particles: with 0.1 % range noise (REFERENCE §3.5) the posterior is unimodal and tight
whenever a pair of landmarks is in view, so a Gaussian fits it; triangulation handles the global start.
Pure Python floats on purpose: 3x3 algebra is cheaper without numpy's call overhead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from agent.localization.triangulation import triangulate
from agent.world.field import Segment
from agent.world.frames import Pose2D, wrap_angle_rad
from agent.world.vision import VisionFrame
from agent.protocol.constants import CYCLE_S


def default_config() -> dict[str, float]:
    """Noise and gate parameters; every key can be overridden by name in :class:`EkfLocalizer`."""
    return {
        # [m/s] position process noise scale with no odometry; 1.5 measured best of 0.6 / 1.0 / 1.5 on the
        # walking scenario of benchmarks/bench_localization.py (median 5.5 / 3.6 / 2.8 cm; standing 7-8 mm)
        "walk_speed_m_s": 1.5,
        "odometry_noise": 0.2,  # [1] position noise as a fraction of the odometry step
        "yaw_noise_rad_s": math.radians(2.0),  # [rad/s] heading process noise (gyro integration, slips)
        "range_noise_m": 0.02,  # [m] range noise floor (calibration 5 mm per axis, camera height)
        "range_noise_rel": 0.004,  # [1] range noise per metre (0.0965 % vision noise + tilt)
        "bearing_noise_rad": math.radians(0.4),  # [rad] bearing noise (0.148° vision noise + tilt + HJ rounding)
        "line_noise_m": 0.05,  # [m] line end point distance noise floor
        "line_noise_rel": 0.01,  # [1] per metre of range
        "line_match_m": 0.6,  # [m] max end point distance to a model line to match it
        "line_match_rad": math.radians(12.0),  # [rad] max angle between a seen and a model line
        "line_min_length_m": 0.4,  # [m] shorter seen segments are ignored (direction unreliable)
        "max_lines": 8,  # the longest this many seen segments per frame are used
        "line_max_heading_sd_rad": math.radians(6.0),  # [rad] use lines only when the heading is this sure
        "gate_chi2": 12.0,  # Mahalanobis gate for one scalar measurement (about 3.5 sigma)
        "triangulation_sd_m": 0.05,  # [m] typical single-frame triangulation error (for the widening test)
        "triangulation_sd_rad": math.radians(1.0),  # [rad] same, heading
        "reset_m": 1.0,  # [m] triangulation this far from the filter counts as disagreeing
        "reset_frames": 4,  # disagreeing frames in a row before a restart from triangulation
        "init_sd_m": 0.3,  # [m] position sd after a (re)start
        "init_sd_rad": math.radians(8.0),  # [rad] heading sd after a (re)start
        "localized_sd_m": 0.5,  # [m] position sd below which the robot counts as localized
    }



class EkfLocalizer:
    """EKF over (x, y, heading) with landmark range/bearing and field-line updates.

    Args:
        landmarks: landmark name -> team-frame (x, y) [m].
        lines: field-line segments in the team frame.
        **overrides: entries of :func:`default_config` by name.

    Raises:
        KeyError: an override names no parameter.
    """

    name = "ekf"

    def __init__(self, landmarks: Mapping[str, tuple[float, float]], lines: Sequence[Segment] = (),
                 **overrides: float) -> None:
        config = default_config()
        unknown = set(overrides) - set(config)
        if unknown:
            raise KeyError(f"unknown EKF parameter(s) {sorted(unknown)}; known: {sorted(config)}")
        config.update(overrides)
        self.config = config
        self.landmarks = dict(landmarks)
        # Model lines as (unit direction, unit normal, offset along the normal, extent along the direction),
        # bucketed so a seen segment is only compared with lines of about its direction: along x, along y,
        # other (the centre-circle chords, compared only near the circle).
        self._lines_x: list[tuple[float, ...]] = []
        self._lines_y: list[tuple[float, ...]] = []
        self._lines_other: list[tuple[float, ...]] = []
        self._other_radius = (math.inf, 0.0)
        for (ax, ay), (bx, by) in lines:
            length = math.hypot(bx - ax, by - ay)
            ux, uy = (bx - ax) / length, (by - ay) / length
            line = (ux, uy, -uy, ux, -uy * ax + ux * ay, ux * ax + uy * ay, ux * bx + uy * by)
            if abs(uy) < 1e-9:
                self._lines_x.append(line)
            elif abs(ux) < 1e-9:
                self._lines_y.append(line)
            else:
                self._lines_other.append(line)
                near, far = self._other_radius
                middle = math.hypot((ax + bx) / 2, (ay + by) / 2)
                self._other_radius = (min(near, middle), max(far, math.hypot(ax, ay), math.hypot(bx, by)))
        self.state: list[float] | None = None
        self.cov: list[list[float]] = [[0.0] * 3 for _ in range(3)]
        self._disagreements = 0
        self.last_triangulation: Pose2D | None = None
        self.resets = 0

    def reset(self) -> None:
        """Forget the pose (a new connection, a side change)."""
        self.state = None
        self._disagreements = 0

    # --- predict ---------------------------------------------------------------------------------------
    def predict(self, yaw_delta_rad: float, odometry_m: tuple[float, float] | None = None,
                dt_s: float = CYCLE_S) -> None:
        """Advance one cycle: heading by the gyro's yaw change, position by odometry (ego forward, left)."""
        if self.state is None:
            return
        c = self.config
        x, y, th = self.state
        q_th = (c["yaw_noise_rad_s"] ** 2) * dt_s
        if odometry_m is None:
            q_xy = (c["walk_speed_m_s"] * dt_s) ** 2
        else:
            f, l = odometry_m
            cs, sn = math.cos(th), math.sin(th)
            x, y = x + cs * f - sn * l, y + sn * f + cs * l
            q_xy = (c["odometry_noise"] * math.hypot(f, l)) ** 2 + 1e-6
        self.state = [x, y, wrap_angle_rad(th + yaw_delta_rad)]
        p = self.cov
        p[0][0] += q_xy
        p[1][1] += q_xy
        p[2][2] += q_th

    # --- correct ---------------------------------------------------------------------------------------
    def _scalar_update(self, residual: float, h: tuple[float, float, float], variance: float) -> bool:
        """One scalar measurement z - h(x) = residual with Jacobian h; False if the gate rejected it."""
        (p00, p01, p02), (p10, p11, p12), (p20, p21, p22) = self.cov
        h0, h1, h2 = h
        ph0 = p00 * h0 + p01 * h1 + p02 * h2
        ph1 = p10 * h0 + p11 * h1 + p12 * h2
        ph2 = p20 * h0 + p21 * h1 + p22 * h2
        s = h0 * ph0 + h1 * ph1 + h2 * ph2 + variance
        if residual * residual > self.config["gate_chi2"] * s:
            return False
        k0, k1, k2 = ph0 / s, ph1 / s, ph2 / s
        st = self.state
        st[0] += k0 * residual  # type: ignore[index]
        st[1] += k1 * residual  # type: ignore[index]
        st[2] = wrap_angle_rad(st[2] + k2 * residual)  # type: ignore[index]
        # P - K (P h)^T; P stays symmetric because P h is the column P·h.
        self.cov = [[p00 - k0 * ph0, p01 - k0 * ph1, p02 - k0 * ph2],
                    [p10 - k1 * ph0, p11 - k1 * ph1, p12 - k1 * ph2],
                    [p20 - k2 * ph0, p21 - k2 * ph1, p22 - k2 * ph2]]
        return True

    def _start(self, pose: Pose2D) -> None:
        c = self.config
        self.state = [pose.x_m, pose.y_m, pose.heading_rad]
        self.cov = [[c["init_sd_m"] ** 2, 0.0, 0.0], [0.0, c["init_sd_m"] ** 2, 0.0],
                    [0.0, 0.0, c["init_sd_rad"] ** 2]]
        self._disagreements = 0
        self.resets += 1

    def correct(self, frame: VisionFrame) -> None:
        """Fuse one vision frame."""
        guess = triangulate(frame, self.landmarks)
        self.last_triangulation = guess
        if self.state is None:
            if guess is None:
                return
            self._start(guess)
        elif guess is not None:
            far = math.hypot(guess.x_m - self.state[0], guess.y_m - self.state[1]) > self.config["reset_m"]
            self._disagreements = self._disagreements + 1 if far else 0
            if self._disagreements >= self.config["reset_frames"]:
                self._start(guess)
            else:
                self._widen_toward(guess)
        self._landmark_updates(frame)
        if self.cov[2][2] <= self.config["line_max_heading_sd_rad"] ** 2:
            self._line_updates(frame)

    def _widen_toward(self, guess: Pose2D) -> None:
        """Innovation-based process noise: where the triangulation is farther from the state than the state's
        own variance plus the triangulation's explain (3 sigma), the motion model missed something (no
        odometry while walking, a push, a slip), so that variance grows to the squared discrepancy. Without
        this the gates would reject every landmark of a robot that moved unseen by the model."""
        c, p = self.config, self.cov
        x, y, heading = self.state  # type: ignore[misc]
        for index, error, noise in ((0, guess.x_m - x, c["triangulation_sd_m"]),
                                    (1, guess.y_m - y, c["triangulation_sd_m"]),
                                    (2, wrap_angle_rad(guess.heading_rad - heading), c["triangulation_sd_rad"])):
            if error * error > 9.0 * (p[index][index] + noise * noise):
                p[index][index] = error * error

    def _landmark_updates(self, frame: VisionFrame) -> None:
        c = self.config
        of, ol = frame.camera_offset
        for name, obs in frame.landmarks.items():
            landmark = self.landmarks.get(name)
            if landmark is None:
                continue
            for kind in (0, 1):  # range, then bearing
                x, y, th = self.state  # type: ignore[misc]
                cs, sn = math.cos(th), math.sin(th)
                cx, cy = x + cs * of - sn * ol, y + sn * of + cs * ol
                dcx, dcy = -sn * of - cs * ol, cs * of - sn * ol  # d(camera)/d(heading)
                dx, dy = landmark[0] - cx, landmark[1] - cy
                q = dx * dx + dy * dy
                r = math.sqrt(q)
                if r < 1e-6:
                    break
                if kind == 0:
                    sd = c["range_noise_m"] + c["range_noise_rel"] * obs.range_m
                    h = (-dx / r, -dy / r, -(dx * dcx + dy * dcy) / r)
                    self._scalar_update(obs.range_m - r, h, sd * sd)
                else:
                    sd = c["bearing_noise_rad"] + c["range_noise_m"] / max(obs.range_m, 0.5)
                    predicted = math.atan2(dy, dx) - th
                    h = (dy / q, -dx / q, (dy * dcx - dx * dcy) / q - 1.0)
                    self._scalar_update(wrap_angle_rad(obs.bearing_rad - predicted), h, sd * sd)

    def _line_updates(self, frame: VisionFrame) -> None:
        c = self.config
        sin_max = math.sin(c["line_match_rad"])
        match_m = c["line_match_m"]
        # The longest segments carry most of the information; a cap keeps the per-frame cost bounded.
        segments = sorted(((math.hypot(b[0] - a[0], b[1] - a[1]), a, b) for a, b in frame.lines), reverse=True)
        for length, (af, al), (bf, bl) in segments[:int(c["max_lines"])]:
            if length < c["line_min_length_m"]:
                break
            x, y, th = self.state  # type: ignore[misc]
            cs, sn = math.cos(th), math.sin(th)
            ax, ay = x + cs * af - sn * al, y + sn * af + cs * al
            bx, by = x + cs * bf - sn * bl, y + sn * bf + cs * bl
            dx, dy = (bx - ax) / length, (by - ay) / length
            candidates = self._lines_x if abs(dy) <= sin_max else self._lines_y if abs(dx) <= sin_max else ()
            near, far = self._other_radius
            if min(math.hypot(ax, ay), math.hypot(bx, by)) < far + match_m and \
                    max(math.hypot(ax, ay), math.hypot(bx, by)) > near - match_m:
                candidates = [*candidates, *self._lines_other]
            best, best_cost = None, math.inf
            for line in candidates:  # cheapest tests first
                ux, uy, nx, ny, offset, lo, hi = line
                sin_angle = abs(dx * uy - dy * ux)
                if sin_angle > sin_max:
                    continue
                da, db = abs(nx * ax + ny * ay - offset), abs(nx * bx + ny * by - offset)
                if da > match_m or db > match_m:
                    continue
                ta, tb = ux * ax + uy * ay, ux * bx + uy * by
                if min(ta, tb) < lo - 0.5 or max(ta, tb) > hi + 0.5:
                    continue
                cost = da + db + sin_angle
                if cost < best_cost:
                    best, best_cost = line, cost
            if best is None:
                continue
            _, _, nx, ny, offset, _, _ = best
            for f, l in ((af, al), (bf, bl)):
                x, y, th = self.state  # type: ignore[misc]
                cs, sn = math.cos(th), math.sin(th)
                px, py = x + cs * f - sn * l, y + sn * f + cs * l
                dpx, dpy = -sn * f - cs * l, cs * f - sn * l
                sd = c["line_noise_m"] + c["line_noise_rel"] * math.hypot(f, l)
                self._scalar_update(-(nx * px + ny * py - offset), (nx, ny, nx * dpx + ny * dpy), sd * sd)

    # --- belief ----------------------------------------------------------------------------------------
    @property
    def pose(self) -> Pose2D | None:
        """The torso pose in the team frame, or None before the first triangulation."""
        if self.state is None:
            return None
        return Pose2D(self.state[0], self.state[1], self.state[2])

    @property
    def position_sd_m(self) -> float:
        """Standard deviation of the position (root of the mean of the x and y variances) [m]; inf if unknown."""
        if self.state is None:
            return math.inf
        return math.sqrt(max(0.0, (self.cov[0][0] + self.cov[1][1]) / 2.0))

    @property
    def localized(self) -> bool:
        """The pose is known to within ``localized_sd_m``."""
        return self.position_sd_m < self.config["localized_sd_m"]
