"""Sense messages read by their learned shape (agent.protocol.sense_shape) give exactly what the predicate-by-
predicate fast path and the general path give, and bad messages of a known shape still fail where they did."""

from __future__ import annotations

import pytest

from agent.protocol.errors import ProtocolError
from agent.protocol.sense import _fast_see, _parse_fast, parse_sense
from agent.protocol.sense_shape import ShapeCache
from tests.agent.protocol_samples import received, vision_message


def _same(a: object, b: object) -> bool:
    # == ignores Sense.order and See.order; the byte round trip needs them too.
    return (a == b and a.order == b.order  # type: ignore[attr-defined]
            and (a.see and a.see.order) == (b.see and b.see.order))  # type: ignore[attr-defined]


def test_every_real_message_reads_the_same_by_its_shape() -> None:
    shapes = ShapeCache(_fast_see)
    by_shape = 0
    for message in received() * 2:             # the second round finds every shape learned
        text = message.decode("latin-1")
        fast = _parse_fast(text, message)
        assert fast is not None
        sense = shapes.parse(text, message)
        if sense is None:
            shapes.learn(fast)
            sense = shapes.parse(text, message)
        else:
            by_shape += 1
        assert sense is not None and _same(sense, fast)
        assert _same(sense, parse_sense(message, fast_path=False))
    assert by_shape > len(received())   # hears, vision with and without players, feet in the air: all shapes


def test_our_servers_messages_read_the_same_by_their_shape() -> None:
    from sim.engine import SimEngine
    from sim.inprocess import InProcessHost
    from tests.sim.scripted import Scripted

    host = InProcessHost(SimEngine(seed=2), record=True)
    for team in (b"A", b"B"):
        host.add(Scripted({0: b"(init (unum 0)(teamname %s))(syn)" % team, 2: b"(beam -3 1 0)(syn)",
                           **{i: b"(he1 1.0)(say m%d)(syn)" % i for i in range(5, 40, 7)}}))
    host.run(60)
    shapes = ShapeCache(_fast_see)
    hits = hears = 0
    for _, _, message in host.stats.transcript * 2:
        text = message.decode("latin-1")
        fast = _parse_fast(text, message)
        assert fast is not None
        sense = shapes.parse(text, message)
        if sense is None:
            shapes.learn(fast)
        else:
            assert _same(sense, fast)
            hits += 1
            hears += bool(sense.hears)
    assert hits >= len(host.stats.transcript) and hears > 0


def test_a_bad_number_in_a_known_shape_still_fails_where_it_is() -> None:
    message = vision_message()
    assert parse_sense(message) is not None and parse_sense(message) is not None   # its shape is known now
    for token in (b"(L (pol ", b"(ax ", b"(rt "):
        offset = message.index(token) + len(token)
        end = min(message.index(b" ", offset), message.index(b")", offset))
        broken = message[:offset] + b"1.x" + message[end:]
        with pytest.raises(ProtocolError) as error:
            parse_sense(broken)
        assert error.value.offset == offset


def test_a_message_that_differs_from_its_shape_goes_the_usual_way() -> None:
    message = vision_message()
    parse_sense(message)
    # A joint given twice, a renamed joint, and extra spacing: same number of foot predicates, other shape.
    start = message.index(b"(HJ")
    joint = message[start:message.index(b")", message.index(b"(ax", start)) + 2]
    with pytest.raises(ProtocolError):
        parse_sense(message + joint)
    renamed = message.replace(b"(n hj1)", b"(n hj9)")
    assert set(parse_sense(renamed).joints) == set(parse_sense(message).joints) - {"hj1"} | {"hj9"}
    assert parse_sense(message.replace(b"(See ", b"(See  ")) == parse_sense(message)
