"""The motions room imports only the standard library, numpy-free kinematics tables and itself.

DESIGN.md: ``motions -> kinematics`` only, and the agent (which must run without MuJoCo) plays these
files, so no module here may import MuJoCo or another room.
"""

from __future__ import annotations

import ast
from pathlib import Path

import motions

ALLOWED_ROOTS = {"motions", "kinematics", "__future__"}
FORBIDDEN_ROOTS = {"mujoco", "sim", "agent", "motion_studio", "pinocchio", "placo"}


def _imported_roots(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), str(path))
    roots: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            roots.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            roots.add(node.module.split(".")[0])
    return roots


def test_motions_imports_no_other_room_and_no_mujoco():
    import sys

    modules = sorted(Path(motions.__file__).parent.glob("*.py"))
    assert len(modules) > 5
    for module in modules:
        roots = _imported_roots(module)
        assert not roots & FORBIDDEN_ROOTS, (module.name, roots & FORBIDDEN_ROOTS)
        third_party = {r for r in roots - ALLOWED_ROOTS if r not in sys.stdlib_module_names}
        assert not third_party, (module.name, third_party)


def test_kinematics_imports_used_here_are_the_light_ones():
    # Only the spec and name maps: kinematics.fk / ik / mjcf pull in Pinocchio, PlaCo and MuJoCo.
    for module in Path(motions.__file__).parent.glob("*.py"):
        tree = ast.parse(module.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("kinematics"):
                assert node.module in ("kinematics", "kinematics.errors", "kinematics.spec", "kinematics.names"), \
                    (module.name, node.module)
