"""Monitor messages (server -> monitor, port 3200, and log lines): game state, kind, scene graph.

A message is three S-expressions (REFERENCE §5.1): the game-state list ``((FieldLength 30)...(play_mode 0))``,
the kind ``(RSG 0 1)`` (full scene) or ``(RDS 0 1)`` (diff), and the scene graph. The game state is kept as
(key, value tokens) pairs in wire order, since ``foul`` may repeat; numbers stay the server's strings so a
message can be written back byte for byte. The scene graph is kept as its exact text (its spacing is ad hoc:
``(nd TRF (SLT ...)(nd Light (setDiffuse 1 1 1 1) (setAmbient ...)))``, so no writer reproduces it) and,
unless asked not to, also parsed into nested lists.

Numbers in monitor messages use C++ default formatting (:func:`~agent.protocol.numbers.format_g6`), and the
game-state list has no separator between its items.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from agent.protocol.errors import ProtocolError
from agent.protocol.numbers import format_g6
from agent.protocol.sexpr import Atom, Node, SExpr, ascii_text, parse_sexpr, read_located

#: Kinds of the second expression: full scene, scene diff.
FULL_SCENE, SCENE_DIFF = "RSG", "RDS"

GameStateEntry = tuple[str, tuple[str, ...]]


@dataclass(frozen=True, slots=True)
class MonitorMessage:
    """One monitor message."""

    entries: tuple[GameStateEntry, ...]
    """Game-state items in wire order: key -> value tokens, e.g. ``("GoalWidth", ("2.1",))``."""
    kind: str
    """``RSG`` (full scene) or ``RDS`` (diff)."""
    kind_arguments: tuple[str, ...]
    """The atoms after the kind (``("0", "1")``: the scene-graph format version)."""
    scene_text: str
    """The scene-graph expression exactly as received."""
    scene: SExpr | None = None
    """The scene graph as nested lists; None when parsed with ``parse_scene=False``."""

    @property
    def is_full(self) -> bool:
        """True for a full scene (sent on connect and on every scene change)."""
        return self.kind == FULL_SCENE

    @property
    def game_state(self) -> dict[str, tuple[str, ...]]:
        """Game-state items by key (for a repeated key, the last one; ``foul`` items are in :attr:`fouls`)."""
        return {key: values for key, values in self.entries if key != "foul"}

    @property
    def fouls(self) -> list[tuple[str, ...]]:
        """The value tokens of every ``(foul ...)`` item, in order."""
        return [values for key, values in self.entries if key == "foul"]


def parse_monitor(data: bytes | str, *, parse_scene: bool = True) -> MonitorMessage:
    """One monitor message (frame payload or log line without its newline) -> :class:`MonitorMessage`.

    Args:
        data: the message.
        parse_scene: also parse the scene graph into :attr:`MonitorMessage.scene` (the bulk of the work
            for a full scene); False keeps only its text, unchecked.

    Raises:
        ProtocolError: not three S-expressions, a game-state item that is not ``(key atom...)``, or a kind
            that is not a list of atoms; with the byte offset.
    """
    text = ascii_text(data).rstrip("\r\n")
    state_nodes, state_end = read_located(text, 0, limit=1)
    kind_nodes, kind_end = read_located(text, state_end, limit=1)
    if not state_nodes or not kind_nodes:
        raise ProtocolError.at("a monitor message needs game state, kind and scene graph", text, len(text))
    scene_text = text[kind_end:].lstrip(" \t\r\n")
    scene_offset = len(text) - len(scene_text)
    scene = None
    if parse_scene:
        expressions = parse_sexpr(text, scene_offset)
        if len(expressions) != 1:
            raise ProtocolError.at(f"expected one scene-graph expression, got {len(expressions)}", text,
                                   scene_offset)
        scene = expressions[0]
    kind_node = kind_nodes[0]
    if not kind_node or not all(isinstance(item, Atom) for item in kind_node):
        raise ProtocolError.at("the kind must be a list of atoms like (RSG 0 1)", text, kind_node.offset)
    return MonitorMessage(
        _entries(state_nodes[0], text),
        str(kind_node[0]),
        tuple(str(item) for item in kind_node[1:]),
        scene_text,
        scene,
    )


def _entries(node: Node, text: str) -> tuple[GameStateEntry, ...]:
    entries = []
    for item in node:
        if not isinstance(item, Node) or not item or not all(isinstance(value, Atom) for value in item):
            raise ProtocolError.at("a game-state item must be (key atom...)", text, item.offset)
        entries.append((str(item[0]), tuple(str(value) for value in item[1:])))
    return tuple(entries)


def format_game_state(entries: Sequence[tuple[str, Sequence[str | int | float]]]) -> bytes:
    """The game-state expression as the server writes it: ``((FieldLength 30)(GoalWidth 2.1)...)``.

    Args:
        entries: (key, values) pairs in order; a value is written as given (``str``), as an integer
            (``int``) or like C++ ``ostream`` (``float``: ``2.1``, ``0.042``, ``-8.74228e-08``).
    """
    items = []
    for key, values in entries:
        spelled = [value if isinstance(value, str) else format_g6(value) for value in values]
        items.append(f"({' '.join([key, *spelled])})")
    return f"({''.join(items)})".encode("ascii")


def format_monitor(message: MonitorMessage) -> bytes:
    """The wire bytes of ``message``: game state, kind, then the scene graph text as received."""
    kind = " ".join([message.kind, *message.kind_arguments])
    return format_game_state(message.entries) + f"({kind})".encode("ascii") + message.scene_text.encode("ascii")
