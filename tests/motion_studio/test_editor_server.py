"""The editor's web edge over real sockets: WebSocket API, scene frames, errors, conflicts, loopback, the CLI."""

import asyncio
import json
import signal
import struct
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pytest
import tornado.httpclient
import tornado.websocket
import umsgpack

from motion_studio.editor.server import EditorServer
from tests.motion_studio.test_editor_session import TEST_XML

CLI = [sys.executable, "-m", "motion_studio"]


def scene_commands(frame: bytes) -> list[dict]:
    """Split a scene frame (4-byte length + msgpack command, repeated) into meshcat commands."""
    commands, offset = [], 0
    while offset < len(frame):
        (length,) = struct.unpack_from(">I", frame, offset)
        commands.append(umsgpack.unpackb(frame[offset + 4:offset + 4 + length]))
        offset += 4 + length
    return commands


class Tab:
    """A scripted browser tab: JSON requests with ids, scene frames and events kept in arrival order."""

    def __init__(self, connection: tornado.websocket.WebSocketClientConnection) -> None:
        self.connection = connection
        self.received: list[object] = []   # bytes (scene frames) and dicts, in order
        self.next_id = 1

    @classmethod
    async def open(cls, server: EditorServer, **headers: str) -> "Tab":
        request = tornado.httpclient.HTTPRequest(f"ws://127.0.0.1:{server.port}/ws", headers=headers)
        tab = cls(await tornado.websocket.websocket_connect(request))
        await tab.wait_for(lambda m: isinstance(m, dict) and m.get("event") == "hello")
        return tab

    async def _read(self) -> object:
        message = await asyncio.wait_for(self.connection.read_message(), 30)
        if message is None:
            raise ConnectionError("server closed the connection")
        item = message if isinstance(message, bytes) else json.loads(message)
        self.received.append(item)
        return item

    async def wait_for(self, predicate) -> dict:
        for item in self.received:
            if predicate(item):
                self.received.remove(item)
                return item
        while True:
            item = await self._read()
            if predicate(item):
                self.received.remove(item)
                return item

    async def request(self, op: str, **args) -> dict:
        request_id = self.next_id
        self.next_id += 1
        self.received.clear()
        await self.connection.write_message(json.dumps({"id": request_id, "op": op, **args}))
        return await self.wait_for(lambda m: isinstance(m, dict) and m.get("id") == request_id)

    def frames_before_last_reply(self) -> list[bytes]:
        return [item for item in self.received if isinstance(item, bytes)]

    def close(self) -> None:
        self.connection.close()


@pytest.fixture
def motion_file(tmp_path: Path) -> Path:
    path = tmp_path / "editor_test.xml"
    path.write_text(TEST_XML)
    return path


@pytest.fixture
def server(motion_file):
    editor = EditorServer(motion_file).start_in_thread()
    yield editor
    editor.stop()


def run(coroutine):
    return asyncio.run(coroutine)


def test_a_tab_gets_the_scene_then_hello_and_an_edit_updates_the_scene_before_its_reply(server):
    async def scenario():
        request = tornado.httpclient.HTTPRequest(f"ws://127.0.0.1:{server.port}/ws")
        connection = await tornado.websocket.websocket_connect(request)
        first, second = await connection.read_message(), await connection.read_message()
        assert isinstance(first, bytes)  # the scene is built before the panel is told about it
        built = scene_commands(first)
        objects = {c["path"] for c in built if c["type"] == "set_object"}
        assert {"/meshcat/nao/torso/shape", "/meshcat/sim/lthigh/shape", "/meshcat/handles/lfoot",
                "/meshcat/com/ball", "/meshcat/support/0"} <= objects
        hello = json.loads(second)
        assert hello["event"] == "hello" and len(hello["joints"]) == 22
        assert hello["state"]["keyframes"][1]["name"] == "lift" and hello["state"]["dirty"] is False
        tab = Tab(connection)
        reply = await tab.request("set_joint", index=1, joint="llj3", angle_deg=47.5, gesture=1)
        assert reply["ok"] and reply["stored_deg"] == 47.5
        assert reply["state"]["pose_deg"]["llj3"] == 47.5 and reply["state"]["dirty"]
        frames = tab.frames_before_last_reply()
        assert len(frames) == 1  # one frame per edit, sent before the reply
        moved = {c["path"]: c for c in scene_commands(frames[0]) if c["type"] == "set_transform"}
        assert "/meshcat/nao/lthigh" in moved and "/meshcat/handles/lfoot" in moved
        assert len(moved["/meshcat/nao/lthigh"]["matrix"]) == 16
        tab.close()

    run(scenario())


def test_opening_a_file_that_does_not_parse_returns_the_error_with_its_line(server, tmp_path):
    broken = tmp_path / "broken.xml"
    broken.write_text(TEST_XML.replace('<lle4 end="-90" />', '<lle4 end="-9O" />'))

    async def scenario():
        tab = await Tab.open(server)
        reply = await tab.request("open", path=str(broken))
        assert not reply["ok"]
        error = reply["error"]
        assert error["kind"] == "MotionFormatError" and error["line"] == 24 and error["field"] == "end"
        assert error["path"] == str(broken) and "-9O" in error["message"]
        assert reply["state"]["path"] == str(server.path)  # nothing opened: the old motion stays
        missing = await tab.request("open", path=str(tmp_path / "nowhere" / "x.xml"))
        assert not missing["ok"] and missing["error"]["field"] == "path"
        tab.close()

    run(scenario())


def test_a_server_whose_file_broke_shows_the_error_and_can_open_another(motion_file, tmp_path):
    motion_file.write_text(TEST_XML.replace("<duration>300</duration>", "<duration>-3</duration>", 1))
    editor = EditorServer(motion_file).start_in_thread()
    good = tmp_path / "good.xml"
    good.write_text(TEST_XML)

    async def scenario():
        request = tornado.httpclient.HTTPRequest(f"ws://127.0.0.1:{editor.port}/ws")
        tab = Tab(await tornado.websocket.websocket_connect(request))
        hello = await tab.wait_for(lambda m: isinstance(m, dict) and m.get("event") == "hello")
        assert hello["state"]["open"] is False
        assert hello["state"]["open_error"]["line"] == 26 and hello["state"]["open_error"]["field"] == "duration"
        refused = await tab.request("set_joint", index=0, joint="llj3", angle_deg=10)
        assert not refused["ok"] and "no motion is open" in refused["error"]["message"]
        opened = await tab.request("open", path="good.xml")  # relative to the first file's folder
        assert opened["ok"] and opened["state"]["path"] == str(good)
        tab.close()

    try:
        run(scenario())
    finally:
        editor.stop()


def test_two_tabs_on_one_file_last_save_wins_with_a_warning(server, motion_file):
    async def scenario():
        first, second = await Tab.open(server), await Tab.open(server)
        assert (await first.request("set_joint", index=0, joint="llj3", angle_deg=20))["ok"]
        assert (await second.request("set_joint", index=0, joint="rlj3", angle_deg=25))["ok"]
        saved = await first.request("save")
        assert saved["ok"] and "warning" not in saved and saved["state"]["dirty"] is False
        told = await second.wait_for(lambda m: isinstance(m, dict) and m.get("event") == "file_saved_elsewhere")
        assert "last save wins" in told["message"]
        assert '<lle3 end="20" />' in motion_file.read_text()
        saved_again = await second.request("save")
        assert saved_again["ok"] and "changed on disk" in saved_again["warning"]
        text = motion_file.read_text()
        assert '<rle3 end="25" />' in text and '<lle3 end="30" />' in text  # the second tab's version, whole
        assert text == TEST_XML.replace('<rle3 end="30" />', '<rle3 end="25" />')
        first.close()
        second.close()

    run(scenario())


def test_ik_over_the_socket_and_an_unreachable_target_keeps_the_pose(server):
    async def scenario():
        tab = await Tab.open(server)
        state = (await tab.request("select", index=0))["state"]
        hand = state["handles"]["lhand"]["position_m"]
        reply = await tab.request("ik", index=0, handle="lhand", position_m=[hand[0], hand[1], hand[2] + 1.0])
        assert not reply["ok"] and reply["error"]["kind"] == "IKError"
        assert reply["state"]["pose_deg"] == state["pose_deg"] and not reply["state"]["dirty"]
        moved = await tab.request("ik", index=0, handle="lhand", position_m=[hand[0], hand[1] - 0.03, hand[2] + 0.03])
        assert moved["ok"] and set(moved["changed"]) <= {"laj1", "laj2", "laj3", "laj4"} and moved["changed"]
        tab.close()

    run(scenario())


def test_physics_preview_sends_progress_then_the_result(server):
    async def scenario():
        tab = await Tab.open(server)
        started = await tab.request("preview_start")
        assert started["ok"] and started["state"]["preview"]["status"] == "running"
        done = await tab.wait_for(lambda m: isinstance(m, dict) and m.get("event") == "preview_done")
        summary = done["state"]["preview"]["summary"]
        assert done["state"]["preview"]["status"] == "done" and isinstance(summary["fell"], bool)
        series = done["series"]
        assert series["t_s"][0] >= 0 and series["t_s"][-1] >= 1.0  # the motion lasts 1 s, then 1 s of holding
        assert len(series["t_s"]) == len(series["torso_height_m"]) == len(series["com_z_m"])
        assert 0.2 < series["torso_height_m"][0] < 0.4
        scrub = await tab.request("scrub", t_s=0.5)
        assert scrub["ok"] and scrub["sim_index"] is not None
        frames = tab.frames_before_last_reply()
        moved = {c["path"] for c in scene_commands(frames[0]) if c["type"] == "set_transform"}
        assert "/meshcat/sim/torso" in moved and "/meshcat/nao/torso" in moved
        edited = await tab.request("set_joint", index=0, joint="hj1", angle_deg=10)
        assert edited["state"]["preview"]["stale"] is True
        tab.close()

    run(scenario())


def test_only_loopback_hosts_and_origins_are_served(server):
    page = urllib.request.urlopen(server.url, timeout=10).read().decode()
    assert "<title>motion-studio editor</title>" in page and '/meshcat.js' in page
    assert urllib.request.urlopen(f"{server.url}meshcat.js", timeout=10).read(30).startswith(b"/*!")
    foreign = urllib.request.Request(server.url, headers={"Host": f"attacker.example:{server.port}"})
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(foreign, timeout=10)
    assert refused.value.code == 403

    async def cross_site():
        with pytest.raises(tornado.httpclient.HTTPClientError) as caught:
            await Tab.open(server, Origin="http://attacker.example")
        return caught.value

    error = run(cross_site())
    assert "403" in str(error)
    assert server._sockets[0].getsockname()[0] == "127.0.0.1"


# ------------------------------------------------------------------------------------------------ CLI
def test_cli_refuses_a_file_that_does_not_parse_and_opens_nothing(tmp_path):
    broken = tmp_path / "broken.xml"
    broken.write_text(TEST_XML.replace('<lle4 end="-90" />', '<lle4 end="-9O" />'))
    result = subprocess.run(CLI + ["edit", str(broken), "--no-browser"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert f"{broken}:24" in result.stderr and "'end'" in result.stderr
    assert "http://" not in result.stdout


def test_cli_serves_on_loopback_and_warns_before_quitting_with_unsaved_changes(motion_file):
    process = subprocess.Popen(CLI + ["edit", str(motion_file), "--no-browser"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        line = process.stdout.readline()
        assert "http://127.0.0.1:" in line, line + process.stderr.read()
        url = line.split("http://", 1)[1].split()[0]
        port = int(url.split(":")[1].rstrip("/"))
        page = urllib.request.urlopen(f"http://{url}", timeout=10).read().decode()
        assert "<title>motion-studio editor</title>" in page

        async def edit_and_interrupt():
            editor = type("S", (), {"port": port})
            tab = await Tab.open(editor)
            assert (await tab.request("set_joint", index=0, joint="llj3", angle_deg=31))["ok"]
            process.send_signal(signal.SIGINT)
            await asyncio.sleep(1.0)
            assert process.poll() is None  # still serving: the unsaved tab was warned about
            process.send_signal(signal.SIGINT)
            tab.close()

        run(edit_and_interrupt())
        assert process.wait(timeout=30) == 0
        assert "unsaved changes" in process.stderr.read()
        assert motion_file.read_text() == TEST_XML  # nothing was saved behind the user's back
    finally:
        if process.poll() is None:
            process.kill()
