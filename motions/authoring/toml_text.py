"""TOML literals for the parameter files the toolkit writes (``motions/params/*.toml``).

Why here: the authoring modules write their own parameter files and the tuning room
(``motion_studio.tuning.params_file``) rewrites sections of them; both must spell numbers the same way (floats
rounded to 6 decimals, so a rewrite that changes nothing leaves the file byte for byte), and motions may not
import motion_studio, so the one spelling lives in this room.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields, is_dataclass


def toml_value(value: object) -> str:
    """A TOML literal of a number, bool, string, list, mapping or dataclass (an inline table of its fields).

    Raises:
        TypeError: a value TOML cannot hold (None, an object).
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(round(value, 6))
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if is_dataclass(value) and not isinstance(value, type):
        value = {f.name: getattr(value, f.name) for f in fields(value)}
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} as TOML")
