"""The server's template writer (agent.protocol.sense_template) writes format_sense's bytes for every shape."""

from __future__ import annotations

import itertools
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from agent.protocol.errors import ProtocolError
from agent.protocol.perceptors import (Accelerometer, ForceResistance, GameState, Gyro, Hear, Polar, See, Sense,
                                       TimePerceptor, VisibleLine, VisibleObject, VisiblePlayer)
from agent.protocol.sense import format_sense, parse_sense
from agent.protocol.sense_template import (LINE_TEMPLATE, PLAYER_CLOSE_BYTES, SEE_CLOSE_BYTES, SEE_OPEN_BYTES,
                                           SEE_SEPARATOR_BYTES, SPELLED_NUMBER, SenseTemplate, game_state_bytes,
                                           hear_bytes, line_template, object_template, part_template,
                                           player_template, time_bytes)

JOINTS = ("hj1 hj2 raj1 raj2 raj3 raj4 laj1 laj2 laj3 laj4 rlj1 rlj2 rlj3 rlj4 rlj5 rlj6 "
          "llj1 llj2 llj3 llj4 llj5 llj6").split()
# Robot type 4: a toe joint after each ankle roll, toe sensors rf1 / lf1 (REFERENCE §2.5).
JOINTS_TOE = JOINTS[:16] + ["rlj7"] + JOINTS[16:] + ["llj7"]
# Values that exercise the spelling: signs, -0.00, rounding at half a cent, big and tiny numbers.
SPECIAL = [0.0, -0.0, -0.001, 0.125, 0.135, -61.93, 1e6, 2.675, -1e-9, 104.36, math.nan, math.inf]


def _sense(template: SenseTemplate, values: list[float], mask: int, see: See | None,
           hears: tuple[Hear, ...], game_state: GameState, now: float) -> Sense:
    joints = template.joints
    frp = {}
    for i, name in enumerate(template.foot_sensors):
        if mask >> i & 1:
            start = 6 + len(joints) + 6 * i
            frp[name] = ForceResistance(name, tuple(values[start:start + 3]), tuple(values[start + 3:start + 6]))
    return Sense(TimePerceptor(now), game_state, Gyro("torso", tuple(values[:3])),
                 Accelerometer("torso", tuple(values[3:6])), dict(zip(joints, values[6:6 + len(joints)])), frp,
                 hears, see)


def _see_bytes(see: See) -> bytes:
    """The See predicate as the vision writer builds it from the item templates."""
    items = [object_template(o.name) % tuple(o[1:]) for o in see.objects]
    for player in see.players:
        parts = b"".join(part_template(name) % tuple(polar) for name, polar in player.parts.items())
        items.append(player_template(player.team, player.unum) % () + parts + PLAYER_CLOSE_BYTES)
    items += [LINE_TEMPLATE % (*line.begin, *line.end) for line in see.lines]
    return SEE_OPEN_BYTES + SEE_SEPARATOR_BYTES.join(items) + SEE_CLOSE_BYTES


SEES = [
    None,
    See((), (), ()),
    See((VisibleObject("G1R", 9.12, 12.4, 4.71), VisibleObject("B", 2.31, -8.52, -12.66)),
        (VisiblePlayer("Rivals", 4, {"head": Polar(5.02, 20.11, 0.93), "lfoot": Polar(5.1, 21.37, -5.6)}),
         VisiblePlayer("Mine", 2, {"rlowerarm": Polar(0.19, -35.4, -23.9)})),
        (VisibleLine(Polar(8.44, -33.05, -3.51), Polar(10.86, 52.2, -2.93)),)),
]


@pytest.mark.parametrize("joints, feet", [(JOINTS, ("rf", "lf")), (JOINTS_TOE, ("rf", "lf", "rf1", "lf1"))],
                         ids=["types 0-3", "type 4"])
def test_every_shape_matches_format_sense(joints: list[str], feet: tuple[str, ...]) -> None:
    template = SenseTemplate(joints, feet)
    values = [SPECIAL[i % len(SPECIAL)] * (1 + i / 7) for i in range(template.value_count)] + [99.0, 98.0]
    hears = (Hear("Mine", 41.26, None, "c,4,-3"), Hear("Rivals", 41.28, -47.5, "xk29"), Hear(None, 1.0, 3.0, "x"))
    for mask, see, count, identity in itertools.product(range(1 << len(feet)), SEES, range(4), (False, True)):
        state = GameState(3 if identity else None, "right" if identity else None, 0, 1, 41.22, "PlayOn")
        expected = format_sense(_sense(template, values, mask, see, hears[:count], state, 104.36))
        written = template.format(values, time_bytes(104.36), game_state_bytes(state), mask,
                                  None if see is None else _see_bytes(see), [hear_bytes(h) for h in hears[:count]])
        assert written == expected, (mask, see, count)


def test_real_sample_messages_are_written_back() -> None:
    """Every real 0.7.3 message our template can express (no unknowns, its own order) comes out the same."""
    from tests.agent.protocol_samples import received
    template = SenseTemplate(JOINTS, ("rf", "lf"))
    checked = 0
    for message in received():
        sense = parse_sense(message)
        if list(sense.joints) != JOINTS or sense.agent_state is not None or (sense.see and sense.see.my_pos_m):
            continue
        if format_sense(Sense(*[getattr(sense, f) for f in ("time", "game_state", "gyro", "acc", "joints", "frp",
                                                              "hears", "see")])) != message:
            continue  # not in the server's own order (only such messages can come from a template)
        feet = [sense.frp.get(name) for name in template.foot_sensors]
        values = [*sense.gyro.rate_deg_s, *sense.acc.acc_m_s2, *sense.joints.values()]
        for foot in feet:
            values += [*foot.contact_m, *foot.force_n] if foot else [0.0] * 6
        mask = sum(1 << i for i, foot in enumerate(feet) if foot)
        written = template.format(values, time_bytes(sense.time.now_s), game_state_bytes(sense.game_state), mask,
                                  None if sense.see is None else _see_bytes(sense.see),
                                  [hear_bytes(h) for h in sense.hears])
        assert written == message
        checked += 1
    assert checked > 100


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(allow_nan=False, width=64, min_value=-1e4, max_value=1e4), min_size=40, max_size=40),
       st.integers(0, 3), st.booleans())
def test_random_values_match_format_sense(values: list[float], mask: int, with_see: bool) -> None:
    template = SenseTemplate(JOINTS, ("rf", "lf"))
    state = GameState(None, None, 2, 0, 300.0, "KickIn_Left")
    see = SEES[2] if with_see else None
    expected = format_sense(_sense(template, values, mask, see, (), state, 7.5))
    assert template.format(values, time_bytes(7.5), game_state_bytes(state), mask,
                           None if see is None else _see_bytes(see)) == expected


def test_spelled_numbers_give_the_same_bytes() -> None:
    """Writers that spell many numbers at once pass bytes (numbers.fixed2_table) into "%s" templates."""
    printf, spelled = SenseTemplate(JOINTS_TOE, ("rf", "lf", "rf1", "lf1")), SenseTemplate(
        JOINTS_TOE, ("rf", "lf", "rf1", "lf1"), number=SPELLED_NUMBER)
    values = [SPECIAL[i % len(SPECIAL)] * (1 + i / 5) for i in range(printf.value_count)]
    spellings = [b"%.2f" % v for v in values]
    state = game_state_bytes(GameState(None, None, 0, 0, 1.0, "PlayOn"))
    for mask in range(16):
        assert spelled.format(spellings, time_bytes(1.0), state, mask, b"(See )") == \
            printf.format(values, time_bytes(1.0), state, mask, b"(See )")
    assert object_template("F%1", SPELLED_NUMBER) % (b"1.00", b"-2.50", b"3.00") == b"(F%1 (pol 1.00 -2.50 3.00))"
    assert part_template("head", SPELLED_NUMBER) % (b"1.00", b"2.00", b"3.00") == b" (head (pol 1.00 2.00 3.00))"
    assert line_template(SPELLED_NUMBER) % tuple(b"%d.00" % i for i in range(6)) == LINE_TEMPLATE % tuple(range(6))


def test_names_that_are_not_atoms_are_refused() -> None:
    with pytest.raises(ProtocolError):
        SenseTemplate(["hj1", "bad name"], ("rf",))
    with pytest.raises(ProtocolError):
        game_state_bytes(GameState(1, "le(ft", 0, 0, 0.0, "PlayOn"))
    with pytest.raises(ProtocolError):
        hear_bytes(Hear("Mine", 1.0, None, "two words"))
    with pytest.raises(ProtocolError):
        player_template("a b", 3)


def test_a_percent_sign_in_a_name_is_written_as_itself() -> None:
    template = SenseTemplate(["a%d", "hj2"], ())
    written = template.format([0.0] * 8, time_bytes(0.0), game_state_bytes(GameState(None, None, 0, 0, 0.0, "x%s")))
    assert b"(HJ (n a%d) (ax 0.00))" in written and b"(pm x%s)" in written
    assert object_template("F%1") % (1.0, 2.0, 3.0) == b"(F%1 (pol 1.00 2.00 3.00))"
    assert SenseTemplate(["x%.2f", "hj2"], (), number=SPELLED_NUMBER).format(
        [b"1.00"] * 8, b"", b"") == b"(GYR (n torso) (rt 1.00 1.00 1.00))(ACC (n torso) (a 1.00 1.00 1.00))" \
        b"(HJ (n x%.2f) (ax 1.00))(HJ (n hj2) (ax 1.00))"
    assert (player_template("T%s", 2) + PLAYER_CLOSE_BYTES) % () == b"(P (team T%s) (id 2))"
