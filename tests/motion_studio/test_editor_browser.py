"""The editor in a real browser: Debian's headless Chromium driven by Playwright (never a downloaded browser).

Opens the editor on a motion, moves a slider, drags an IK handle, plays, runs the physics preview, saves and
checks the file changed exactly as expected, checks the unsaved-changes warning on closing, and stores a
screenshot in out/editor_screenshot.png. The slider -> 3D view latency is measured and printed (figures only,
no timed assertion; ``motion-studio bench editor`` prints the same figure on its own).
"""

import json
import subprocess
from pathlib import Path

import pytest

from motion_studio.editor.browser import browser_unavailable_reason, headless_chromium, latency_figures, \
    open_editor, press_slider
from motion_studio.editor.server import EditorServer
from tests.motion_studio.test_editor_session import TEST_XML

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "out"

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def browser_context():
    reason = browser_unavailable_reason()
    if reason is not None and "Chromium" in reason:
        # The project's own set-up installs Debian's chromium where it can (root and apt).
        subprocess.run(["bash", str(ROOT / "scripts" / "setup_browser.sh")], capture_output=True, timeout=900)
        reason = browser_unavailable_reason()
    if reason is not None:
        pytest.skip(f"browser tests need headless Chromium: {reason}")
    with headless_chromium() as context:
        yield context


@pytest.fixture
def editor(tmp_path):
    path = tmp_path / "editor_test.xml"
    path.write_text(TEST_XML)
    server = EditorServer(path).start_in_thread()
    yield server
    server.stop()


def body_quaternion(page, body: str) -> list[float]:
    return page.evaluate(f"motionStudio.viewer.scene_tree.find(['meshcat', 'nao', '{body}']).object.quaternion"
                         ".toArray()")


def on_screen(page, position_m: list[float]) -> dict:
    """Page coordinates of a point of the editor's display frame (x right, y forward, z up; m)."""
    return page.evaluate("""(p) => {
        const viewer = motionStudio.viewer, THREE = MeshCat.THREE;
        const root = viewer.scene_tree.find(['meshcat']).object;
        const point = root.localToWorld(new THREE.Vector3(p[0], p[1], p[2])).project(viewer.camera);
        const rect = viewer.renderer.domElement.getBoundingClientRect();
        return {x: rect.left + (point.x + 1) / 2 * rect.width, y: rect.top + (1 - point.y) / 2 * rect.height};
    }""", position_m)


def test_edit_play_preview_and_save_in_a_real_browser(browser_context, editor, capsys):
    page = open_editor(browser_context, editor.url)
    problems = []
    page.on("pageerror", lambda error: problems.append(f"page error: {error}"))
    page.on("console", lambda message: problems.append(f"console: {message.text}")
            if message.type == "error" else None)
    assert page.locator("#keyframe-list li").count() == 3
    assert page.locator("#view canvas").count() == 1

    # Select the "lift" phase and move the LHipPitch slider five steps (0.1 deg each) with the keyboard.
    page.click("#kf-1")
    page.wait_for_function("motionStudio.state.selected === 1")
    assert page.input_value("#number-llj3") == "45"
    thigh_before = body_quaternion(page, "lthigh")
    press_slider(page, "llj3", "ArrowRight", 5)
    assert page.input_value("#slider-llj3") == "45.5" and page.input_value("#number-llj3") == "45.5"
    assert page.evaluate("motionStudio.state.pose_deg.llj3") == 45.5
    assert "unsaved" in page.text_content("#dirty-mark")
    assert body_quaternion(page, "lthigh") != thigh_before  # the 3D view moved the thigh

    # Time the slider -> view path (latency figures printed, never asserted).
    page.evaluate("const m = motionStudio.metrics; m.sliderLatenciesMs.length = 0; m.serverMs.length = 0;"
                  "m.replyMs.length = 0")
    latencies = press_slider(page, "llj3", "ArrowRight", 10) + press_slider(page, "llj3", "ArrowLeft", 10)
    figures = latency_figures(latencies, page.evaluate("motionStudio.metrics.serverMs"),
                              page.evaluate("motionStudio.metrics.replyMs"))
    assert page.evaluate("motionStudio.state.pose_deg.llj3") == 45.5  # back where it was

    # Drag the left foot handle up in the 3D view: IK moves the left leg, one undo step for the whole drag.
    before = page.evaluate("motionStudio.state")
    foot = before["handles"]["lfoot"]["position_m"]
    start, goal = on_screen(page, foot), on_screen(page, [foot[0], foot[1], foot[2] + 0.02])  # 2 cm up
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    for step in range(1, 9):
        fraction = step / 8
        page.mouse.move(start["x"] + (goal["x"] - start["x"]) * fraction,
                        start["y"] + (goal["y"] - start["y"]) * fraction)
    page.mouse.up()
    page.evaluate("motionStudio.idle()")
    assert page.text_content("#ik-status").startswith("moved "), page.text_content("#ik-status")
    after = page.evaluate("motionStudio.state")
    foot_before, foot_after = before["handles"]["lfoot"]["position_m"], after["handles"]["lfoot"]["position_m"]
    assert foot_after[2] > foot_before[2] + 0.005, (foot_before, foot_after, problems)
    assert after["handles"]["rfoot"] == before["handles"]["rfoot"]
    assert after["pose_deg"]["llj4"] != before["pose_deg"]["llj4"]
    page.click("#undo")
    page.wait_for_function("motionStudio.state.pose_deg.llj4 === -90")
    assert page.evaluate("motionStudio.state.pose_deg") == before["pose_deg"]

    # Play the motion at real speed from the start: the view follows the timeline to its end.
    page.locator("#time").press("Home")
    page.evaluate("motionStudio.idle()")
    assert page.text_content("#time-label") == "0.000 s"
    page.click("#play")
    page.wait_for_function("motionStudio.playing === false && motionStudio.metrics.playWallS !== null")
    page.evaluate("motionStudio.idle()")
    assert page.text_content("#time-label") == "1.000 s"
    play_frames = page.evaluate("motionStudio.metrics.playFrames")
    page_play_wall_s = page.evaluate("motionStudio.metrics.playWallS")
    assert play_frames >= 2  # how many depends on the machine's speed: printed below, not asserted

    # Physics preview: the simulated robot next to the kinematic one, the result and the plot.
    page.click("#preview")
    page.wait_for_function("motionStudio.state.preview.status === 'done'", timeout=60000)
    result = page.text_content("#preview-result")
    assert result.startswith(("fell at", "stayed up"))
    assert page.evaluate("motionStudio.viewer.scene_tree.find(['meshcat', 'sim']).object.visible")
    page.click("#kf-1")
    page.wait_for_function("motionStudio.state.selected === 1 && motionStudio.state.view_time_s === null")

    # Save: the file differs from the original in exactly the edited value.
    page.click("#save")
    page.wait_for_function("motionStudio.state.dirty === false")
    saved = Path(editor.path).read_text()
    expected = TEST_XML.replace('\t\t\t\t<lle3 end="45" />', '\t\t\t\t<lle3 end="45.5" />')
    assert expected != TEST_XML and saved == expected

    OUT.mkdir(exist_ok=True)
    screenshot = OUT / "editor_screenshot.png"
    page.screenshot(path=str(screenshot))
    assert screenshot.stat().st_size > 20_000

    # Closing with unsaved changes asks first (beforeunload); staying keeps the edit unsaved.
    press_slider(page, "hj2", "ArrowUp", 1)
    dialogs = []

    def stay(dialog):
        dialogs.append(dialog.type)
        dialog.dismiss()

    page.on("dialog", stay)
    page.close(run_before_unload=True)
    page.wait_for_timeout(500)
    assert dialogs == ["beforeunload"] and not page.is_closed()
    assert Path(editor.path).read_text() == expected
    assert not problems, problems
    page.close()

    figures.update(play_frames=play_frames, preview=result, screenshot=str(screenshot))
    (OUT / "editor_latency.json").write_text(json.dumps(figures, indent=1))
    with capsys.disabled():
        print(f"\n[editor] slider -> updated 3D view in headless Chromium over {figures['moves']} moves: median "
              f"{figures['median_ms']} ms, p90 {figures['p90_ms']} ms, max {figures['max_ms']} ms (server share: "
              f"median {figures['server_median_ms']} ms); play: {play_frames} frames in "
              f"{page_play_wall_s:.2f} s for 1.00 s of motion; screenshot {screenshot}")
