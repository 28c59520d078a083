"""``motion-studio play``: a motion played headless on our simulator, with the verdict as the exit code."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from motion_studio.cli import _register_commands, app

CROUCH = """<?xml version="1.0" encoding="UTF-8"?>
<robot>
  <low_skills><low_skill name="crouch" firstPhase="down"/></low_skills>
  <phases>
    <phase name="down" next="hold">
      <effectors>
        <lle3 end="30"/><rle3 end="30"/><lle4 end="-60"/><rle4 end="-60"/><lle5 end="30"/><rle5 end="30"/>
      </effectors>
      <duration>500</duration>
    </phase>
    <phase name="hold" isFinal="true">
      <effectors/>
      <duration>300</duration>
    </phase>
  </phases>
</robot>
"""

# Both hips thrown far forward with straight knees: the robot topples backward.
TOPPLE = CROUCH.replace('name="crouch"', 'name="topple"').replace(
    '<lle3 end="30"/><rle3 end="30"/><lle4 end="-60"/><rle4 end="-60"/><lle5 end="30"/><rle5 end="30"/>',
    '<lle3 end="90"/><rle3 end="90"/>').replace("<duration>500</duration>", "<duration>200</duration>")


def _run(*args: str):
    _register_commands()
    return CliRunner().invoke(app, ["play", *args])


def test_a_crouch_stays_up_and_writes_its_plot_and_animation(tmp_path):
    motion = tmp_path / "crouch.xml"
    motion.write_text(CROUCH)
    result = _run(str(motion), "--json", "--plot", str(tmp_path / "c.png"), "--html", str(tmp_path / "c.html"))
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output.strip().splitlines()[-1])
    assert summary["fell"] is False
    assert 0.30 < summary["final_torso_height_m"] < 0.37   # crouched, below the 0.385 m of the zero pose
    assert (tmp_path / "c.png").stat().st_size > 10_000
    assert "meshcat" in (tmp_path / "c.html").read_text()[:200_000].lower()


def test_a_motion_that_topples_the_robot_exits_with_1(tmp_path):
    motion = tmp_path / "topple.xml"
    motion.write_text(TOPPLE)
    result = _run(str(motion), "--json", "--hold", "2")
    assert result.exit_code == 1, result.output
    assert json.loads(result.output.strip().splitlines()[-1])["fell"] is True


def test_a_malformed_file_names_the_line_and_exits_with_2(tmp_path):
    motion = tmp_path / "bad.xml"
    motion.write_text(CROUCH.replace('<lle4 end="-60"/>', '<lle4 end="minus sixty"/>'))
    result = _run(str(motion))
    assert result.exit_code == 2
    assert "bad.xml:7:" in result.output and "lle4" in result.output
