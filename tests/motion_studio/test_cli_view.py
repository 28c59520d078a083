"""`motion-studio view` and `demo` as a user runs them: real processes, a real HTTP socket."""

import base64
import json
import re
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

CLI = [sys.executable, "-m", "motion_studio"]


def scene_commands(html: str) -> list[dict]:
    """Decode the msgpack commands meshcat embeds (base64) in a static HTML scene."""
    import umsgpack

    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return [umsgpack.unpackb(base64.b64decode(blob)) for blob in blobs]


def run_cli(*args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(CLI + list(args), capture_output=True, text=True, timeout=timeout)


def test_view_html_writes_a_scene_with_every_body(tmp_path):
    out = tmp_path / "pose.html"
    pose = tmp_path / "pose.json"
    pose.write_text(json.dumps({"joints_deg": {"llj3": 30, "LKneePitch": -60}}))
    result = run_cli("view", "--pose", str(pose), "-j", "he1=45", "--html", str(out))
    assert result.returncode == 0, result.stderr
    html = out.read_text()
    assert html.startswith("<!DOCTYPE html>") or "<html" in html[:200]
    commands = scene_commands(html)
    objects = {c["path"] for c in commands if c["type"] == "set_object"}
    transforms = {c["path"] for c in commands if c["type"] == "set_transform"}
    for body in ("torso", "head", "lfoot", "rlowerarm", "lhip2"):
        assert f"/meshcat/nao/{body}/shape" in objects
        assert f"/meshcat/nao/{body}" in transforms


def test_view_rejects_bad_input_with_a_clear_message(tmp_path):
    result = run_cli("view", "-j", "llj9=10", "--html", str(tmp_path / "x.html"))
    assert result.returncode != 0 and "unknown joint 'llj9'" in (result.stderr + result.stdout)
    result = run_cli("view", "-j", "llj3=nan", "--html", str(tmp_path / "x.html"))
    assert result.returncode != 0 and "must be finite" in (result.stderr + result.stdout)
    result = run_cli("view", "--type", "7", "--html", str(tmp_path / "x.html"))
    assert result.returncode == 2 and "'--type'" in result.stderr and "expected 0 to 4" in result.stderr
    assert not (tmp_path / "x.html").exists()


def test_view_serves_on_loopback_only():
    process = subprocess.Popen(CLI + ["view", "-j", "llj3=20"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True)
    try:
        url = None
        for _ in range(200):
            line = process.stdout.readline()
            match = re.search(r"meshcat viewer: (http://\S+)", line)
            if match:
                url = match.group(1)
                break
        assert url is not None and url.startswith("http://127.0.0.1:")
        with urllib.request.urlopen(url, timeout=10) as response:
            assert response.status == 200
            assert b"meshcat" in response.read().lower()
    finally:
        process.terminate()
        process.wait(timeout=10)


def test_demo_writes_models_and_preview(tmp_path):
    result = run_cli("demo", "--out", str(tmp_path), "--match-duration", "2", "--players", "1")
    assert result.returncode == 0, result.stderr
    assert "4.6071" in result.stdout and "camera height in the crouch" in result.stdout
    for robot_type in range(5):
        assert (tmp_path / f"nao_type{robot_type}.xml").read_text().startswith("<mujoco")
        assert "<robot" in (tmp_path / f"nao_type{robot_type}.urdf").read_text()
    assert (tmp_path / "preview.html").stat().st_size > 10_000
    assert "match-0      0:0" in result.stdout
    assert (tmp_path / "match" / "results.jsonl").exists() and (tmp_path / "match" / "replay.html").exists()


def test_bench_kinematics_prints_the_figures_as_json():
    result = run_cli("bench", "kinematics", "--json", "--poses", "5")
    assert result.returncode == 0, result.stderr
    figures = json.loads(result.stdout.strip().splitlines()[-1])
    assert set(figures) >= {"fk_us", "ik_ms", "max_com_diff_m", "max_frame_diff_m"}
    assert figures["max_com_diff_m"] < 1e-6 and figures["max_frame_diff_m"] < 1e-6
