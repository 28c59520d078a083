"""Sense messages of our server: exact bytes, predicate order, values of a known state (REFERENCE §3.3-3.4)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from agent.protocol.perceptors import GameState, Hear, Polar, See, VisibleLine, VisibleObject, VisiblePlayer
from agent.protocol.sense import format_sense
from sim.inprocess import InProcessHost
from sim.perceptors import body_sense, wire_joint_order
from sim.vision import VisionConfig
from tests.sim.scripted import Scripted, engine, predicate_names, run_until

WIRE_JOINTS = ("hj1 hj2 raj1 raj2 raj3 raj4 laj1 laj2 laj3 laj4 rlj1 rlj2 rlj3 rlj4 rlj5 rlj6 "
               "llj1 llj2 llj3 llj4 llj5 llj6").split()


def test_every_perceptor_kind_has_the_server_bytes() -> None:
    joints = tuple(WIRE_JOINTS)
    angles = [float(i) for i in range(22)]
    angles[3] = -61.93
    see = See((VisibleObject("G1R", 9.12, 12.4, 4.71), VisibleObject("B", 2.31, -8.52, -12.66)),
              (VisiblePlayer("Rivals", 4, {"head": Polar(5.02, 20.11, 0.93)}),),
              (VisibleLine(Polar(8.44, -33.05, -3.51), Polar(10.86, 52.2, -2.93)),))
    sense = body_sense(104.36, GameState(3, "right", 0, 1, 41.22, "PlayOn"),
                       [Hear("Mine", 41.26, None, "c,4,-3,2,1,0"), Hear("Rivals", 41.28, -47.5, "xk29")],
                       [0.57, -12.4, 3.06], [0.12, -0.33, 9.79], joints, angles,
                       {"rf": (np.array([0.01, -0.03, -0.01]), np.array([-0.41, 0.96, 23.18]))}, see)
    text = format_sense(sense).decode()
    assert text.startswith(
        "(time (now 104.36))(GS (unum 3) (team right) (sl 0) (sr 1) (t 41.22) (pm PlayOn))"
        "(hear Mine 41.26 self c,4,-3,2,1,0)(hear Rivals 41.28 -47.50 xk29)"
        "(GYR (n torso) (rt 0.57 -12.40 3.06))(ACC (n torso) (a 0.12 -0.33 9.79))"
        "(HJ (n hj1) (ax 0.00))(HJ (n hj2) (ax 1.00))"
        "(See (G1R (pol 9.12 12.40 4.71)) (B (pol 2.31 -8.52 -12.66)) "
        "(P (team Rivals) (id 4) (head (pol 5.02 20.11 0.93))) (L (pol 8.44 -33.05 -3.51) (pol 10.86 52.20 -2.93)))"
        "(HJ (n raj1) (ax 2.00))(HJ (n raj2) (ax -61.93))")
    assert "(HJ (n rlj5) (ax 14.00))(FRP (n rf) (c 0.01 -0.03 -0.01) (f -0.41 0.96 23.18))(HJ (n rlj6) (ax 15.00))" \
        in text
    assert text.endswith("(HJ (n llj6) (ax 21.00))")
    assert "AgentState" not in text


def test_wire_joint_order_of_each_robot_type() -> None:
    assert wire_joint_order(0)[0] == tuple(WIRE_JOINTS)
    names = wire_joint_order(4)[0]
    assert names.index("rlj7") == names.index("rlj6") + 1 and names[-1] == "llj7"


@pytest.fixture(scope="module")
def standing_messages() -> list[bytes]:
    """Messages of one robot that inits, beams to (-3, 2, 0) and stands 2 s, noise off."""
    sim = engine()
    host = InProcessHost(sim)
    agent = Scripted({0: b"(init (unum 5)(teamname Mine))(syn)", 2: b"(beam -3 2 0)(syn)"})
    host.add(agent)
    run_until(host, agent, 110)
    return agent.received


def test_standing_robot_percepts(standing_messages: list[bytes]) -> None:
    last = standing_messages[-1].decode()
    # At rest: ACC (0, 0, 9.81) in torso axes (the real server: exactly that; here the heels sink 0.3 mm
    # deeper than the toes, a 0.1° tilt, so y may read 0.02), GYR 0, feet loaded with half the weight each.
    acc = re.search(r"\(ACC \(n torso\) \(a (\S+) (\S+) (\S+)\)\)", last).groups()  # type: ignore[union-attr]
    assert acc[0] in ("0.00", "-0.00") and abs(float(acc[1])) <= 0.03 and acc[2] == "9.81"
    gyr = re.search(r"\(GYR \(n torso\) \(rt (\S+) (\S+) (\S+)\)\)", last).groups()  # type: ignore[union-attr]
    assert all(abs(float(v)) <= 0.05 for v in gyr)
    for foot in ("lf", "rf"):
        c = re.search(rf"\(FRP \(n {foot}\) \(c (\S+) (\S+) (\S+)\) \(f (\S+) (\S+) (\S+)\)\)", last)
        assert c is not None
        values = [float(v) for v in c.groups()]
        assert values[1] == pytest.approx(-0.01, abs=0.005) and values[2] == -0.01
        assert values[5] == pytest.approx(22.6, abs=0.3)
    assert all(f"(HJ (n {j}) (ax " in last for j in WIRE_JOINTS)
    assert re.search(r"\(HJ \(n \w+\) \(ax (?!-?0\.0[0-2]\))", last) is None   # every joint held at ~0


def test_predicate_order(standing_messages: list[bytes]) -> None:
    with_vision = next(m for m in standing_messages[60:] if b"(See" in m)
    expected = (["time", "GS", "GYR", "ACC", "HJ hj1", "HJ hj2", "See"]
                + [f"HJ {j}" for j in WIRE_JOINTS[2:15]] + ["FRP rf", "HJ rlj6"]
                + [f"HJ {j}" for j in WIRE_JOINTS[16:21]] + ["FRP lf", "HJ llj6"])
    assert predicate_names(with_vision) == expected


def test_game_state_identity_only_in_the_first_message_after_init(standing_messages: list[bytes]) -> None:
    with_identity = [i for i, m in enumerate(standing_messages) if b"(unum " in m]
    assert with_identity == [2]   # init answered message 0, applied before message 2 was made
    assert b"(GS (unum 5) (team left) (sl 0) (sr 0) (t 0.00) (pm BeforeKickOff))" in standing_messages[2]


def test_vision_every_third_message_from_the_first(standing_messages: list[bytes]) -> None:
    assert [i for i, m in enumerate(standing_messages[:12]) if b"(See" in m] == [0, 3, 6, 9]


def test_landmark_at_a_known_place_has_the_expected_polar_values() -> None:
    sim = engine()
    host = InProcessHost(sim)
    agent = Scripted({0: b"(init (unum 1)(teamname Mine))(syn)"})
    host.add(agent)
    run_until(host, agent, 2)
    key = next(iter(sim.world.by_key))
    host.run(3)
    # Stand the robot exactly, facing +x at (-14.2, 9.2): the head centre is 0.155 m above the torso.
    sim.world.place_robot(key, -14.2, 9.2, 0.0, z_m=0.385)
    sim.world.end_cycle()
    frame = sim._vision([sim.agents[key]])
    if not frame:   # not this agent's vision cycle: take the next one
        sim.agents[key].perceptor_cycles += 3 - sim.agents[key].perceptor_cycles % 3
        frame = sim._vision([sim.agents[key]])
    seen = {o.name: o for o in frame[key].objects}
    camera = np.array([-14.2, 9.2, 0.385 + 0.155])
    rel = np.array([15.0, 10.0, 0.0]) - camera           # F1R, world frame; the camera looks along +x
    assert seen["F1R"].distance_m == pytest.approx(float(np.linalg.norm(rel)), abs=1e-6)
    assert seen["F1R"].azimuth_deg == pytest.approx(math.degrees(math.atan2(rel[1], rel[0])), abs=1e-6)
    assert seen["F1R"].elevation_deg == pytest.approx(math.degrees(math.atan2(rel[2], math.hypot(*rel[:2]))),
                                                      abs=1e-6)
    assert "F1L" not in seen and "G1L" not in seen      # behind the camera
    own = frame[key].players
    assert len(own) == 1 and own[0].team == "Mine" and set(own[0].parts) == {"rlowerarm", "llowerarm"}
    # Own lower arms at zero pose: centre (±0.098, 0.14, 0.084) from the torso, camera at (0, 0, 0.155);
    # the real server reports (0.18, ±35.1..36.1, -21.4..-24.5) with its calibration error (samples).
    arm = np.array([0.098, 0.14, 0.084 - 0.155])
    assert own[0].parts["llowerarm"].distance_m == pytest.approx(float(np.linalg.norm(arm)), abs=1e-3)
    assert own[0].parts["llowerarm"].azimuth_deg == pytest.approx(90.0 - math.degrees(math.atan2(0.14, 0.098)),
                                                                  abs=0.2)
    assert own[0].parts["rlowerarm"].azimuth_deg == pytest.approx(-own[0].parts["llowerarm"].azimuth_deg, abs=0.2)
    assert own[0].parts["rlowerarm"].elevation_deg == pytest.approx(
        math.degrees(math.atan2(arm[2], math.hypot(arm[0], arm[1]))), abs=0.2)


def test_noise_is_seeded_and_small() -> None:
    def first_vision(seed: int) -> bytes:
        sim = engine(seed=seed, noise=True)
        host = InProcessHost(sim)
        agent = Scripted()
        host.add(agent)
        run_until(host, agent, 1)
        return agent.received[0]
    assert first_vision(3) == first_vision(3)
    assert first_vision(3) != first_vision(4)


# ---- against the real server: the line list and its order --------------------------------------------
def _real_frame(agent: str, index: int) -> tuple[dict[str, tuple[float, ...]], list[tuple[float, ...]]]:
    from tests.agent.protocol_samples import records
    message = next(str(r["msg"]) for r in records() if r["k"] == "recv" and r["a"] == agent and r["i"] == index)
    see = message[message.index("(See"):]
    number = r"(-?[\d.]+)"
    objects = {name: tuple(map(float, v)) for name, *v in
               re.findall(rf"\((F1L|F2L|F1R|F2R|G1L|G2L|G1R|G2R) \(pol {number} {number} {number}\)\)", see)}
    lines = [tuple(map(float, v)) for v in re.findall(
        rf"\(L \(pol {number} {number} {number}\) \(pol {number} {number} {number}\)\)", see)]
    return objects, lines


def _camera(pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    x, y, z, yaw = pose
    rotation = np.array([[math.cos(yaw), -math.sin(yaw), 0.0], [math.sin(yaw), math.cos(yaw), 0.0], [0, 0, 1.0]])
    return np.array([x, y, z]), rotation


def _fit_camera(objects: dict[str, tuple[float, ...]], guess: tuple[float, ...]) -> np.ndarray:
    """Camera (x, y, z, yaw) of an upright robot that best explains the seen landmarks (Gauss-Newton)."""
    from sim.field import LANDMARKS
    from sim.vision import polar
    names = list(objects)
    observed = np.array([objects[n] for n in names])
    points = np.array([LANDMARKS[n] for n in names])

    def residual(pose: np.ndarray) -> np.ndarray:
        camera, rotation = _camera(pose)
        return (np.stack(polar((points - camera) @ rotation), axis=1) - observed).ravel()

    pose = np.array(guess, dtype=float)
    for _ in range(30):
        r = residual(pose)
        jacobian = np.stack([(residual(pose + step) - r) / 1e-6 for step in np.eye(4) * 1e-6], axis=1)
        pose += np.linalg.lstsq(jacobian, -r, rcond=None)[0]
    return pose


@pytest.mark.parametrize("agent, index, guess", [
    ("L", 0, (0.0, -1.0, 1.6, 0.0)),            # spawned at (0, -1), facing +y
    ("L", 3, (-14.2, 9.2, 0.55, -math.pi / 2)),   # left init spot, facing +x
    ("R", 3, (14.2, 9.2, 0.55, math.pi / 2)),     # right init spot, facing -x
])
def test_lines_come_in_the_real_servers_order_and_direction(agent: str, index: int,
                                                            guess: tuple[float, ...]) -> None:
    from sim.vision import Observer, see
    objects, real_lines = _real_frame(agent, index)
    camera, rotation = _camera(_fit_camera(objects, guess))
    ours = see([Observer(camera, rotation, np.zeros(3), "X", 1)], np.array([0.0, 0.0, 0.042]), [],
               np.random.default_rng(0), VisionConfig(noise=False, calibration=False))[0].lines
    assert len(ours) == len(real_lines)
    for real, line in zip(real_lines, ours):
        far = 0 if real[0] > real[3] else 1     # compare the far end: the fit error grows near the camera
        ours_far = (line.begin, line.end)[far]
        assert ours_far.distance_m == pytest.approx(real[3 * far], abs=0.3)
        assert ours_far.azimuth_deg == pytest.approx(real[3 * far + 1], abs=1.5)
