"""The gait parameter file (``motions/params/gait.toml``): one section per generated walk motion on top of a
shared ``[common]`` section, read into :class:`~motions.authoring.gait.GaitParams` and written back by the
tuner.

Layout::

    [common]                 # shared by every section (posture, timing), overridable per section
    torso_height_m = 0.345
    arm = { shoulder_pitch_deg = -90.0 }
    [walk_forward]           # section name = motion name (XML low_skill name)
    provenance = "..."       # how these numbers were found (not a gait parameter)
    step_length_m = 0.06

Units are in the key names (``_m``, ``_deg``, ``_ms``); cycles are 20 ms server cycles.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import fields, replace
from pathlib import Path

from motions.authoring.common import PARAMS_DIR, ArmPose
from motions.authoring.gait import GaitParams
from motions.authoring.toml_text import toml_value

#: The shipped gait parameter file.
GAIT_PARAMS_PATH = PARAMS_DIR / "gait.toml"
#: Section shared by all motions.
COMMON = "common"
#: Keys of a section that are not gait parameters.
META_KEYS = ("provenance", "measured", "measured_forward_m_s", "measured_left_m_s", "measured_stop_m")


def _gait_values(table: Mapping[str, object], where: str) -> dict[str, object]:
    """Gait parameter values of one TOML table (``arm`` as an inline table of ArmPose fields).

    Raises:
        ValueError: an unknown key (names the section and lists the known ones) or a bad arm table.
    """
    known = {f.name for f in fields(GaitParams)}
    values: dict[str, object] = {}
    for key, value in table.items():
        if key in META_KEYS:
            continue
        if key not in known:
            raise ValueError(f"{where}: unknown key {key!r}; known: {', '.join(sorted(known))}")
        if key == "arm":
            if not isinstance(value, Mapping):
                raise ValueError(f"{where}: arm must be an inline table of {[f.name for f in fields(ArmPose)]}")
            arm_known = {f.name for f in fields(ArmPose)}
            if set(value) - arm_known:
                raise ValueError(f"{where}: arm has unknown keys {sorted(set(value) - arm_known)}; "
                                 f"known: {sorted(arm_known)}")
            value = ArmPose(**value)
        values[key] = value
    return values


def parse_gait_params(text: str, path: str = "<string>") -> dict[str, GaitParams]:
    """Motion name -> GaitParams of every section but ``[common]`` (defaults <- common <- section).

    Raises:
        ValueError: bad TOML, an unknown key, or a bad value (the message names the file and section).
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"{path}: {error}") from None
    common = _gait_values(data.get(COMMON, {}), f"{path} [{COMMON}]")
    out = {}
    for name, table in data.items():
        if name == COMMON:
            continue
        where = f"{path} [{name}]"
        if not isinstance(table, Mapping):
            raise ValueError(f"{where}: expected a section")
        try:
            out[name] = GaitParams(**{**common, **_gait_values(table, where)})
        except TypeError as error:
            raise ValueError(f"{where}: {error}") from None
    return out


def load_gait_params(path: Path = GAIT_PARAMS_PATH) -> dict[str, GaitParams]:
    """Read a gait parameter file; see :func:`parse_gait_params`."""
    return parse_gait_params(Path(path).read_text(encoding="utf-8"), str(path))


def provenance(path: Path, section: str) -> str:
    """The ``provenance`` text of a section ("" if none)."""
    data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    return str(data.get(section, {}).get("provenance", ""))


def section_overrides(params: GaitParams, common: GaitParams) -> dict[str, object]:
    """The parameters where ``params`` differs from ``common`` (what a section must say)."""
    return {f.name: getattr(params, f.name) for f in fields(params)
            if getattr(params, f.name) != getattr(common, f.name)}


def dumps_gait_params(common: GaitParams, sections: Mapping[str, GaitParams],
                      provenances: Mapping[str, str], header: str,
                      measured: Mapping[str, Mapping[str, float]] | None = None) -> str:
    """TOML text: ``header`` as comments, the full ``[common]`` section, then each motion's differences, each
    after its provenance and its ``measured`` figures (meta keys the motion files copy into their constants,
    written with 4 decimals as the tuner always has)."""
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    lines += ["", f"[{COMMON}]"]
    if provenances.get(COMMON):
        lines.append(f"provenance = {toml_value(provenances[COMMON])}")
    lines += [f"{f.name} = {toml_value(getattr(common, f.name))}" for f in fields(common)]
    for name, params in sections.items():
        lines += ["", f"[{name}]"]
        if provenances.get(name):
            lines.append(f"provenance = {toml_value(provenances[name])}")
        lines += [f"{key} = {value:.4f}" for key, value in (measured or {}).get(name, {}).items()]
        lines += [f"{key} = {toml_value(value)}" for key, value in section_overrides(params, common).items()]
    return "\n".join(lines) + "\n"


def read_common(path: Path = GAIT_PARAMS_PATH) -> GaitParams:
    """The ``[common]`` section alone as GaitParams."""
    data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    return replace(GaitParams(), **_gait_values(data.get(COMMON, {}), f"{path} [{COMMON}]"))


def read_header(path: Path = GAIT_PARAMS_PATH) -> str:
    """The leading comment block of a parameter file (without the ``#``), to keep it when rewriting."""
    lines = []
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        if not line.startswith("#"):
            break
        lines.append(line[1:].removeprefix(" "))
    return "\n".join(lines)


__all__ = ["COMMON", "GAIT_PARAMS_PATH", "dumps_gait_params", "load_gait_params", "parse_gait_params",
           "provenance", "read_common", "read_header", "section_overrides"]
