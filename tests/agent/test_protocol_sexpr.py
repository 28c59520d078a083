"""S-expression reader and writer: examples, located errors, and round-trip properties."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from agent.protocol.errors import ProtocolError
from agent.protocol.sexpr import Atom, Node, ascii_text, format_sexpr, parse_sexpr, read_located
from tests.agent.protocol_samples import monitor_lines, received, sent


def test_reads_concatenated_expressions_into_nested_lists() -> None:
    assert parse_sexpr(b"(time (now 77.68))(GS (sl 0) (t 0.00))") == [
        ["time", ["now", "77.68"]],
        ["GS", ["sl", "0"], ["t", "0.00"]],
    ]
    assert parse_sexpr("(init (unum 1)(teamname CapL))") == [["init", ["unum", "1"], ["teamname", "CapL"]]]
    assert parse_sexpr(b"") == []
    assert parse_sexpr(b"(nd(nd))()") == [["nd", ["nd"]], []]


def test_any_separator_run_splits_items() -> None:
    assert parse_sexpr(b" (a\tb\r\n(c  d) ) \n(e)") == [["a", "b", ["c", "d"]], ["e"]]


def test_atoms_keep_every_printable_character_but_parentheses() -> None:
    assert parse_sexpr(b"(say c,4,-3;'\"\\|~)") == [["say", "c,4,-3;'\"\\|~"]]


@pytest.mark.parametrize(
    ("data", "offset", "words"),
    [
        (b"(a (b)", 6, "not closed"),  # truncated: end of input
        (b"(a)(b", 5, "not closed"),
        (b"(a))", 3, "without a matching"),  # stray ')'
        (b")(a)", 0, "without a matching"),
        (b"abc(a)", 0, "outside any list"),  # atom at top level
        (b"(a) b", 4, "outside any list"),
        (b"(a \x00)", 3, "0x00"),  # control byte
        (b"(say caf\xc3\xa9)", 8, "0xc3"),  # non-ASCII
        (b"(a\x7f)", 2, "0x7f"),
    ],
)
def test_malformed_input_names_the_byte_offset(data: bytes, offset: int, words: str) -> None:
    with pytest.raises(ProtocolError) as error:
        parse_sexpr(data)
    assert error.value.offset == offset
    assert words in str(error.value)
    assert f"byte {offset}" in str(error.value)
    assert error.value.snippet == data[max(0, offset - 24) : offset + 24]


def test_text_input_must_be_ascii_too() -> None:
    with pytest.raises(ProtocolError) as error:
        parse_sexpr("(say \u65e5\u672c)")  # not Latin-1 either: must not turn into "?"
    assert error.value.offset == 5
    with pytest.raises(ProtocolError) as error:
        parse_sexpr("(a \t\x01)")
    assert error.value.offset == 4


def test_unclosed_list_error_names_where_it_opened() -> None:
    with pytest.raises(ProtocolError) as error:
        parse_sexpr(b"(time (now 1.00))(HJ (n hj1) (ax 1.00)")
    assert error.value.offset == 38
    assert "opened at byte 17" in str(error.value)


def test_located_reader_records_offsets_and_stops_at_a_limit() -> None:
    text = "(time (now 1.00)) (HJ (n hj1) (ax 2.00))"
    nodes, end = read_located(text, 0, limit=1)
    assert nodes == [["time", ["now", "1.00"]]] and end == 17
    assert isinstance(nodes[0], Node) and nodes[0].offset == 0 and nodes[0][1].offset == 6
    now = nodes[0][1][1]
    assert isinstance(now, Atom) and now.offset == 11
    rest, end = read_located(text, end)
    assert rest[0].offset == 18 and end == len(text)


@pytest.mark.parametrize("message", received()[:40] + sent() + monitor_lines())
def test_located_and_fast_readers_agree_on_real_messages(message: bytes) -> None:
    text = ascii_text(message)
    nodes, _ = read_located(text)
    assert nodes == parse_sexpr(message)

    def check(node: Node) -> None:
        assert text[node.offset] == "("
        for item in node:
            if isinstance(item, Node):
                check(item)
            else:
                assert text.startswith(item, item.offset)

    for node in nodes:
        check(node)


def test_writer_uses_the_server_spacing() -> None:
    assert format_sexpr([["beam", "-2.5", "0", "0"], ["syn"]]) == b"(beam -2.5 0 0)(syn)"
    assert format_sexpr([["GS", ["sl", "0"], ["t", "0.00"]], []]) == b"(GS (sl 0) (t 0.00))()"


@pytest.mark.parametrize("bad", ["", "a b", "a(b", "x)", "caf\u00e9", "tab\there"])
def test_writer_rejects_atoms_that_would_change_the_structure(bad: str) -> None:
    with pytest.raises(ProtocolError) as error:
        format_sexpr([["say", bad]])
    assert error.value.offset == 5  # "(say " was written before it


def test_writer_rejects_non_list_items() -> None:
    with pytest.raises(ProtocolError):
        format_sexpr(["syn"])  # type: ignore[list-item]
    with pytest.raises(ProtocolError):
        format_sexpr([["he1", 0.5]])


def test_sample_messages_in_server_spacing_survive_read_then_write() -> None:
    for message in received():
        assert format_sexpr(parse_sexpr(message)) == message


_ATOM = st.text(alphabet=st.characters(min_codepoint=0x21, max_codepoint=0x7E, exclude_characters="()"),
                min_size=1, max_size=8)
_TREE = st.recursive(_ATOM, lambda children: st.lists(children, max_size=5), max_leaves=40)
_EXPRESSIONS = st.lists(st.lists(_TREE, max_size=5), max_size=5)


@given(_EXPRESSIONS)
def test_write_then_read_gives_the_tree_back(expressions: list[list[object]]) -> None:
    assert parse_sexpr(format_sexpr(expressions)) == expressions


@given(_EXPRESSIONS, st.data())
def test_extra_separators_do_not_change_the_tree(expressions: list[list[object]], data: st.DataObject) -> None:
    text = format_sexpr(expressions).decode()
    padded = "".join(
        char + (data.draw(st.sampled_from(["", " ", "\n", "\t ", "\r\n"])) if char in "() " else "")
        for char in text
    )
    assert parse_sexpr(padded) == expressions
