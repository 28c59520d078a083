"""The room graph of DESIGN.md, read from every module's imports (as magma's TestDependencies does)."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ROOMS = ("kinematics", "motions", "agent", "sim", "nao3d_gym", "motion_studio")
# DESIGN.md "Dependencies between rooms"; sim may use only agent.protocol from the agent room.
ALLOWED = {
    "kinematics": set(),
    "motions": {"kinematics"},
    "agent": {"motions", "kinematics"},
    "sim": {"agent.protocol", "kinematics"},
    # The Gymnasium environments (issue 16): the in-process world spoken to in the wire language.
    "nao3d_gym": {"sim", "agent.protocol", "kinematics"},
    "motion_studio": {"sim", "agent", "motions", "kinematics", "nao3d_gym"},
}


def imported_modules(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


def room_modules(room: str) -> list[Path]:
    return sorted((ROOT / room).rglob("*.py"))


@pytest.mark.parametrize("room", ROOMS)
def test_rooms_import_only_what_design_allows(room):
    violations = []
    for path in room_modules(room):
        for name in imported_modules(path):
            top = name.split(".")[0]
            if top not in ROOMS or top == room:
                continue
            if not any(name == dep or name.startswith(dep + ".") for dep in ALLOWED[room]):
                violations.append(f"{path.relative_to(ROOT)} imports {name}")
    assert not violations, "imports against DESIGN.md's room graph:\n" + "\n".join(violations)


def test_nothing_imports_motion_studio():
    offenders = [f"{p.relative_to(ROOT)}" for room in ROOMS if room != "motion_studio"
                 for p in room_modules(room) if any(n.split(".")[0] == "motion_studio" for n in imported_modules(p))]
    assert not offenders


def test_agent_runs_without_mujoco():
    """The agent must run against the real server on machines without MuJoCo: importing it loads none."""
    modules = [p.relative_to(ROOT).with_suffix("").as_posix().replace("/", ".") for p in room_modules("agent")]
    modules = [m.removesuffix(".__init__") for m in modules if not m.endswith("__main__")]
    code = ("import importlib, sys\n"
            f"for name in {modules!r}:\n    importlib.import_module(name)\n"
            "print('mujoco' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "False"


def _edits_sys_path(path: Path) -> bool:
    """True if the module calls a mutating method of ``sys.path`` or assigns to it."""
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        target = None
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            target = node.func.value
        elif isinstance(node, (ast.Assign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            target = next((t for t in targets if isinstance(t, ast.Attribute)), None)
        if (isinstance(target, ast.Attribute) and target.attr == "path" and isinstance(target.value, ast.Name)
                and target.value.id == "sys"):
            return True
    return False


def test_no_module_edits_sys_path():
    """The editable install makes every room importable; a sys.path edit hides a missing install step."""
    folders = (*ROOMS, "benchmarks", "scripts", "tests")
    offenders = [str(p.relative_to(ROOT)) for folder in folders for p in sorted((ROOT / folder).rglob("*.py"))
                 if _edits_sys_path(p)]
    assert not offenders, "modules that edit sys.path: " + ", ".join(offenders)
