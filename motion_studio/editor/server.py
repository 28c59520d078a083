"""The editor's web edge: tornado serves the page and meshcat's viewer script, and one WebSocket per tab.

Loopback only: the server binds 127.0.0.1 and answers only requests whose Host (and, for the WebSocket,
Origin) is that address or ``localhost`` on its port, so other web pages cannot drive it (DNS rebinding,
cross-site WebSockets). Over the WebSocket, text frames carry JSON (requests with an ``id``, replies with the
same ``id``, events without), binary frames carry meshcat scene commands (``scene.BufferedWindow``). A reply
is sent after the scene frame its request produced, so when the page reads the reply the 3D view has the
commands already. Previews run in a worker thread; their progress and results come back on the event loop.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import json
import logging
import signal
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any
from urllib.parse import urlparse

import meshcat
import tornado.httpserver
import tornado.netutil
import tornado.web
import tornado.websocket

from motion_studio.editor.api import EditorTab, Workspace
from motion_studio.editor.scene import BufferedWindow

logger = logging.getLogger(__name__)

STATIC_DIR = Path(__file__).with_name("static")
MESHCAT_JS = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
HOST = "127.0.0.1"
#: Progress events per second at most, per preview.
PROGRESS_RATE_HZ = 10.0


class ThreadBackground:
    """Runs previews in worker threads; progress and results are handed back to the event loop."""

    def __init__(self, loop: asyncio.AbstractEventLoop, workers: int = 2) -> None:
        self.loop = loop
        self.executor = concurrent.futures.ThreadPoolExecutor(max_workers=workers, thread_name_prefix="preview")

    def submit(self, work: Callable[[Callable[[float], None]], Any], on_progress: Callable[[float], None],
               on_done: Callable[[Any, BaseException | None], None]) -> None:
        last = [0.0]

        def report(fraction: float) -> None:
            now = time.monotonic()
            if now - last[0] >= 1.0 / PROGRESS_RATE_HZ:
                last[0] = now
                self.loop.call_soon_threadsafe(on_progress, fraction)

        def run() -> None:
            try:
                result = work(report)
            except BaseException as error:  # reported to the tab by on_done
                self.loop.call_soon_threadsafe(on_done, None, error)
                return
            self.loop.call_soon_threadsafe(on_done, result, None)

        self.executor.submit(run)

    def shutdown(self) -> None:
        self.executor.shutdown(wait=False, cancel_futures=True)


def _log_request(handler: tornado.web.RequestHandler) -> None:
    """Requests at DEBUG, refusals and failures at WARNING (a page load is a dozen requests)."""
    status = handler.get_status()
    level = logging.DEBUG if status < 400 else logging.WARNING
    logger.log(level, "%d %s %s", status, handler.request.method, handler.request.uri)


def _allowed_hosts(port: int) -> set[str]:
    return {f"{HOST}:{port}", f"localhost:{port}"}


class _LoopbackHandler(tornado.web.RequestHandler):
    def initialize(self, port: int) -> None:
        self.port = port

    def prepare(self) -> None:
        if self.request.host not in _allowed_hosts(self.port):
            raise tornado.web.HTTPError(403, "host not allowed")

    def set_default_headers(self) -> None:
        self.set_header("Cache-Control", "no-store")


class FileHandler(_LoopbackHandler):
    """One fixed file: the page, its script and style, or meshcat's viewer bundle."""

    def initialize(self, port: int, path: Path, content_type: str) -> None:  # type: ignore[override]
        super().initialize(port)
        self.path = path
        self.content_type = content_type

    def get(self) -> None:
        self.set_header("Content-Type", self.content_type)
        self.write(self.path.read_bytes())


class NoIconHandler(_LoopbackHandler):
    """``/favicon.ico``: nothing (browsers ask for it; a 404 would show as an error in the console)."""

    def get(self) -> None:
        self.set_status(204)


class TabSocket(tornado.websocket.WebSocketHandler):
    """One browser tab: its EditorTab, requests in, replies, events and scene frames out."""

    def initialize(self, server: EditorServer) -> None:
        self.server = server
        self.tab: EditorTab | None = None
        self.window = BufferedWindow()

    def check_origin(self, origin: str) -> bool:
        return urlparse(origin).netloc in _allowed_hosts(self.server.port)

    def prepare(self) -> None:
        if self.request.host not in _allowed_hosts(self.server.port):
            raise tornado.web.HTTPError(403, "host not allowed")

    def open(self) -> None:  # type: ignore[override]
        # Each edit answers with two small writes (scene frame, reply): with Nagle's algorithm the second
        # waits for the client's delayed ACK, measured 40-150 ms per edit.
        self.set_nodelay(True)
        self.tab = self.server.workspace.open_tab(self.window, self._notify)
        self._send(self.tab.hello())

    def on_message(self, message: str | bytes) -> None:
        if self.tab is None:
            return
        request_id = None
        try:
            request = json.loads(message)
            request_id = request.get("id") if isinstance(request, dict) else None
            reply = self.tab.handle(request)
        except json.JSONDecodeError as error:
            reply = {"ok": False, "error": {"message": f"not JSON: {error}", "kind": "EditorError"}}
        except Exception as error:  # the server survives any request; the tab sees what happened
            logger.exception("request failed: %r", message[:200])
            reply = {"ok": False, "error": {"message": f"internal error: {error!r}", "kind": type(error).__name__}}
        reply["id"] = request_id
        self._send(reply)

    def on_close(self) -> None:
        if self.tab is not None:
            self.server.workspace.close_tab(self.tab)
            self.tab = None

    def _notify(self, event: dict[str, Any]) -> None:
        self._send(event)

    def _send(self, message: dict[str, Any]) -> None:
        """The scene commands made so far, then the JSON message (the page relies on this order)."""
        if self.ws_connection is None:
            return
        frame = self.window.flush()
        try:
            if frame is not None:
                self.write_message(frame, binary=True)
            self.write_message(json.dumps(message))
        except tornado.websocket.WebSocketClosedError:
            logger.debug("tab closed before a message could be sent")


class EditorServer:
    """The editor on 127.0.0.1.

    Args:
        path: the motion file every tab opens (need not exist yet).
        robot_type: 0-4.
        port: TCP port; 0 picks a free one.
    """

    def __init__(self, path: Path, robot_type: int = 0, port: int = 0) -> None:
        self.path = Path(path)
        self.robot_type = robot_type
        self._sockets = tornado.netutil.bind_sockets(port, HOST)
        self.port: int = self._sockets[0].getsockname()[1]
        self.workspace = Workspace(self.path, robot_type)
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._thread: threading.Thread | None = None
        self._started = threading.Event()
        self._interrupts = 0
        self.on_interrupt: Callable[[list[EditorTab]], bool] | None = None
        """Called on Ctrl-C with the tabs holding unsaved changes; return True to stop."""

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.port}/"

    def _application(self) -> tornado.web.Application:
        port = self.port
        files = [("/", STATIC_DIR / "index.html", "text/html; charset=utf-8"),
                 ("/app.js", STATIC_DIR / "app.js", "text/javascript; charset=utf-8"),
                 ("/style.css", STATIC_DIR / "style.css", "text/css; charset=utf-8"),
                 ("/meshcat.js", MESHCAT_JS, "text/javascript; charset=utf-8")]
        routes: list[Any] = [(route, FileHandler, {"port": port, "path": path, "content_type": kind})
                             for route, path, kind in files]
        routes.append(("/favicon.ico", NoIconHandler, {"port": port}))
        routes.append(("/ws", TabSocket, {"server": self}))
        return tornado.web.Application(routes, websocket_max_message_size=1 << 20, log_function=_log_request)

    async def serve(self) -> None:
        """Serve until ``stop`` is called (or Ctrl-C decides so, see ``on_interrupt``)."""
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        background = ThreadBackground(self._loop)
        self.workspace.background = background
        http = tornado.httpserver.HTTPServer(self._application())
        http.add_sockets(self._sockets)
        if threading.current_thread() is threading.main_thread():
            self._loop.add_signal_handler(signal.SIGINT, self._interrupted)
        self._started.set()
        try:
            await self._stop.wait()
        finally:
            http.stop()
            background.shutdown()
            for tab in list(self.workspace.tabs):
                self.workspace.close_tab(tab)

    def _interrupted(self) -> None:
        dirty = self.workspace.dirty_tabs()
        if self.on_interrupt is None or self.on_interrupt(dirty):
            self.stop()

    def run(self) -> None:
        """Serve on this thread until stopped."""
        asyncio.run(self.serve())

    def start_in_thread(self) -> EditorServer:
        """Serve on a daemon thread (tests, benchmarks); returns once the server accepts connections."""
        self._thread = threading.Thread(target=self.run, name="motion-editor", daemon=True)
        self._thread.start()
        if not self._started.wait(30.0):
            raise RuntimeError("editor server did not start within 30 s")
        return self

    def stop(self) -> None:
        """Stop serving (from any thread)."""
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(10.0)
