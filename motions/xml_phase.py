"""Reader and writer of the XML phase format (FIIT / Kouretes3D motions, REFERENCE §6a).

Degrees in the file, SimSpark-signed radians inside; effector names (``lle3``) in the file, wire names
(``llj3``) inside. Reading then writing a file in the canonical layout gives back the same bytes, and a file
laid out elsewhere keeps its phase order, effector order, phase attribute order, number texts (``46`` stays
``46``, ``-7.50`` stays ``-7.50`` while unchanged), XML declaration, ``<robot>`` attributes, line endings and
comments before ``<robot>``.

Canonical layout (the FIIT files' own style): the declaration ``<?xml version="1.0" encoding="UTF-8"?>``,
header comments each as ``<!--text-->`` on their own line, tab indentation, ``<constants>`` (only if there
are constants) and ``<low_skills>`` each followed by one empty line, self-closing elements written
``<lle3 end="46" />`` (``<effectors />`` when empty), attributes in the order of REFERENCE §6a
(``name next isFinal skipIfFlag setFlagTrue setFlagFalse``; ``end computed``), ``<effectors>``,
``<duration>``, ``<finalize>`` in that order, LF line endings and a final newline.

Not kept: comments inside ``<robot>``, blank lines and indentation other than the canonical ones, the
order of an effector's ``end``/``computed`` attributes, the spelling of ``isFinal`` values (``True`` is
written ``true``).

Decisions on points REFERENCE leaves open:
- ``next`` or ``finalize`` naming no phase is a warning (logged and kept in ``source.warnings``), not an
  error: REFERENCE says the motion then ends after that phase. A ``firstPhase`` naming no phase is an error.
- ``<duration>`` must be a whole number of milliseconds >= 0 (0: below).
- Phase names are matched exactly (the 2012 agent ignores case; two names differing only in case would
  be ambiguous there, so avoid them).

Files other tools wrote (robocup-fiit's moves, read 2026-11-28: 78 of 111 files broke the stricter reader
before) are read as FIIT's own loader reads them; where the reading makes a choice (0 ms, a repeated effector or
phase, an attribute outside the format) a warning names the line:
- ``end`` and ``<duration>`` may be arithmetic over the ``<constants>`` (``strafe_leg_crouch+30``,
  ``-2*strafe_leg_crouch``; ``motions.expressions``); the text is written back while it keeps its value;
- a phase without ``<effectors>`` holds every joint, as an empty one does;
- an effector listed twice in a phase: the later one counts (the server applies the later command);
- a phase name used twice: the later phase replaces the earlier (FIIT keeps phases in a map by name);
- an attribute outside §6a on ``<phase>`` (FIIT's ``opposite``) is ignored by playback and written back;
- ``<type>``, ``<author>``, ``<extendedFromMove>`` and ``<description>`` in ``<low_skills>`` (beside or inside
  ``<low_skill>``) describe the motion: not played, written back where they were;
- a ``<duration>`` of 0 ms: FIIT's loader rounds every duration up to whole 20 ms cycles, so 0 is one cycle.
A FIIT move annotation (root ``<annotation>``: a move's preconditions, no phases) is an error that says so.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping

from motions.errors import ConversionError, MotionFormatError
from motions.expressions import ExpressionError, evaluate
from motions.joints import joint_by_effector, joint_by_wire, known_effector_names
from motions.model import SERVER_CYCLE_MS, XML, JointTarget, Keyframe, KeyframeSource, Motion, MotionSource
from motions.numbers import degrees_text_for_rad, is_whole, parse_decimal, parse_integer, shortest_decimal
from motions.xml_tree import XmlNode, parse_xml

logger = logging.getLogger(__name__)

CANONICAL_DECLARATION = '<?xml version="1.0" encoding="UTF-8"?>'
#: FIIT's descriptive elements in ``<low_skills>`` (its loader reads them as notes on the move).
LOW_SKILL_NOTES = ("type", "author", "extendedFromMove", "description")
#: A phase written with a duration of 0 ms lasts one cycle [ms] (FIIT's loader rounds durations up to cycles).
ZERO_DURATION_MS = SERVER_CYCLE_MS

# XML attribute name -> Keyframe field, in the canonical (REFERENCE §6a) order.
PHASE_ATTRIBUTES: dict[str, str] = {
    "name": "name", "next": "next", "isFinal": "is_final", "skipIfFlag": "skip_if_flag",
    "setFlagTrue": "set_flag_true", "setFlagFalse": "set_flag_false",
}


# ---------------------------------------------------------------------------------------------- reading
def _number(text: str, constants: Mapping[str, float]) -> float:
    """``text`` of an ``end`` or ``<duration>``: a plain decimal, else arithmetic over ``constants``; the one
    reading of number texts that the reader and the writer (which keeps a text while it reads as the value) share.

    Raises:
        ExpressionError: neither (the caller names the line and the field).
    """
    value = parse_decimal(text)
    return value if value is not None else evaluate(text, constants)


class _Reader:
    """Turns the element tree of one file into a Motion, raising errors that name path, line and field."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.warnings: list[str] = []
        self.constant_values: dict[str, float] = {}

    def error(self, node: XmlNode, detail: str, field: str | None, element: str | None = None) -> MotionFormatError:
        return MotionFormatError(detail, path=self.path, line=node.line, field=field, element=element)

    def warn(self, node: XmlNode, message: str) -> None:
        text = f"{self.path}:{node.line}: {message}"
        self.warnings.append(text)
        logger.warning(text)

    def no_text(self, node: XmlNode) -> None:
        if node.text.strip():
            raise self.error(node, f"unexpected text {node.text.strip()!r} in <{node.tag}>", node.tag)

    def check_attributes(self, node: XmlNode, allowed: tuple[str, ...], required: tuple[str, ...],
                         element: str | None = None, lenient: bool = False) -> tuple[tuple[str, str], ...]:
        """Raise on a missing required attribute and on one not ``allowed``; with ``lenient`` the latter are
        warnings instead, and returned (attribute, value) in file order."""
        extra: list[tuple[str, str]] = []
        for key, value in node.attributes:
            if key not in allowed:
                if not lenient:
                    raise self.error(node, f"unknown attribute {key!r}; allowed: {', '.join(allowed)}", key,
                                     element or node.tag)
                self.warn(node, f"attribute {key}={value!r} of <{node.tag}> is not in the format (allowed: "
                          f"{', '.join(allowed)}): ignored by playback, written back")
                extra.append((key, value))
        for key in required:
            if node.attribute(key) is None:
                raise self.error(node, "missing required attribute", key, element or node.tag)
        return tuple(extra)

    def children(self, node: XmlNode, allowed: tuple[str, ...]) -> dict[str, list[XmlNode]]:
        """Children grouped by tag; any other tag is an error naming what is allowed."""
        self.no_text(node)
        groups: dict[str, list[XmlNode]] = {tag: [] for tag in allowed}
        for child in node.children:
            if child.tag not in groups:
                raise self.error(child, f"unexpected element <{child.tag}> in <{node.tag}>; expected "
                                 f"{', '.join('<' + t + '>' for t in allowed)}", child.tag)
            groups[child.tag].append(child)
        return groups

    def optional(self, parent: XmlNode, nodes: list[XmlNode], tag: str) -> XmlNode | None:
        """The one ``<tag>`` child, None if absent; more than one is an error."""
        if len(nodes) > 1:
            raise self.error(nodes[1], f"<{tag}> appears more than once in <{parent.tag}>", tag)
        return nodes[0] if nodes else None

    def required(self, parent: XmlNode, nodes: list[XmlNode], tag: str) -> XmlNode:
        """The one ``<tag>`` child; absent or repeated is an error."""
        node = self.optional(parent, nodes, tag)
        if node is None:
            raise self.error(parent, f"missing <{tag}> in <{parent.tag}>", tag)
        return node

    # ------------------------------------------------------------------------------------------ parts
    def constants(self, node: XmlNode | None) -> tuple[dict[str, float], dict[str, str]]:
        values: dict[str, float] = {}
        texts: dict[str, str] = {}
        if node is None:
            return values, texts
        for constant in self.children(node, ("constant",))["constant"]:
            self.no_text(constant)
            self.check_attributes(constant, ("name", "value"), ("name", "value"))
            name, text = constant.attribute("name") or "", constant.attribute("value") or ""
            value = parse_decimal(text)
            if value is None:
                raise self.error(constant, f"expected a number, got {text!r}", "value", "constant")
            if name in values:
                raise self.error(constant, f"constant {name!r} is defined twice", "name", "constant")
            values[name], texts[name] = value, text
        self.constant_values = values
        return values, texts

    def low_skill(self, node: XmlNode) -> tuple[str, str, XmlNode, tuple[tuple[str, str, bool], ...]]:
        """Name, first phase, the element, and FIIT's descriptive notes (tag, text, inside <low_skill>)."""
        groups = self.children(node, ("low_skill",) + LOW_SKILL_NOTES)
        skills = groups["low_skill"]
        if len(skills) > 1:
            raise self.error(skills[1], "only one <low_skill> per file is allowed", "low_skill")
        skill = self.required(node, skills, "low_skill")
        self.children(skill, LOW_SKILL_NOTES)  # only notes inside it
        notes = [(child.tag, self.note_text(child), True) for child in skill.children]
        notes += [(child.tag, self.note_text(child), False) for child in node.children if child.tag != "low_skill"]
        self.check_attributes(skill, ("name", "firstPhase"), ("name", "firstPhase"))
        return skill.attribute("name") or "", skill.attribute("firstPhase") or "", skill, tuple(notes)

    def note_text(self, node: XmlNode) -> str:
        self.no_text_children(node)
        self.check_attributes(node, (), ())
        return node.text

    def target(self, node: XmlNode, phase_name: str) -> tuple[str, JointTarget, str]:
        spec = joint_by_effector(node.tag)
        if spec is None:
            raise self.error(node, f"unknown effector <{node.tag}>; known: {', '.join(known_effector_names())}",
                             node.tag, f"phase {phase_name!r}")
        self.no_text(node)
        self.check_attributes(node, ("end", "computed"), ("end",))
        text = node.attribute("end") or ""
        try:
            angle_deg = _number(text, self.constant_values)
        except ExpressionError as problem:
            raise self.error(node, f"expected a number or arithmetic over the constants, got {text!r} ({problem})",
                             "end", node.tag) from None
        return spec.perceptor, JointTarget(math.radians(angle_deg), node.attribute("computed")), text

    def duration(self, node: XmlNode, phase_name: str) -> float:
        self.no_text_children(node)
        text = node.text
        element = f"phase {phase_name!r}"
        milliseconds = parse_integer(text)
        if milliseconds is None:
            if parse_decimal(text) is not None:
                raise self.error(node, f"expected a whole number of milliseconds, got {text!r}", "duration",
                                 element)
            try:
                value = _number(text, self.constant_values)
            except ExpressionError as problem:
                raise self.error(node, f"expected a number of milliseconds or arithmetic over the constants, got "
                                 f"{text!r} ({problem})", "duration", element) from None
            if not is_whole(value):
                raise self.error(node, f"expected a whole number of milliseconds, got {text!r} = {value:g}",
                                 "duration", element)
            milliseconds = round(value)
        if milliseconds < 0:
            raise self.error(node, f"duration must not be negative, got {text!r}", "duration", element)
        if milliseconds == 0:
            self.warn(node, f"phase {phase_name!r}: duration 0 ms is played as one cycle ({ZERO_DURATION_MS} ms), "
                      "as FIIT's loader plays it")
            return ZERO_DURATION_MS / 1000.0
        return milliseconds / 1000.0

    def no_text_children(self, node: XmlNode) -> None:
        if node.children:
            raise self.error(node.children[0], f"unexpected element <{node.children[0].tag}> in <{node.tag}>",
                             node.children[0].tag)

    def phase(self, node: XmlNode) -> Keyframe:
        extra = self.check_attributes(node, tuple(PHASE_ATTRIBUTES), ("name",), "phase", lenient=True)
        name = node.attribute("name") or ""
        parts = self.children(node, ("effectors", "duration", "finalize"))
        effectors = self.optional(node, parts["effectors"], "effectors")
        duration_node = self.required(node, parts["duration"], "duration")
        finalize_node = self.optional(node, parts["finalize"], "finalize")
        targets: dict[str, JointTarget] = {}
        texts: dict[str, str] = {}
        lines: dict[str, int] = {}
        children: list[XmlNode] = []
        if effectors is not None:   # none: holds every joint, as an empty <effectors/>
            self.no_text(effectors)
            children = effectors.children
        for child in children:
            wire, target, text = self.target(child, name)
            if wire in targets:
                self.warn(child, f"<{child.tag}> is listed twice in phase {name!r} (first on line {lines[wire]}): "
                          "the later one counts")
                del targets[wire]  # the later one also takes the later place in the phase
            targets[wire], texts[wire], lines[wire] = target, text, child.line
        is_final_text = node.attribute("isFinal")
        is_final = None
        if is_final_text is not None:
            if is_final_text.strip().lower() not in ("true", "false"):
                raise self.error(node, f"expected true or false, got {is_final_text!r}", "isFinal", f"phase {name!r}")
            is_final = is_final_text.strip().lower() == "true"
        finalize = None
        if finalize_node is not None:
            self.no_text_children(finalize_node)
            finalize = finalize_node.text.strip()
        source = KeyframeSource(line=node.line, attribute_order=tuple(k for k, _ in node.attributes),
                                duration_text=duration_node.text, value_texts=texts, target_lines=lines,
                                extra_attributes=extra)
        return Keyframe(name=name, duration_s=self.duration(duration_node, name), targets=targets,
                        next=node.attribute("next"), finalize=finalize, is_final=is_final,
                        skip_if_flag=node.attribute("skipIfFlag"), set_flag_true=node.attribute("setFlagTrue"),
                        set_flag_false=node.attribute("setFlagFalse"), source=source)

    def phases(self, node: XmlNode) -> list[Keyframe]:
        nodes = self.children(node, ("phase",))["phase"]
        if not nodes:
            raise self.error(node, "<phases> holds no <phase>", "phase")
        read: dict[str, tuple[XmlNode, Keyframe]] = {}
        for phase_node in nodes:
            keyframe = self.phase(phase_node)
            if keyframe.name in read:
                self.warn(phase_node, f"phase name {keyframe.name!r} is already used on line "
                          f"{read[keyframe.name][0].line}: this later phase replaces it")
                del read[keyframe.name]
            read[keyframe.name] = (phase_node, keyframe)
        keyframes = [keyframe for _, keyframe in read.values()]
        for phase_node, keyframe in read.values():
            if keyframe.next is not None and keyframe.next not in read:
                self.warn(phase_node, f"phase {keyframe.name!r}: next={keyframe.next!r} names no phase; the motion "
                          "ends after this phase")
            if keyframe.finalize is not None and keyframe.finalize not in read:
                self.warn(phase_node, f"phase {keyframe.name!r}: finalize {keyframe.finalize!r} names no phase; "
                          "the motion ends after this phase when another motion is requested")
        return keyframes


def loads_xml(text: str, path: str = "<string>") -> Motion:
    """Read an XML phase motion from ``text``.

    Args:
        text: the whole file (line endings as in the file: CRLF is kept for writing back).
        path: file name used in error messages and kept in ``motion.source.path``.

    Returns:
        The motion, ``source_format == "xml"``.

    Raises:
        MotionFormatError: not well-formed XML, wrong structure, missing ``low_skill``/``firstPhase``,
            ``firstPhase`` naming no phase, unknown effector, an ``end`` that is neither a number nor arithmetic
            over the constants, a negative or fractional ``duration``, a FIIT move annotation; each with path,
            line and field. (What FIIT's own loader accepts beyond REFERENCE §6a is read with a warning: module
            docstring.)
    """
    document = parse_xml(text, path)
    reader = _Reader(path)
    root = document.root
    if root.tag == "annotation":
        raise reader.error(root, "this is a FIIT move annotation (a move's preconditions and effects), not a motion: "
                           "the motion is the XML file with a <robot> root of the same move", root.tag)
    if root.tag != "robot":
        raise reader.error(root, f"the root element must be <robot>, got <{root.tag}>", root.tag)
    parts = reader.children(root, ("constants", "low_skills", "phases"))
    constants_node = reader.optional(root, parts["constants"], "constants")
    skills_node = reader.required(root, parts["low_skills"], "low_skills")
    phases_node = reader.required(root, parts["phases"], "phases")
    constants, constant_texts = reader.constants(constants_node)
    name, first_phase, skill_node, notes = reader.low_skill(skills_node)
    keyframes = reader.phases(phases_node)
    if first_phase not in {k.name for k in keyframes}:
        raise reader.error(skill_node, f"firstPhase {first_phase!r} names no phase; phases: "
                           f"{', '.join(repr(k.name) for k in keyframes)}", "firstPhase", "low_skill")
    source = MotionSource(path=path, line_ending="\r\n" if "\r\n" in text else "\n",
                          final_newline=text.endswith("\n"), xml_declaration=document.declaration,
                          root_attributes=tuple(root.attributes), constant_texts=constant_texts,
                          warnings=tuple(reader.warnings), low_skill_notes=notes)
    return Motion(name=name, keyframes=keyframes, source_format=XML, first_phase=first_phase,
                  constants=constants, header_comments=tuple(document.prolog_comments), source=source)


# ---------------------------------------------------------------------------------------------- writing
def _attribute_text(value: str) -> str:
    """Escape an attribute value for double quotes; whitespace controls as character references so that
    attribute-value normalisation gives them back."""
    return (value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
            .replace("\t", "&#9;").replace("\n", "&#10;").replace("\r", "&#13;"))


def _element_text(value: str) -> str:
    return value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _attributes(pairs: list[tuple[str, str]]) -> str:
    return "".join(f' {key}="{_attribute_text(value)}"' for key, value in pairs)


def _value_of(text: str, constants: dict[str, float]) -> float | None:
    """A number text as the reader reads it (``_number``); None if it no longer reads."""
    try:
        return _number(text, constants)
    except ExpressionError:
        return None


def _duration_text(keyframe: Keyframe, constants: dict[str, float]) -> str:
    milliseconds = keyframe.duration_s * 1000.0
    if not (math.isfinite(milliseconds) and is_whole(milliseconds) and round(milliseconds) >= 1):
        raise ConversionError(f"an XML phase lasts a whole number of milliseconds >= 1, got {milliseconds!r} ms "
                              "(round the durations, e.g. convert.to_xml(..., round_durations=True))",
                              field="duration", element=f"phase {keyframe.name!r}")
    whole = round(milliseconds)
    old = keyframe.source.duration_text if keyframe.source else None
    return old if old is not None and _value_of(old, constants) == whole else str(whole)


def _end_text(keyframe: Keyframe, wire: str, angle_rad: float, constants: dict[str, float]) -> str:
    old = keyframe.source.value_texts.get(wire) if keyframe.source else None
    if old is not None:
        old_deg = _value_of(old, constants)
        if old_deg is not None and math.radians(old_deg) == angle_rad:
            return old
    return degrees_text_for_rad(angle_rad)


def _phase_lines(keyframe: Keyframe, constants: dict[str, float]) -> list[str]:
    values = {attr: getattr(keyframe, name) for attr, name in PHASE_ATTRIBUTES.items()}
    values["isFinal"] = None if keyframe.is_final is None else ("true" if keyframe.is_final else "false")
    order = [a for a in (keyframe.source.attribute_order if keyframe.source else ()) if a in PHASE_ATTRIBUTES]
    order += [a for a in PHASE_ATTRIBUTES if a not in order]
    pairs = [(a, values[a]) for a in order if values[a] is not None]
    pairs += list(keyframe.source.extra_attributes) if keyframe.source else []
    lines = [f"\t\t<phase{_attributes(pairs)}>"]
    effector_lines = []
    for wire, target in keyframe.targets.items():
        spec = joint_by_wire(wire)
        if spec is None:
            raise ConversionError(f"unknown joint {wire!r} (targets are keyed by wire names such as 'llj3')",
                                  field=wire, element=f"phase {keyframe.name!r}")
        if target.angle_rad is None:
            if target.computed is not None:
                raise ConversionError("a computed target needs a fallback angle ('end')", field=spec.effector,
                                      element=f"phase {keyframe.name!r}")
            continue  # not commanded: an XML phase simply does not list the joint
        if not math.isfinite(target.angle_rad):
            raise ConversionError(f"angle must be finite, got {target.angle_rad!r}", field=spec.effector,
                                  element=f"phase {keyframe.name!r}")
        attrs = [("end", _end_text(keyframe, wire, target.angle_rad, constants))]
        if target.computed is not None:
            attrs.append(("computed", target.computed))
        effector_lines.append(f"\t\t\t\t<{spec.effector}{_attributes(attrs)} />")
    if effector_lines:
        lines += ["\t\t\t<effectors>", *effector_lines, "\t\t\t</effectors>"]
    else:
        lines.append("\t\t\t<effectors />")
    lines.append(f"\t\t\t<duration>{_element_text(_duration_text(keyframe, constants))}</duration>")
    if keyframe.finalize is not None:
        lines.append(f"\t\t\t<finalize>{_element_text(keyframe.finalize)}</finalize>")
    lines.append("\t\t</phase>")
    return lines


def _comment_line(comment: str) -> str:
    if "--" in comment or comment.endswith("-"):
        raise ConversionError("an XML comment may not contain '--' or end with '-'", field="header_comments")
    return f"<!--{comment}-->"


def dumps_xml(motion: Motion) -> str:
    """Write ``motion`` as an XML phase file (canonical layout, or the layout it was read with).

    ``first_phase`` None is written as the first keyframe's name; targets with ``angle_rad`` None are left
    out (an unlisted joint holds still).

    Raises:
        ConversionError: no keyframes, duplicate or empty phase names, a duration that is not a whole
            number of ms >= 1, an unknown joint key, a non-finite angle, a bad comment.
    """
    if not motion.keyframes:
        raise ConversionError(f"motion {motion.name!r} has no phases", field="phases")
    names = [k.name for k in motion.keyframes]
    for index, name in enumerate(names):
        if names.index(name) != index:
            raise ConversionError(f"phase name {name!r} is used twice", field="name", element=f"phase {name!r}")
    first_phase = motion.first_phase if motion.first_phase is not None else names[0]
    # Layout details only count when they came from an XML file; anything else gets the canonical ones.
    source = motion.source if motion.source is not None and motion.source_format == XML else MotionSource(
        xml_declaration=CANONICAL_DECLARATION)
    lines: list[str] = [source.xml_declaration] if source.xml_declaration else []
    lines += [_comment_line(c) for c in motion.header_comments]
    lines.append(f"<robot{_attributes(list(source.root_attributes))}>")
    if motion.constants:
        lines.append("\t<constants>")
        for name, value in motion.constants.items():
            old = source.constant_texts.get(name)
            text = old if old is not None and parse_decimal(old) == value else shortest_decimal(value)
            lines.append(f"\t\t<constant{_attributes([('name', name), ('value', text)])} />")
        lines += ["\t</constants>", ""]
    skill_attributes = _attributes([('name', motion.name), ('firstPhase', first_phase)])
    inside = [f"\t\t\t<{tag}>{_element_text(text)}</{tag}>" for tag, text, within in source.low_skill_notes if within]
    beside = [f"\t\t<{tag}>{_element_text(text)}</{tag}>" for tag, text, within in source.low_skill_notes if not within]
    skill_lines = ([f"\t\t<low_skill{skill_attributes}>", *inside, "\t\t</low_skill>"] if inside
                   else [f"\t\t<low_skill{skill_attributes} />"])
    lines += ["\t<low_skills>", *skill_lines, *beside, "\t</low_skills>", "", "\t<phases>"]
    constants = dict(motion.constants)
    for keyframe in motion.keyframes:
        lines += _phase_lines(keyframe, constants)
    lines += ["\t</phases>", "</robot>"]
    text = "\n".join(lines) + ("\n" if source.final_newline else "")
    return text.replace("\n", source.line_ending) if source.line_ending != "\n" else text
