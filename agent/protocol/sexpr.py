"""S-expression reader and writer for the wire: bytes <-> nested lists of ``str`` atoms.

The grammar is the one rcssserver3d speaks: a message is one or more lists, ``(`` and ``)`` delimit lists,
atoms are runs of printable ASCII without parentheses, and space/tab/CR/LF separate items. The reader is a
compiled-regex tokenizer feeding an explicit stack (no recursion, no per-character Python work): the fast
:func:`parse_sexpr` gives plain ``str`` atoms; :func:`read_located` also records each atom's and list's byte
offset (for error messages further up). Any byte outside printable ASCII and those four separators is an
error, as is an atom outside a list or an unbalanced parenthesis; the error names the byte offset.

The writer puts one space between the items of a list and nothing between top-level lists, which is how
the server prints sense messages (REFERENCE §3.1).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import Union

from agent.protocol.errors import ProtocolError

#: Bytes allowed anywhere in a message: the four separators and printable ASCII.
_BAD_BYTE = re.compile(rb"[^ \t\n\r!-~]")
_ALLOWED_BYTES = b" \t\n\r" + bytes(range(0x21, 0x7F))
_TOKEN = re.compile(r"[()]|[^ \t\n\r()]+")
_ATOM = re.compile(r"[!-'*-~]+\Z")

#: A parsed expression: a list whose items are atoms or further expressions.
SExpr = list[Union[str, "SExpr"]]


class Atom(str):
    """An atom that remembers its byte offset in the message (made by :func:`read_located`)."""

    offset: int


class Node(list):  # type: ignore[type-arg]
    """A list that remembers the byte offset of its ``(`` (made by :func:`read_located`)."""

    __slots__ = ("offset",)
    offset: int


def ascii_text(data: bytes | str) -> str:
    """``data`` as a ``str`` after checking every byte is a separator or printable ASCII.

    Offsets into the result are byte offsets into ``data``, since every character is one byte.

    Raises:
        ProtocolError: at the first byte outside ``[ \\t\\n\\r!-~]``.
    """
    if isinstance(data, str):
        if not data.isascii():  # all earlier characters are ASCII, so the index is a byte offset too
            offset = next(index for index, char in enumerate(data) if not char.isascii())
            raise ProtocolError.at(f"character {data[offset]!r} is not ASCII", data, offset)
        raw = data.encode("ascii")
    else:
        raw = data
    if raw.translate(None, _ALLOWED_BYTES):  # bytes are left over: find the first (rare, slower)
        bad = _BAD_BYTE.search(raw)
        offset = bad.start() if bad is not None else 0
        raise ProtocolError.at(f"byte {raw[offset]:#04x} is not allowed on the wire", raw, offset)
    return data if isinstance(data, str) else data.decode("ascii")


def parse_sexpr(data: bytes | str, start: int = 0) -> list[SExpr]:
    """All top-level expressions of ``data[start:]``, as nested lists of ``str`` atoms.

    Example: ``b"(time (now 1.00))(syn)"`` -> ``[["time", ["now", "1.00"]], ["syn"]]``. Error offsets are
    offsets into the whole ``data``.

    Raises:
        ProtocolError: a byte outside printable ASCII and separators, an atom outside a list, a ``)``
            without its ``(`` (offset of that byte), or a list left open (offset ``len(data)``).
    """
    text = ascii_text(data)
    root: list[SExpr] = []
    stack: list[SExpr] = []
    current: SExpr = root  # type: ignore[assignment]
    for token in _TOKEN.findall(text, start):
        if token == "(":
            child: SExpr = []
            current.append(child)
            stack.append(current)
            current = child
        elif token == ")":
            if not stack:
                raise _locate_error(text, start)
            current = stack.pop()
        elif current is root:
            raise _locate_error(text, start)
        else:
            current.append(token)
    if stack:
        raise _locate_error(text, start)
    return root


def read_located(text: str, start: int = 0, limit: int | None = None) -> tuple[list[Node], int]:
    """Top-level expressions from ``text[start:]`` as :class:`Node`/:class:`Atom` trees with byte offsets.

    Args:
        text: output of :func:`ascii_text` (already checked).
        start: offset to begin at (leading separators are skipped).
        limit: stop after this many top-level expressions (None: read to the end).

    Returns:
        (expressions, offset just past the last one read).

    Raises:
        ProtocolError: as :func:`parse_sexpr`.
    """
    root: list[Node] = []
    stack: list[Node] = []
    current: Node | None = None
    end = start
    for match in _TOKEN.finditer(text, start):
        token = match.group()
        if token == "(":
            node = Node()
            node.offset = match.start()
            if current is None:
                root.append(node)
            else:
                current.append(node)
                stack.append(current)
            current = node
        elif token == ")":
            if current is None:
                raise ProtocolError.at("')' without a matching '('", text, match.start())
            current = stack.pop() if stack else None
            if current is None:
                end = match.end()
                if limit is not None and len(root) >= limit:
                    return root, end
        elif current is None:
            raise ProtocolError.at(f"atom {token!r} outside any list", text, match.start())
        else:
            atom = Atom(token)
            atom.offset = match.start()
            current.append(atom)
    if current is not None:
        innermost = current.offset
        raise ProtocolError.at(
            f"unexpected end of message: list opened at byte {innermost} is not closed", text, len(text)
        )
    return root, end


def _locate_error(text: str, start: int) -> ProtocolError:
    """The located error for ``text[start:]``, which the fast reader found malformed (re-read for offsets)."""
    try:
        read_located(text, start)
    except ProtocolError as error:
        return error
    raise AssertionError("fast and located readers disagree")  # pragma: no cover


def format_sexpr(expressions: Iterable[Sequence[object]]) -> bytes:
    """Top-level lists as wire bytes: items of a list separated by one space, lists concatenated.

    Example: ``[["beam", "-2.5", "0", "0"], ["syn"]]`` -> ``b"(beam -2.5 0 0)(syn)"``. Numbers must already
    be spelled as strings (see :mod:`agent.protocol.numbers`), so the format of every value is explicit.

    Raises:
        ProtocolError: an atom that is empty, not a ``str``, or contains a separator, a parenthesis or a
            non-printable byte (offset = where it would have been written).
    """
    out: list[str] = []
    for expression in expressions:
        _write(expression, out)
    return "".join(out).encode("ascii")


def _write(expression: Sequence[object], out: list[str]) -> None:
    if isinstance(expression, str):
        raise ProtocolError(f"top-level item {expression!r} must be a list", _written(out), expression[:16].encode())
    out.append("(")
    separator = ""
    for item in expression:
        out.append(separator)
        separator = " "
        if isinstance(item, str):
            if _ATOM.match(item) is None:
                raise ProtocolError(
                    f"atom {item!r} is empty or holds a separator, parenthesis or non-printable byte",
                    _written(out),
                    item[:16].encode("latin-1", "replace"),
                )
            out.append(item)
        elif isinstance(item, Sequence):
            _write(item, out)
        else:
            raise ProtocolError(
                f"item {item!r} is neither a str atom nor a list", _written(out), repr(item)[:16].encode()
            )
    out.append(")")


def _written(out: list[str]) -> int:
    return sum(len(part) for part in out)
