"""One section of the dynamic elements' file (``motions/params/dynamic_elements.toml``, ``agent.motion.dynamic``)
rewritten through the tuning room's one writer (``params_file.write_sections``): the walk-lean, turn-gain and
kick-distance tuners all write that way, and the written file must load back to exactly the element given, or
it is left as it was."""

from __future__ import annotations

from pathlib import Path

from agent.motion.dynamic import DEFAULT_PARAMS_PATH, load_dynamic_params
from motion_studio.tuning.params_file import write_sections


def write_dynamic_section(name: str, element: object, text: str, path: Path = DEFAULT_PARAMS_PATH) -> Path:
    """Replace section ``[name]`` of ``path`` by ``text`` (its TOML, provenance included); ``element`` is what the
    section must load back to (``getattr(DynamicParams, name)``).

    Raises:
        TuningError: the rewritten file does not load back to ``element`` (the file is left unchanged).
    """
    def check(written: Path) -> None:
        loaded = getattr(load_dynamic_params(written), name)
        if loaded != element:
            raise ValueError(f"[{name}] reads back as {loaded}, expected {element}")

    return write_sections(path, {name: text}, check)


__all__ = ["write_dynamic_section"]
