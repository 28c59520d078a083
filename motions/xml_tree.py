"""A small XML element tree that remembers the line of every element, built with expat.

ElementTree forgets where elements were, and error messages must name the line (DESIGN.md: errors name the
file, the line and the field). Attribute order is kept (``ordered_attributes``) so writers can repeat it.
Document type declarations and entity definitions are refused: motion files need neither, and refusing them
closes the entity-expansion attacks a hostile file could attempt.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from xml.parsers import expat

from motions.errors import MotionFormatError


@dataclass
class XmlNode:
    """One element: tag, attributes in file order, 1-based line of its start tag, children, direct text."""

    tag: str
    attributes: list[tuple[str, str]]
    line: int
    children: list[XmlNode] = field(default_factory=list)
    text: str = ""

    def attribute(self, name: str) -> str | None:
        """Value of attribute ``name``, None if absent."""
        for key, value in self.attributes:
            if key == name:
                return value
        return None


@dataclass
class XmlDocument:
    """The root element plus what stands before it: the XML declaration text and prolog comments."""

    root: XmlNode
    declaration: str | None
    prolog_comments: list[str]


class _Builder:
    """Expat handlers that assemble ``XmlNode`` objects; lines come from the parser's current position."""

    def __init__(self, parser: expat.XMLParserType, path: str) -> None:
        self.parser = parser
        self.path = path
        self.stack: list[XmlNode] = []
        self.root: XmlNode | None = None
        self.prolog_comments: list[str] = []

    def start(self, tag: str, flat_attributes: list[str]) -> None:
        pairs = list(zip(flat_attributes[0::2], flat_attributes[1::2]))
        node = XmlNode(tag, pairs, self.parser.CurrentLineNumber)
        if self.stack:
            self.stack[-1].children.append(node)
        else:
            self.root = node
        self.stack.append(node)

    def end(self, tag: str) -> None:
        self.stack.pop()

    def characters(self, data: str) -> None:
        if self.stack:
            self.stack[-1].text += data

    def comment(self, data: str) -> None:
        # Only comments before the root are kept: they hold how the file was made (DESIGN.md).
        if self.root is None:
            self.prolog_comments.append(data)

    def refuse(self, *args: object) -> None:
        raise MotionFormatError("document type declarations and entity definitions are not allowed in motion "
                                "files", path=self.path, line=self.parser.CurrentLineNumber, field="DOCTYPE")


def _declaration(text: str) -> str | None:
    """The ``<?xml ...?>`` declaration as written at the very start of the text, None if absent."""
    if text.startswith("<?xml"):
        end = text.find("?>")
        if end != -1:
            return text[: end + 2]
    return None


def parse_xml(text: str, path: str) -> XmlDocument:
    """Parse ``text`` into an element tree with line numbers.

    Args:
        text: the whole file as text.
        path: file name for error messages.

    Raises:
        MotionFormatError: not well-formed XML (line and column from expat), or a DOCTYPE/entity declaration.
    """
    parser = expat.ParserCreate()
    parser.ordered_attributes = True
    parser.buffer_text = True
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    builder = _Builder(parser, path)
    parser.StartElementHandler = builder.start
    parser.EndElementHandler = builder.end
    parser.CharacterDataHandler = builder.characters
    parser.CommentHandler = builder.comment
    parser.StartDoctypeDeclHandler = builder.refuse
    parser.EntityDeclHandler = builder.refuse
    try:
        parser.Parse(text, True)
    except expat.ExpatError as error:
        message = expat.errors.messages[error.code]
        raise MotionFormatError(f"not well-formed XML: {message} (column {error.offset + 1})",
                                path=path, line=error.lineno) from None
    if builder.root is None:  # expat reports an empty document itself; kept for safety
        raise MotionFormatError("no root element", path=path, line=1)
    return XmlDocument(builder.root, _declaration(text), builder.prolog_comments)
