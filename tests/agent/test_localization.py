"""Localization: triangulation geometry and ambiguity, the seed's FIFO filter (Algorithm 1), the EKF."""

from __future__ import annotations

import math
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from agent.errors import ConfigError
from agent.localization import EkfLocalizer, FifoFilter, SeedLocalizer, make_localizer, triangulate
from agent.localization.triangulation import intersect_pair
from agent.protocol import parse_sense
from agent.world.field import FIELD_LINES, LANDMARKS
from agent.world.frames import Pose2D, wrap_angle_rad
from agent.world.vision import GroundObservation, VisionFrame
from agent.world_model import WorldModel
from tests.agent import synthetic_world as synth

TEAM_LANDMARKS = {name: (p[0], p[1]) for name, p in LANDMARKS.items()}


def ideal_frame(x, y, heading, names=None) -> VisionFrame:
    """Exact ground observations of landmarks from a pose (camera at the torso's ground point)."""
    pose = Pose2D(x, y, heading)
    landmarks = {}
    for name, (lx, ly) in TEAM_LANDMARKS.items():
        if names is not None and name not in names:
            continue
        forward, left = pose.to_ego(lx, ly)
        landmarks[name] = GroundObservation(math.hypot(forward, left), math.atan2(left, forward), forward, left,
                                            math.hypot(forward, left))
    return VisionFrame(0.0, 0.54, (0.0, 0.0), landmarks, None, ())


@settings(max_examples=200, deadline=None)
@given(st.floats(-14.5, 14.5), st.floats(-9.5, 9.5), st.floats(-math.pi, math.pi),
       st.sampled_from([("F1L", "G1L"), ("G1R", "G2R"), ("F1R", "F2R"), ("F1L", "F1R"), ("F2L", "G2L", "G1L")]))
def test_triangulation_recovers_the_pose_and_resolves_the_mirror_candidate(x, y, heading, names):
    lx = [TEAM_LANDMARKS[n][0] for n in names]
    # Robots collinear with the two landmarks have no defined intersection side: skip those.
    if len(set(lx)) == 1 and abs(x - lx[0]) < 0.3:
        return
    pose = triangulate(ideal_frame(x, y, heading, names), TEAM_LANDMARKS)
    assert pose is not None
    assert (pose.x_m, pose.y_m) == pytest.approx((x, y), abs=1e-6)
    assert abs(wrap_angle_rad(pose.heading_rad - heading)) < 1e-6


def test_triangulation_needs_two_landmarks():
    assert triangulate(ideal_frame(0.0, 0.0, 0.0, ("F1R",)), TEAM_LANDMARKS) is None


def test_circles_that_miss_use_the_closest_approach():
    a = GroundObservation(4.0, 0.5, 0, 0, 4.0)
    b = GroundObservation(4.0, -0.5, 0, 0, 4.0)
    point = intersect_pair((0.0, 5.0), a, (0.0, -5.0), b)  # radii sum 8 < distance 10
    assert point == pytest.approx((0.0, 0.0), abs=1e-9)  # on the line between the centres, at the radical line


def test_triangulation_accounts_for_the_camera_offset():
    frame = ideal_frame(-3.0, 1.0, 0.7)
    # Camera 5 cm ahead of the torso: observations are taken from there.
    pose = Pose2D(-3.0, 1.0, 0.7)
    cam = pose.to_team(0.05, 0.0)
    shifted = {}
    for name, obs in frame.landmarks.items():
        f, l = Pose2D(cam[0], cam[1], 0.7).to_ego(*TEAM_LANDMARKS[name])
        shifted[name] = GroundObservation(math.hypot(f, l), math.atan2(l, f), f + 0.05, l, obs.distance_m)
    result = triangulate(VisionFrame(0.0, 0.54, (0.05, 0.0), shifted, None, ()), TEAM_LANDMARKS)
    assert (result.x_m, result.y_m) == pytest.approx((-3.0, 1.0), abs=1e-9)


# --- Algorithm 1 -----------------------------------------------------------------------------------------
def p(x, y=0.0, h=0.0):
    return Pose2D(x, y, h)


def test_fifo_mean_of_agreeing_estimates_and_circular_heading():
    fifo = FifoFilter()
    fifo.add(p(1.0, 0.0, math.pi - 0.1))
    mean = fifo.add(p(1.2, 0.2, -math.pi + 0.1))
    assert (mean.x_m, mean.y_m) == pytest.approx((1.1, 0.1))
    assert abs(wrap_angle_rad(mean.heading_rad - math.pi)) < 1e-9


def test_fifo_disagreeing_estimate_is_dropped_and_pops_the_oldest():
    fifo = FifoFilter()
    for x in (0.0, 0.1, 0.2):
        fifo.add(p(x))
    mean = fifo.add(p(5.0))  # > 2 m from the mean: dropped, oldest (0.0) popped
    assert [e.x_m for e in fifo.queue] == [0.1, 0.2]
    assert mean.x_m == pytest.approx(0.15)


def test_fifo_persistent_jump_empties_the_queue_and_restarts_there():
    fifo = FifoFilter()
    for x in (0.0, 0.1, 0.2):
        fifo.add(p(x))
    for _ in range(3):
        fifo.add(p(5.0))
    assert fifo.mean is None and not fifo.queue
    assert fifo.add(p(5.0)).x_m == 5.0


def test_fifo_full_queue_keeps_the_last_ten_and_well_localized_from_five():
    fifo = FifoFilter()
    for i in range(4):
        fifo.add(p(0.01 * i))
    assert not fifo.well_localized
    for i in range(4, 15):
        fifo.add(p(0.01 * i))
    assert len(fifo.queue) == 10 and fifo.well_localized
    assert fifo.mean.x_m == pytest.approx(sum(0.01 * i for i in range(5, 15)) / 10)


def test_fifo_2012_quirk_pops_without_pushing_when_full():
    fifo = FifoFilter(pop_without_push_when_full=True)
    for i in range(11):
        fifo.add(p(0.01 * i))
    assert len(fifo.queue) == 9 and fifo.queue[-1].x_m == pytest.approx(0.09)


# --- EKF ---------------------------------------------------------------------------------------------------
def _run(localizer_name, path, seed=3):
    """Feed a WorldModel synthetic noisy frames along a path of world poses; return the final errors."""
    model = WorldModel("Mine", 2, localization=localizer_name)
    rng = random.Random(seed)
    errors = []
    previous = None
    for i, (x, y, heading) in enumerate(path):
        seen = synth.see(x, y, heading, rng=rng, ball=None) if i % 3 == 0 else None
        yaw_rate = 0.0 if previous is None else math.degrees(wrap_angle_rad(heading - previous)) / 0.02
        previous = heading
        model.update(parse_sense(synth.sense_bytes(10.0 + 0.02 * i, see_value=seen, unum=2 if i == 0 else None,
                                                   side="left" if i == 0 else None, gyro=(0.0, 0.0, yaw_rate))))
        if model.pose is not None:
            errors.append((math.hypot(model.pose.x_m - x, model.pose.y_m - y),
                           abs(math.degrees(wrap_angle_rad(model.pose.heading_rad - heading)))))
    return model, errors


def test_ekf_standing_is_within_a_few_centimetres():
    model, errors = _run("ekf", [(-5.0, 3.0, 0.3)] * 60)
    assert model.localized
    assert errors[-1][0] < 0.05 and errors[-1][1] < 1.0


def test_ekf_follows_a_turn_with_the_gyro_where_the_seed_lags():
    turn = [(-5.0, 0.0, math.radians(-40 + 80 * i / 100)) for i in range(100)]  # 40 deg/s
    _, ekf_errors = _run("ekf", turn)
    _, seed_errors = _run("seed", turn)
    ekf_heading = sorted(e[1] for e in ekf_errors[30:])[len(ekf_errors[30:]) // 2]
    seed_heading = sorted(e[1] for e in seed_errors[30:])[len(seed_errors[30:]) // 2]
    assert ekf_heading < 1.0
    assert ekf_heading < seed_heading


def test_ekf_recovers_within_a_few_frames_after_a_teleport():
    path = [(-5.0, 3.0, 0.0)] * 30 + [(-8.0, -2.0, 0.4)] * 45
    _, errors = _run("ekf", path)
    assert errors[29][0] < 0.05
    assert all(position < 0.1 and heading < 1.0 for position, heading in errors[30 + 15:])


def test_ekf_uses_lines_with_a_single_landmark():
    ekf = EkfLocalizer(TEAM_LANDMARKS, FIELD_LINES)
    ekf.correct(ideal_frame(-5.0, 0.0, 0.0, ("G1R", "G2R")))
    assert ekf.pose is not None
    before = ekf.cov[1][1]
    # Robot at (-5, 0) facing 0; the halfway line (x = 0) 5 m ahead, as two ego end points.
    frame = VisionFrame(0.0, 0.54, (0.0, 0.0), {}, None, (), (((5.0, -2.0), (5.0, 2.0)),))
    ekf.correct(frame)
    assert ekf.cov[0][0] < 0.3 ** 2  # a line across the view pins down x


def test_unknown_localizer_and_parameter_are_named():
    with pytest.raises(ConfigError, match="ekf"):
        make_localizer("particles", TEAM_LANDMARKS)
    with pytest.raises(KeyError, match="gate_chi2"):
        EkfLocalizer(TEAM_LANDMARKS, gate_chi3=1.0)
    assert isinstance(make_localizer("seed", TEAM_LANDMARKS), SeedLocalizer)
