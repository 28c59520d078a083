"""Fall detection and stand-up decisions from the world model alone (REFERENCE §7.7): suspicion from gyro or
accelerometer, confirmation by unloaded feet at rest, the side from the accelerometer, success by loaded
feet under an upright torso, retries; played through SkillBehavior with stand-in motions."""

from __future__ import annotations

import math

from agent.motion import MotionController, MotionLibrary
from agent.skills.behavior import SkillBehavior
from agent.skills.standup import (CHECK_TIMEOUT_CYCLES, CONFIRM_CYCLES, CONFIRM_LYING, QUIET_CYCLES, RECOVERY_CYCLES,
                                  SIDE_ROLL_MOTION, UNLOADED_CYCLES, FallWatch, lying_side, standup_side)
from agent.world.state import FootContact
from agent.world_model import WorldModel
from kinematics import JOINT_NAMES
from motions.model import XML, JointTarget, Keyframe, Motion

G = 9.81
BACK = (0.0, G, 0.3)
FRONT = (0.0, -G, 1.5)
SIDE = (G, 1.0, 0.5)
UPRIGHT = (0.0, 1.5, 9.7)
LOADED = {"lf": FootContact((0.0, 0.0, 0.0), (0.0, 0.0, 22.6)), "rf": FootContact((0.0, 0.0, 0.0), (0.0, 0.0, 22.6))}
EDGE_ON = {"lf": FootContact((0.0, 0.0, 0.0), (0.0, 9.9, 0.1))}  # lying: heels touch, no vertical load


def _world(acc=UPRIGHT, gyro=(0.0, 0.0, 0.0), feet=None, up_z=1.0) -> WorldModel:
    world = WorldModel("T", 1)
    _set(world, acc, gyro, feet if feet is not None else LOADED, up_z)
    world.body.joints_rad = {name: 0.0 for name in JOINT_NAMES}
    return world


def _set(world: WorldModel, acc, gyro=(0.0, 0.0, 0.0), feet=None, up_z=None) -> None:
    world.body.acc_m_s2 = acc
    world.body.gyro_deg_s = gyro
    world.body.feet = dict(feet or {})
    if up_z is not None:
        world.body.up_z = up_z


def test_lying_side_from_the_accelerometer():
    assert lying_side(_world(BACK)) == "back"
    assert lying_side(_world(FRONT)) == "front"
    assert lying_side(_world(SIDE)) == "side"
    assert lying_side(_world(UPRIGHT)) is None
    assert lying_side(_world((0.0, 30.0, 0.0))) is None  # an impact, not gravity
    assert standup_side(_world(SIDE)) == "back" and standup_side(_world((G, -1.0, 0.5))) == "front"


def test_fall_confirmed_only_after_the_feet_carry_nothing_for_a_while():
    world = _world()
    watch = FallWatch()
    _set(world, UPRIGHT, gyro=(250.0, 0.0, 0.0), feet=LOADED, up_z=0.9)  # the fall starts: gyro spike
    watch.update(world)
    assert watch.suspected and not watch.fallen
    for cycle in range(CONFIRM_LYING - 1):
        _set(world, BACK, feet=EDGE_ON, up_z=0.05)
        watch.update(world)
    assert not watch.fallen
    for cycle in range(CONFIRM_CYCLES - CONFIRM_LYING + 1):
        _set(world, BACK, feet=EDGE_ON, up_z=0.05)
        watch.update(world)
    assert watch.fallen and watch.side == "back"


def test_fall_confirmed_while_a_walk_still_kicks_the_legs():
    """Fallen on its front while the walk goes on: the accelerometer shakes (not at rest) and the feet hit the
    ground every third cycle; the orientation filter still says the torso lies."""
    world = _world()
    watch = FallWatch()
    world.body.pitch_forward_rad = math.radians(80.0)
    for cycle in range(3 * CONFIRM_CYCLES):
        shaken = (3.0, -17.0, 4.0) if cycle % 2 else (-1.0, -4.0, -5.0)
        _set(world, shaken, gyro=(90.0, 40.0, 150.0), feet=LOADED if cycle % 3 == 0 else {}, up_z=-0.25)
        watch.update(world)
    assert watch.fallen and watch.side == "front"


def test_a_bump_is_not_a_fall():
    world = _world()
    watch = FallWatch()
    _set(world, UPRIGHT, gyro=(300.0, 80.0, 0.0), feet=LOADED, up_z=0.95)
    watch.update(world)
    assert watch.suspected
    for _ in range(3 * CONFIRM_CYCLES):
        _set(world, UPRIGHT, feet=LOADED, up_z=0.97)
        watch.update(world)
    assert not watch.fallen and not watch.suspected


def test_lying_with_loaded_feet_is_not_a_fall():
    world = _world()
    watch = FallWatch()
    for _ in range(3 * CONFIRM_CYCLES):  # on the back, but something presses the soles (e.g. feet on a robot)
        _set(world, BACK, feet=LOADED, up_z=0.05)
        watch.update(world)
    assert not watch.fallen
    for _ in range(CONFIRM_CYCLES):
        _set(world, BACK, feet={}, up_z=0.05)
        watch.update(world)
    assert watch.fallen and watch.side == "back"


def test_sitting_with_unloaded_feet_is_a_fall_after_a_while():
    world = _world()
    watch = FallWatch()
    _set(world, UPRIGHT, gyro=(250.0, 0.0, 0.0), feet=LOADED, up_z=0.9)
    watch.update(world)
    for _ in range(UNLOADED_CYCLES - 1):  # sitting on its bottom: torso up, feet in the air
        _set(world, (0.0, 4.0, 8.9), feet={}, up_z=0.9)
        watch.update(world)
    assert not watch.fallen
    watch.update(world)
    assert watch.fallen and watch.side == "back"


def _stand_in(name: str) -> Motion:
    """A two-phase stand-in for a stand-up motion (what it does to the body does not matter here)."""
    phases = [Keyframe("a", 0.04, {"llj3": JointTarget.from_deg(10.0)}, next="b"),
              Keyframe("b", 0.04, {"llj3": JointTarget.from_deg(0.0)}, is_final=True)]
    return Motion(name, phases, source_format=XML, first_phase="a")


def _behavior(roll: bool = False) -> SkillBehavior:
    names = ("standup_back", "standup_front") + ((SIDE_ROLL_MOTION,) if roll else ())
    library = MotionLibrary({name: _stand_in(name) for name in names})
    return SkillBehavior(MotionController(library))


def _cycle(behavior: SkillBehavior, world: WorldModel, cycles: int = 1) -> None:
    for _ in range(cycles):
        world.game.server_time_s += 0.02
        behavior(world)


def _play_to_end(behavior: SkillBehavior, world: WorldModel, name: str) -> None:
    """Cycles until the stand-in motion ``name`` has played once more (at most 30)."""
    before = behavior.motion.completed[name]
    for _ in range(30):
        _cycle(behavior, world)
        if behavior.motion.completed[name] > before:
            return
    raise AssertionError(f"{name} did not end")


def test_behavior_plays_the_side_standup_and_ends_once_the_feet_carry_an_upright_robot():
    behavior, world = _behavior(), _world()
    _set(world, FRONT, feet={}, up_z=0.1)
    _cycle(behavior, world, CONFIRM_CYCLES + QUIET_CYCLES)
    assert behavior.recovering and behavior.standup.sides == ["front"]
    _play_to_end(behavior, world, "standup_front")
    _set(world, UPRIGHT, feet=LOADED, up_z=0.97)
    _cycle(behavior, world, RECOVERY_CYCLES + 1)
    assert not behavior.recovering and behavior.standup.done and behavior.standup.attempts == 1
    assert not behavior.fall_watch.fallen


def test_standup_retries_with_the_side_it_lies_on_now():
    behavior, world = _behavior(), _world()
    _set(world, BACK, feet={}, up_z=0.05)
    _cycle(behavior, world, CONFIRM_CYCLES + 1)
    _play_to_end(behavior, world, "standup_back")
    _set(world, FRONT, feet={}, up_z=0.1)  # it rolled over onto its front instead of standing
    _cycle(behavior, world, 8 + QUIET_CYCLES)
    assert behavior.standup.sides == ["back", "front"]
    assert behavior.recovering


def test_standup_waits_for_the_robot_to_come_to_rest_before_it_reads_the_side():
    behavior, world = _behavior(), _world()
    for _ in range(CONFIRM_CYCLES + 5):  # confirmed while the legs still kick (a walk still playing)
        _set(world, BACK, gyro=(150.0, 40.0, 0.0), feet={}, up_z=0.05)
        _cycle(behavior, world)
    assert behavior.recovering and behavior.standup.attempts == 0
    _set(world, FRONT, feet={}, up_z=0.1)  # it came to rest on its front
    _cycle(behavior, world, QUIET_CYCLES)
    assert behavior.standup.sides == ["front"]


def test_standup_retries_when_not_upright_in_time():
    behavior, world = _behavior(), _world()
    _set(world, BACK, feet={}, up_z=0.05)
    _cycle(behavior, world, CONFIRM_CYCLES + 1)
    _play_to_end(behavior, world, "standup_back")
    _set(world, (0.0, 4.0, 8.9), feet=EDGE_ON, up_z=0.9)  # sitting: upright-ish, feet unloaded, not lying
    _cycle(behavior, world, CHECK_TIMEOUT_CYCLES + 1 + QUIET_CYCLES)
    assert behavior.standup.attempts == 2 and behavior.standup.sides == ["back", "back"]


def test_a_robot_on_its_side_rolls_once_then_stands_up_from_the_side_it_leans_to():
    behavior, world = _behavior(roll=True), _world()
    _set(world, SIDE, feet={}, up_z=0.1)
    _cycle(behavior, world, CONFIRM_CYCLES + QUIET_CYCLES)
    assert behavior.recovering and behavior.standup.attempts == 0
    _play_to_end(behavior, world, SIDE_ROLL_MOTION)
    _cycle(behavior, world, QUIET_CYCLES + 1)  # the roll left it on its side: no second roll
    assert behavior.standup.sides == ["back"]  # SIDE leans back (+y)


def test_after_the_roll_onto_its_back_the_back_standup_starts_at_once_while_the_robot_still_rolls():
    behavior, world = _behavior(roll=True), _world()
    _set(world, SIDE, feet={}, up_z=0.1)
    _cycle(behavior, world, CONFIRM_CYCLES + QUIET_CYCLES)
    _set(world, (0.3 * G, 0.3 * G, 0.1 * G), gyro=(90.0, 30.0, 0.0), feet={}, up_z=0.3)  # rolling: not at rest
    _play_to_end(behavior, world, SIDE_ROLL_MOTION)
    _cycle(behavior, world, 2)  # the skill sees the roll's end, then starts the stand-up
    assert behavior.standup.sides == ["back"] and behavior.motion.motion_name == "standup_back"


def test_after_a_roll_that_left_it_on_its_side_or_front_the_robot_rests_and_reads_the_side_first():
    for acc, side in (((0.72 * G, 0.23 * G, 0.1 * G), "back"), ((0.3 * G, -0.5 * G, 0.1 * G), "front")):
        behavior, world = _behavior(roll=True), _world()
        _set(world, SIDE, feet={}, up_z=0.1)
        _cycle(behavior, world, CONFIRM_CYCLES + QUIET_CYCLES)
        _set(world, acc, gyro=(90.0, 30.0, 0.0), feet={}, up_z=0.3)
        _play_to_end(behavior, world, SIDE_ROLL_MOTION)
        _cycle(behavior, world, 3)
        assert behavior.standup.attempts == 0  # still tumbling: it waits
        _set(world, SIDE if side == "back" else FRONT, feet={}, up_z=0.1)
        _cycle(behavior, world, QUIET_CYCLES + 1)
        assert behavior.standup.sides == [side]


def test_a_robot_on_its_side_turned_to_its_front_plays_the_front_standup_without_a_roll():
    behavior, world = _behavior(roll=True), _world()
    _set(world, (0.9 * G, -0.4 * G, 0.5), feet={}, up_z=0.1)  # about 66 deg from its front
    _cycle(behavior, world, CONFIRM_CYCLES + QUIET_CYCLES)
    assert behavior.standup.sides == ["front"]
    assert behavior.motion.completed[SIDE_ROLL_MOTION] == 0
