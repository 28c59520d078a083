"""`motion-studio convert`, `validate`, `motions list` and `--version`, run as a user runs them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import motions

CLI = [sys.executable, "-m", "motion_studio"]
FILES = Path(__file__).resolve().parents[2] / "motions" / "files"


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(CLI + list(args), capture_output=True, text=True, timeout=120)


def test_convert_webots_to_xml_and_back_gives_the_same_poses(tmp_path):
    xml, back = tmp_path / "turn.xml", tmp_path / "turn.motion"
    assert run_cli("convert", str(FILES / "turn_left.motion"), str(xml)).returncode == 0
    result = run_cli("convert", str(xml), str(back))
    assert result.returncode == 0, result.stderr
    original, again = motions.load(FILES / "turn_left.motion"), motions.load(back)
    assert len(again.keyframes) == len(original.keyframes)
    for a, b in zip(original.keyframes, again.keyframes):
        assert abs(a.duration_s - b.duration_s) < 1e-9
        assert {k: t.angle_rad for k, t in a.targets.items()} == {k: t.angle_rad for k, t in b.targets.items()}


def test_convert_names_the_option_that_gives_a_cycle_up_and_writes_nothing(tmp_path):
    target = tmp_path / "walk.motion"
    result = run_cli("convert", str(FILES / "walk_forward.xml"), str(target))
    assert result.returncode == 2 and not target.exists()
    assert len(result.stderr.strip().splitlines()) == 1 and "--unroll-cycle" in result.stderr
    result = run_cli("convert", str(FILES / "walk_forward.xml"), str(target), "--unroll-cycle", "--drop-dynamic",
                     "--drop-unreachable")
    assert result.returncode == 0, result.stderr
    assert motions.load(target).source_format == "webots"


def test_validate_reports_each_file_on_one_line_with_its_line_and_field(tmp_path):
    text = (FILES / "kick.xml").read_text()
    at = text.index(' end="') + len(' end="')
    line = text[:at].count("\n") + 1
    bad = tmp_path / "bad.xml"
    bad.write_text(text[:at] + "abc" + text[text.index('"', at):])  # the first angle is not a number
    good = FILES / "kick.xml"
    result = run_cli("validate", str(good), str(bad))
    assert result.returncode == 1
    assert f"{good}: ok" in result.stdout
    assert result.stderr.strip().startswith(f"{bad}:{line}:") and "'end'" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    missing = run_cli("validate", str(tmp_path / "none.xml"))
    assert missing.returncode == 2 and "cannot read" in missing.stderr


def test_motions_list_shows_every_shipped_file_and_version_prints_the_version():
    result = run_cli("motions", "list")
    assert result.returncode == 0, result.stderr
    listed = {line.split()[0] for line in result.stdout.splitlines()[1:]}
    shipped = {str(p.relative_to(FILES)) for p in FILES.rglob("*") if p.suffix in (".xml", ".motion")}
    assert listed == shipped
    version = run_cli("--version")
    assert version.returncode == 0 and version.stdout.startswith("motion-studio (nao3d-toolkit) ")
