"""The protocol room stays light: standard library, its own modules and the toolkit's base error only.

sim/ and the agent both import agent.protocol, and the agent must run against the real server without
MuJoCo, so an import of a heavy or upward dependency here is a design error, caught by reading the imports.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import agent.protocol

PROTOCOL_DIR = Path(agent.protocol.__file__).parent
ALLOWED_PROJECT_IMPORTS = {"agent.protocol", "kinematics.errors"}


def _imports(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module)
    return names


def test_protocol_modules_import_only_the_standard_library_and_allowed_project_modules() -> None:
    modules = sorted(PROTOCOL_DIR.glob("*.py"))
    assert len(modules) >= 9
    for module in modules:
        for name in _imports(module):
            top = name.split(".")[0]
            if top in sys.stdlib_module_names or top == "__future__":
                continue
            assert any(name == allowed or name.startswith(allowed + ".") for allowed in ALLOWED_PROJECT_IMPORTS), (
                f"{module.name} imports {name}"
            )


def test_no_module_of_the_agent_imports_mujoco() -> None:
    for module in Path(agent.protocol.__file__).parents[1].rglob("*.py"):
        assert not any(name.split(".")[0] == "mujoco" for name in _imports(module)), module
