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
- ``<duration>`` must be a whole number of milliseconds > 0 (the 2012 agent uses ``Integer.parseInt``, and a
  controller divides by the duration).
- Phase names are matched exactly (the 2012 agent ignores case; two names differing only in case would
  be ambiguous there, so avoid them).
"""

from __future__ import annotations

import logging
import math

from motions.errors import ConversionError, MotionFormatError
from motions.joints import joint_by_effector, joint_by_wire, known_effector_names
from motions.model import XML, JointTarget, Keyframe, KeyframeSource, Motion, MotionSource
from motions.numbers import degrees_text_for_rad, is_whole, parse_decimal, parse_integer, shortest_decimal
from motions.xml_tree import XmlNode, parse_xml

logger = logging.getLogger(__name__)

CANONICAL_DECLARATION = '<?xml version="1.0" encoding="UTF-8"?>'

# XML attribute name -> Keyframe field, in the canonical (REFERENCE §6a) order.
PHASE_ATTRIBUTES: dict[str, str] = {
    "name": "name", "next": "next", "isFinal": "is_final", "skipIfFlag": "skip_if_flag",
    "setFlagTrue": "set_flag_true", "setFlagFalse": "set_flag_false",
}


# ---------------------------------------------------------------------------------------------- reading
class _Reader:
    """Turns the element tree of one file into a Motion, raising errors that name path, line and field."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.warnings: list[str] = []

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
                         element: str | None = None) -> None:
        for key, _ in node.attributes:
            if key not in allowed:
                raise self.error(node, f"unknown attribute {key!r}; allowed: {', '.join(allowed)}", key,
                                 element or node.tag)
        for key in required:
            if node.attribute(key) is None:
                raise self.error(node, "missing required attribute", key, element or node.tag)

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
        return values, texts

    def low_skill(self, node: XmlNode) -> tuple[str, str, XmlNode]:
        skills = self.children(node, ("low_skill",))["low_skill"]
        if len(skills) > 1:
            raise self.error(skills[1], "only one <low_skill> per file is allowed", "low_skill")
        skill = self.required(node, skills, "low_skill")
        self.no_text(skill)
        self.check_attributes(skill, ("name", "firstPhase"), ("name", "firstPhase"))
        return skill.attribute("name") or "", skill.attribute("firstPhase") or "", skill

    def target(self, node: XmlNode, phase_name: str) -> tuple[str, JointTarget, str]:
        spec = joint_by_effector(node.tag)
        if spec is None:
            raise self.error(node, f"unknown effector <{node.tag}>; known: {', '.join(known_effector_names())}",
                             node.tag, f"phase {phase_name!r}")
        self.no_text(node)
        self.check_attributes(node, ("end", "computed"), ("end",))
        text = node.attribute("end") or ""
        angle_deg = parse_decimal(text)
        if angle_deg is None:
            raise self.error(node, f"expected a number, got {text!r}", "end", node.tag)
        return spec.perceptor, JointTarget(math.radians(angle_deg), node.attribute("computed")), text

    def duration(self, node: XmlNode, phase_name: str) -> float:
        self.no_text_children(node)
        text = node.text
        element = f"phase {phase_name!r}"
        milliseconds = parse_integer(text)
        if milliseconds is None:
            what = "a whole number of" if parse_decimal(text) is not None else "a number of"
            raise self.error(node, f"expected {what} milliseconds, got {text!r}", "duration", element)
        if milliseconds < 0:
            raise self.error(node, f"duration must not be negative, got {text!r}", "duration", element)
        if milliseconds == 0:
            raise self.error(node, "duration must be at least 1 ms, got 0", "duration", element)
        return milliseconds / 1000.0

    def no_text_children(self, node: XmlNode) -> None:
        if node.children:
            raise self.error(node.children[0], f"unexpected element <{node.children[0].tag}> in <{node.tag}>",
                             node.children[0].tag)

    def phase(self, node: XmlNode) -> Keyframe:
        self.check_attributes(node, tuple(PHASE_ATTRIBUTES), ("name",), "phase")
        name = node.attribute("name") or ""
        parts = self.children(node, ("effectors", "duration", "finalize"))
        effectors = self.required(node, parts["effectors"], "effectors")
        duration_node = self.required(node, parts["duration"], "duration")
        finalize_node = self.optional(node, parts["finalize"], "finalize")
        self.no_text(effectors)
        targets: dict[str, JointTarget] = {}
        texts: dict[str, str] = {}
        lines: dict[str, int] = {}
        for child in effectors.children:
            wire, target, text = self.target(child, name)
            if wire in targets:
                raise self.error(child, f"<{child.tag}> is listed twice in phase {name!r}", child.tag)
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
                                duration_text=duration_node.text, value_texts=texts, target_lines=lines)
        return Keyframe(name=name, duration_s=self.duration(duration_node, name), targets=targets,
                        next=node.attribute("next"), finalize=finalize, is_final=is_final,
                        skip_if_flag=node.attribute("skipIfFlag"), set_flag_true=node.attribute("setFlagTrue"),
                        set_flag_false=node.attribute("setFlagFalse"), source=source)

    def phases(self, node: XmlNode) -> list[Keyframe]:
        nodes = self.children(node, ("phase",))["phase"]
        if not nodes:
            raise self.error(node, "<phases> holds no <phase>", "phase")
        keyframes: list[Keyframe] = []
        first_line: dict[str, int] = {}
        for phase_node in nodes:
            keyframe = self.phase(phase_node)
            if keyframe.name in first_line:
                raise self.error(phase_node, f"phase name {keyframe.name!r} is already used on line "
                                 f"{first_line[keyframe.name]}", "name", "phase")
            first_line[keyframe.name] = phase_node.line
            keyframes.append(keyframe)
        for phase_node, keyframe in zip(nodes, keyframes):
            if keyframe.next is not None and keyframe.next not in first_line:
                self.warn(phase_node, f"phase {keyframe.name!r}: next={keyframe.next!r} names no phase; the motion "
                          "ends after this phase")
            if keyframe.finalize is not None and keyframe.finalize not in first_line:
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
            ``firstPhase`` naming no phase, duplicate phase names, unknown effector, non-numeric ``end``,
            bad or non-positive ``duration``; each with path, line and field.
    """
    document = parse_xml(text, path)
    reader = _Reader(path)
    root = document.root
    if root.tag != "robot":
        raise reader.error(root, f"the root element must be <robot>, got <{root.tag}>", root.tag)
    parts = reader.children(root, ("constants", "low_skills", "phases"))
    constants_node = reader.optional(root, parts["constants"], "constants")
    skills_node = reader.required(root, parts["low_skills"], "low_skills")
    phases_node = reader.required(root, parts["phases"], "phases")
    constants, constant_texts = reader.constants(constants_node)
    name, first_phase, skill_node = reader.low_skill(skills_node)
    keyframes = reader.phases(phases_node)
    if first_phase not in {k.name for k in keyframes}:
        raise reader.error(skill_node, f"firstPhase {first_phase!r} names no phase; phases: "
                           f"{', '.join(repr(k.name) for k in keyframes)}", "firstPhase", "low_skill")
    source = MotionSource(path=path, line_ending="\r\n" if "\r\n" in text else "\n",
                          final_newline=text.endswith("\n"), xml_declaration=document.declaration,
                          root_attributes=tuple(root.attributes), constant_texts=constant_texts,
                          warnings=tuple(reader.warnings))
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


def _duration_text(keyframe: Keyframe) -> str:
    milliseconds = keyframe.duration_s * 1000.0
    if not (math.isfinite(milliseconds) and is_whole(milliseconds) and round(milliseconds) >= 1):
        raise ConversionError(f"an XML phase lasts a whole number of milliseconds >= 1, got {milliseconds!r} ms "
                              "(round the durations, e.g. convert.to_xml(..., round_durations=True))",
                              field="duration", element=f"phase {keyframe.name!r}")
    whole = round(milliseconds)
    old = keyframe.source.duration_text if keyframe.source else None
    return old if old is not None and parse_integer(old) == whole else str(whole)


def _end_text(keyframe: Keyframe, wire: str, angle_rad: float) -> str:
    old = keyframe.source.value_texts.get(wire) if keyframe.source else None
    if old is not None:
        old_deg = parse_decimal(old)
        if old_deg is not None and math.radians(old_deg) == angle_rad:
            return old
    return degrees_text_for_rad(angle_rad)


def _phase_lines(keyframe: Keyframe) -> list[str]:
    values = {attr: getattr(keyframe, name) for attr, name in PHASE_ATTRIBUTES.items()}
    values["isFinal"] = None if keyframe.is_final is None else ("true" if keyframe.is_final else "false")
    order = [a for a in (keyframe.source.attribute_order if keyframe.source else ()) if a in PHASE_ATTRIBUTES]
    order += [a for a in PHASE_ATTRIBUTES if a not in order]
    pairs = [(a, values[a]) for a in order if values[a] is not None]
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
        attrs = [("end", _end_text(keyframe, wire, target.angle_rad))]
        if target.computed is not None:
            attrs.append(("computed", target.computed))
        effector_lines.append(f"\t\t\t\t<{spec.effector}{_attributes(attrs)} />")
    if effector_lines:
        lines += ["\t\t\t<effectors>", *effector_lines, "\t\t\t</effectors>"]
    else:
        lines.append("\t\t\t<effectors />")
    lines.append(f"\t\t\t<duration>{_element_text(_duration_text(keyframe))}</duration>")
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
    lines += ["\t<low_skills>",
              f"\t\t<low_skill{_attributes([('name', motion.name), ('firstPhase', first_phase)])} />",
              "\t</low_skills>", "", "\t<phases>"]
    for keyframe in motion.keyframes:
        lines += _phase_lines(keyframe)
    lines += ["\t</phases>", "</robot>"]
    text = "\n".join(lines) + ("\n" if source.final_newline else "")
    return text.replace("\n", source.line_ending) if source.line_ending != "\n" else text
