"""Driving the editor in Debian's headless Chromium with Playwright: the launch recipe and the latency bench.

Never downloads a browser: Playwright is pointed at the system Chromium (``scripts/setup_browser.sh``
installs it), with a fresh profile per run and no network features (sync, updates, QUIC, first-run pages).
"""

from __future__ import annotations

import contextlib
import shutil
import statistics
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

CHROMIUM_ARGS: tuple[str, ...] = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                                  "--disable-background-networking", "--disable-component-update", "--disable-sync")
VIEWPORT = {"width": 1400, "height": 860}


def chromium_path() -> str | None:
    """The system Chromium's executable, None if it is not installed."""
    for candidate in ("/usr/bin/chromium", shutil.which("chromium"), shutil.which("chromium-browser")):
        if candidate and Path(candidate).exists():
            return candidate
    return None


def chromium_version() -> str:
    """``Chromium 156.0.8078.79`` (the package's own answer; the user agent hides the minor numbers)."""
    executable = chromium_path()
    if executable is None:
        return "Chromium (not installed)"
    try:
        output = subprocess.run([executable, "--version"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.TimeoutExpired):
        return "Chromium (version unknown)"
    return " ".join(output.split()[:2]) or "Chromium (version unknown)"


def browser_unavailable_reason() -> str | None:
    """Why the browser tests cannot run here (None if they can)."""
    try:
        import playwright.sync_api  # noqa: F401  (dev extra)
    except ImportError:
        return "the playwright package is not installed (pip install -e '.[dev]')"
    if chromium_path() is None:
        return "Chromium is not installed (scripts/setup_browser.sh installs Debian's package; needs root and apt)"
    return None


@contextlib.contextmanager
def headless_chromium() -> Iterator[Any]:
    """A Playwright browser context on the system Chromium with a fresh, temporary user-data dir."""
    from playwright.sync_api import sync_playwright

    executable = chromium_path()
    if executable is None:
        raise RuntimeError(browser_unavailable_reason() or "Chromium not found")
    with tempfile.TemporaryDirectory(prefix="motion-studio-chromium-") as profile, sync_playwright() as playwright:
        context = playwright.chromium.launch_persistent_context(
            profile, executable_path=executable, headless=True, args=list(CHROMIUM_ARGS), viewport=VIEWPORT)
        try:
            yield context
        finally:
            context.close()


def open_editor(context: Any, url: str) -> Any:
    """A new page on the editor, once its WebSocket handshake and first scene are done."""
    page = context.new_page()
    page.goto(url)
    page.wait_for_function("window.motionStudio && window.motionStudio.ready !== null")
    page.evaluate("window.motionStudio.ready")
    page.wait_for_function("window.motionStudio.state && window.motionStudio.state.open !== undefined")
    page.evaluate("window.motionStudio.metrics.syncGpu = true")  # time to the pixels, not to the draw calls
    return page


def press_slider(page: Any, joint: str, key: str = "ArrowRight", times: int = 1) -> list[float]:
    """Move a joint slider with the keyboard, one step per press, waiting for each view update.

    Returns:
        The slider-to-view latency of each press [ms], as the page measured it: from the input event to the
        frame that shows the new pose, its pixels finished (``open_editor`` sets ``syncGpu``).
    """
    slider = page.locator(f"#slider-{joint}")
    slider.focus()
    latencies = []
    for _ in range(times):
        before = page.evaluate("window.motionStudio.metrics.sliderLatenciesMs.length")
        slider.press(key)
        page.wait_for_function(f"window.motionStudio.metrics.sliderLatenciesMs.length > {before}")
        page.evaluate("window.motionStudio.idle()")
        latencies.append(page.evaluate("window.motionStudio.metrics.sliderLatenciesMs.at(-1)"))
    return latencies


def latency_figures(latencies_ms: list[float], server_ms: list[float],
                    reply_ms: list[float] | None = None) -> dict[str, float | int]:
    """Median, 90th percentile, min and max of the latencies; medians of the server's share and of the time
    to the reply (before the frame is drawn) [ms]."""
    ordered = sorted(latencies_ms)
    p90 = ordered[min(len(ordered) - 1, int(round(0.9 * (len(ordered) - 1))))]
    figures: dict[str, float | int] = {
        "moves": len(ordered), "median_ms": round(statistics.median(ordered), 2), "p90_ms": round(p90, 2),
        "min_ms": round(ordered[0], 2), "max_ms": round(ordered[-1], 2),
        "server_median_ms": round(statistics.median(server_ms), 3) if server_ms else float("nan")}
    if reply_ms:
        figures["reply_median_ms"] = round(statistics.median(reply_ms), 2)
    return figures


def bench_slider_latency(motion_path: Path, joint: str = "llj3", moves: int = 40, robot_type: int = 0,
                         screenshot: Path | None = None) -> dict[str, Any]:
    """Open the editor on a copy of ``motion_path`` in headless Chromium and time ``moves`` slider steps.

    Args:
        motion_path: any motion file (copied to a temporary folder: the original is never written).
        joint: the slider moved (wire name). moves: key presses (half right, half back left).
        robot_type: 0-4. screenshot: write a PNG of the page here at the end, if given.

    Returns:
        Latency figures (see ``latency_figures``) plus the motion and browser versions.
    """
    from motion_studio.editor.server import EditorServer

    with tempfile.TemporaryDirectory(prefix="motion-studio-bench-") as folder:
        copy = Path(folder) / Path(motion_path).name
        shutil.copyfile(motion_path, copy)
        server = EditorServer(copy, robot_type).start_in_thread()
        try:
            with headless_chromium() as context:
                page = open_editor(context, server.url)
                press_slider(page, joint, "ArrowRight", 3)  # warm-up: first frames compile shaders
                page.evaluate("const m = window.motionStudio.metrics; m.sliderLatenciesMs.length = 0;"
                              "m.serverMs.length = 0; m.replyMs.length = 0")
                latencies = press_slider(page, joint, "ArrowRight", moves // 2)
                latencies += press_slider(page, joint, "ArrowLeft", moves - moves // 2)
                server_ms = page.evaluate("window.motionStudio.metrics.serverMs")
                reply_ms = page.evaluate("window.motionStudio.metrics.replyMs")
                renderer = page.evaluate("""() => { const gl = window.motionStudio.viewer.renderer.getContext();
                    const info = gl.getExtension('WEBGL_debug_renderer_info');
                    return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : 'unknown'; }""")
                if screenshot is not None:
                    screenshot.parent.mkdir(parents=True, exist_ok=True)
                    page.screenshot(path=str(screenshot))
        finally:
            server.stop()
    figures: dict[str, Any] = dict(latency_figures(latencies, server_ms, reply_ms))
    figures.update(motion=str(motion_path), joint=joint, browser=f"{chromium_version()} (headless, --disable-gpu)",
                   webgl=renderer)
    return figures
