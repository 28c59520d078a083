"""Editor figures without a browser: time per request of the editor's API and of the physics preview.

Figures only (``motion-studio bench editor`` and ``benchmarks/bench_editor.py`` print them), never pass/fail.
The browser part (slider -> 3D view in headless Chromium) is ``browser.bench_slider_latency``.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from agent.protocol.constants import CYCLE_S

#: The benchmark's motion: a two-phase crouch written by hand (no file of motions/ is needed).
BENCH_MOTION = """<?xml version="1.0" encoding="UTF-8"?>
<!-- motion-studio bench editor: a two-phase crouch written by hand for the benchmark -->
<robot>
\t<low_skills>
\t\t<low_skill name="bench_crouch" firstPhase="down" />
\t</low_skills>

\t<phases>
\t\t<phase name="down" next="up">
\t\t\t<effectors>
\t\t\t\t<lle3 end="30" />
\t\t\t\t<lle4 end="-60" />
\t\t\t\t<lle5 end="30" />
\t\t\t\t<rle3 end="30" />
\t\t\t\t<rle4 end="-60" />
\t\t\t\t<rle5 end="30" />
\t\t\t</effectors>
\t\t\t<duration>500</duration>
\t\t</phase>
\t\t<phase name="up">
\t\t\t<effectors>
\t\t\t\t<lle3 end="0" />
\t\t\t\t<lle4 end="0" />
\t\t\t\t<lle5 end="0" />
\t\t\t\t<rle3 end="0" />
\t\t\t\t<rle4 end="0" />
\t\t\t\t<rle5 end="0" />
\t\t\t</effectors>
\t\t\t<duration>500</duration>
\t\t</phase>
\t</phases>
</robot>
"""


def write_bench_motion(folder: Path) -> Path:
    """The benchmark motion as a file in ``folder``."""
    path = Path(folder) / "bench_crouch.xml"
    path.write_text(BENCH_MOTION)
    return path


def _median_ms(samples_s: list[float]) -> float:
    return round(statistics.median(samples_s) * 1000.0, 3)


def bench_requests(motion_path: Path | None = None, repeats: int = 50, robot_type: int = 0) -> dict[str, Any]:
    """Median time per request inside the editor (no sockets): slider edit, scrub, IK drag step, preview.

    Returns:
        ``set_joint_ms``, ``scrub_ms``, ``ik_ms`` (medians, each including the scene commands it makes),
        ``scene_bytes_per_edit``, ``preview_wall_s`` and ``preview_realtime_factor`` (simulated / wall time).
    """
    from motion_studio.editor.api import Workspace
    from motion_studio.editor.scene import BufferedWindow

    with tempfile.TemporaryDirectory(prefix="motion-studio-bench-") as folder:
        path = Path(motion_path) if motion_path is not None else write_bench_motion(Path(folder))
        window = BufferedWindow()
        tab = Workspace(path, robot_type).open_tab(window, lambda event: None)
        window.flush()
        timings: dict[str, list[float]] = {"set_joint": [], "scrub": [], "ik": []}
        frame_bytes = []
        foot = tab.handle({"op": "select", "index": 0})["state"]["handles"]["lfoot"]["position_m"]
        for i in range(repeats):
            requests = {
                "set_joint": {"op": "set_joint", "index": 0, "joint": "hj1", "angle_deg": (i % 20) - 10.0,
                              "gesture": 1},
                "scrub": {"op": "scrub", "t_s": (i % 50) / 50.0 * tab.session.motion.duration_s},
                "ik": {"op": "ik", "index": 0, "handle": "lfoot", "gesture": 2,
                       "position_m": [foot[0], foot[1], foot[2] + 0.0004 * (i % 25)]},
            }
            for name, request in requests.items():
                started = time.perf_counter()
                reply = tab.handle(request)
                frame = window.flush()
                timings[name].append(time.perf_counter() - started)
                if not reply["ok"]:
                    raise RuntimeError(f"benchmark request {request} failed: {reply['error']['message']}")
                if name == "set_joint" and frame is not None:
                    frame_bytes.append(len(frame))
        started = time.perf_counter()
        tab.handle({"op": "preview_start"})
        preview_wall_s = time.perf_counter() - started
        result = tab.preview.result
        simulated_s = result.cycles * CYCLE_S if result is not None else float("nan")
    return {"set_joint_ms": _median_ms(timings["set_joint"]), "scrub_ms": _median_ms(timings["scrub"]),
            "ik_ms": _median_ms(timings["ik"]), "scene_bytes_per_edit": int(statistics.median(frame_bytes)),
            "preview_wall_s": round(preview_wall_s, 3),
            "preview_realtime_factor": round(simulated_s / preview_wall_s, 1), "repeats": repeats}
