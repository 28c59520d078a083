"""The editor's request API without transport: JSON-like requests in, replies and scene commands out.

One ``EditorTab`` per browser tab: its own session (undo history, selection), scene and preview. The
``Workspace`` holds the tabs of one editor process, so a save in one tab can tell the other tabs on the same
file. ``server.py`` moves these dicts over a WebSocket; tests may call ``EditorTab.handle`` directly.

Units at this edge: angles in degrees (SimSpark sign), durations in ms, positions in m, time in s; inside,
radians and seconds (the session's units).

Request: ``{"op": NAME, ...arguments}``. Reply: ``{"ok": true, "state": {...}}`` (plus ``warning`` or
``notice`` when there is one), or ``{"ok": false, "error": {"message", "kind", "field", "path", "line"}}``
with the state unchanged. ``scrub`` replies without the full state (it runs at frame rate).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import meshcat
import numpy as np

from kinematics import SpecError, robot_spec
from kinematics.errors import IKError, ToolkitError
from motions import MotionFormatError

from motion_studio.editor.errors import EditorError
from motion_studio.editor.ik_handles import HANDLES, ORIENTED_HANDLES, HandleSolver, rotation_from_xyz_deg, \
    xyz_deg_from_rotation
from motion_studio.editor.preview_jobs import Background, InlineBackground, TabPreview
from motion_studio.editor.scene import BufferedWindow, EditorScene
from motion_studio.editor.session import EditorSession, copy_motion

logger = logging.getLogger(__name__)

Notify = Callable[[dict[str, Any]], None]
#: IK results move a joint only if they change it by more than this [rad] (0.05°): the solver's noise on the
#: joints that hold the other handles (< 0.03° measured) stays out of the file.
IK_MIN_CHANGE_RAD = math.radians(0.05)


def error_reply(error: BaseException) -> dict[str, Any]:
    """The ``error`` part of a reply: message plus where (path, line, field) and what kind."""
    info: dict[str, Any] = {"message": str(error), "kind": type(error).__name__,
                            "field": getattr(error, "field", None)}
    if isinstance(error, MotionFormatError):
        info.update(path=error.path, line=error.line)
    if isinstance(error, IKError):
        info.update(task=error.task, residual=error.residual, field="handle")
    if isinstance(error, OSError):
        info.update(path=error.filename, message=f"{error.strerror or error}: {error.filename}")
    return info


class Workspace:
    """The tabs of one editor process on a starting file.

    Args:
        path: the file every new tab opens. robot_type: 0-4.
        background: where previews run (default: inline, blocking).
    """

    def __init__(self, path: Path, robot_type: int = 0, background: Background | None = None) -> None:
        self.path = Path(path)
        self.robot_type = robot_type
        self.background = background or InlineBackground()
        self.tabs: list[EditorTab] = []
        self._solver: HandleSolver | None = None

    @property
    def solver(self) -> HandleSolver:
        """One FK/IK model for all tabs (requests run one at a time on the server's loop)."""
        if self._solver is None:
            self._solver = HandleSolver(self.robot_type)
        return self._solver

    def open_tab(self, window: BufferedWindow, notify: Notify) -> EditorTab:
        """A new tab on the workspace's file; if that file does not parse, a tab with no motion and the error."""
        tab = EditorTab(self, window, notify)
        self.tabs.append(tab)
        return tab

    def close_tab(self, tab: EditorTab) -> None:
        if tab in self.tabs:
            self.tabs.remove(tab)
            tab.preview.cancel()

    def dirty_tabs(self) -> list[EditorTab]:
        """Tabs with unsaved changes."""
        return [tab for tab in self.tabs if tab.session is not None and tab.session.dirty]

    def saved(self, path: Path, by: EditorTab) -> None:
        """Tell the other tabs on ``path`` that it was just written."""
        for tab in self.tabs:
            if tab is not by and tab.session is not None and tab.session.path is not None \
                    and _same_file(tab.session.path, path):
                tab.notify({"event": "file_saved_elsewhere", "path": str(path),
                            "message": f"{path} was saved from another tab: saving here replaces that version "
                                       "(last save wins)"})


def _same_file(a: Path, b: Path) -> bool:
    return a.resolve() == b.resolve()


class EditorTab:
    """One browser tab: session + scene + preview; ``handle`` carries out one request.

    Args:
        workspace: the process's tabs. window: where scene commands go. notify: sends an event to this tab
            (preview progress, a save elsewhere); called on the request thread.
    """

    def __init__(self, workspace: Workspace, window: BufferedWindow, notify: Notify) -> None:
        self.workspace = workspace
        self.window = window
        self.notify = notify
        self.robot_type = workspace.robot_type
        self.spec = robot_spec(self.robot_type)
        self.solver = workspace.solver
        self.scene = EditorScene(meshcat.Visualizer(window=window), self.robot_type, self.solver.painter)
        self.scene.build()
        self.preview = TabPreview(workspace.background, self.robot_type, self._preview_progress,
                                  self._preview_finished)
        self.view_time_s: float | None = None
        self.session: EditorSession | None = None
        self.open_error: dict[str, Any] | None = None
        try:
            self.session = EditorSession.open(workspace.path, self.robot_type)
        except (ToolkitError, OSError) as error:
            self.open_error = error_reply(error)
        self._paint()
        self._ops: dict[str, Callable[[dict[str, Any]], dict[str, Any] | None]] = {
            "state": lambda r: None, "select": self._select, "set_joint": self._set_joint,
            "clear_joint": self._clear_joint, "set_duration": self._set_duration, "rename": self._rename,
            "set_links": self._set_links, "add": self._add, "duplicate": self._duplicate, "delete": self._delete,
            "move": self._move, "mirror_keyframe": self._mirror_keyframe, "mirror_motion": self._mirror_motion,
            "undo": self._undo, "redo": self._redo, "scrub": self._scrub, "ik": self._ik, "save": self._save,
            "save_as": self._save_as, "open": self._open, "preview_start": self._preview_start,
            "preview_cancel": self._preview_cancel, "preview_series": self._preview_series,
        }

    # ------------------------------------------------------------------------------------- dispatch
    def hello(self) -> dict[str, Any]:
        """What a tab needs once: the joints with their limits, the handles, and the state."""
        joints = [{"wire": j.perceptor, "effector": j.effector, "nao": j.nao_name, "min_deg": j.min_deg,
                   "max_deg": j.max_deg} for j in self.spec.joints]
        return {"event": "hello", "robot_type": self.robot_type, "joints": joints, "handles": list(HANDLES),
                "oriented_handles": sorted(ORIENTED_HANDLES), "state": self.state()}

    def handle(self, request: dict[str, Any]) -> dict[str, Any]:
        """Carry out one request; never raises for bad input (the reply says what was wrong)."""
        started = time.perf_counter()
        op = request.get("op") if isinstance(request, dict) else None
        handler = self._ops.get(op) if isinstance(op, str) else None
        if handler is None:
            return {"ok": False, "error": {"message": f"unknown op {op!r}; known: {', '.join(sorted(self._ops))}",
                                           "kind": "EditorError", "field": "op"}}
        if self.session is None and op not in ("open", "state"):
            return {"ok": False, "error": {"message": "no motion is open: open a file first", "kind": "EditorError",
                                           "field": "path"}, "state": self.state()}
        try:
            extra = handler(request) or {}
        except (ToolkitError, OSError, KeyError, TypeError, ValueError) as error:
            if not isinstance(error, (ToolkitError, OSError)):
                logger.warning("bad %r request %r: %r", op, request, error)
                error = EditorError(f"bad request for {op!r}: {error!r}")
            self._paint()  # an IK failure leaves the pose as it was: put the handles back
            reply = {"ok": False, "error": error_reply(error)}
            if op != "scrub":
                reply["state"] = self.state()
            return reply
        reply = {"ok": True, **extra}
        if op != "scrub":
            reply["state"] = self.state()
            if self.session is not None and self.session.notice:
                reply.setdefault("notice", self.session.notice)
        reply["server_ms"] = round((time.perf_counter() - started) * 1000.0, 3)
        return reply

    # ------------------------------------------------------------------------------------- state
    def state(self) -> dict[str, Any]:
        """Everything the panel shows, in panel units (degrees, ms, m)."""
        session = self.session
        if session is None:
            return {"open": False, "open_error": self.open_error, "preview": self.preview.state(None)}
        times = session.keyframe_times_s()
        keyframes = []
        for keyframe, end_s in zip(session.motion.keyframes, times):
            flags = {k: v for k, v in (("skipIfFlag", keyframe.skip_if_flag), ("setFlagTrue", keyframe.set_flag_true),
                                       ("setFlagFalse", keyframe.set_flag_false), ("isFinal", keyframe.is_final))
                     if v is not None}
            keyframes.append({"name": keyframe.name, "duration_ms": round(keyframe.duration_s * 1000.0, 3),
                              "end_s": end_s, "listed": sum(t.angle_rad is not None for t in keyframe.targets.values()),
                              "next": keyframe.next, "finalize": keyframe.finalize, "flags": flags})
        index = session.selected
        pose = session.keyframe_pose(index)
        q = self.solver.vector(pose)
        balance = self.solver.balance(q)
        handles = {}
        for name, matrix in self.solver.handle_poses(q).items():
            handles[name] = {"position_m": [round(float(v), 5) for v in matrix[:3, 3]],
                             "rotation_deg": [round(v, 3) for v in xyz_deg_from_rotation(matrix[:3, :3])]}
        return {
            "open": True, "path": str(session.path) if session.path else None, "format": session.format,
            "name": session.motion.name, "dirty": session.dirty, "can_undo": session.can_undo,
            "can_redo": session.can_redo, "keyframes": keyframes, "selected": index,
            "duration_s": session.motion.duration_s,
            "pose_deg": {name: round(math.degrees(value), 4) for name, value in pose.items()},
            "listed": session.listed_joints(index), "handles": handles,
            "balance": {"com_m": [round(float(v), 5) for v in balance.com_m], "inside": balance.inside,
                        "margin_m": round(balance.margin_m, 5)},
            "view_time_s": self.view_time_s, "load_warnings": list(session.load_warnings),
            "preview": self.preview.state(session.version), "open_error": None,
        }

    # ------------------------------------------------------------------------------------- scene
    def _paint(self) -> None:
        """Show the selected keyframe (with handles), or the playback pose at ``view_time_s`` (without)."""
        session = self.session
        if session is None:
            self.scene.show_sim(None)
            return
        if self.view_time_s is None:
            pose = self.solver.vector(session.keyframe_pose(session.selected))
            handles = self.solver.handle_poses(pose)
            sim_time = session.keyframe_times_s()[session.selected]
        else:
            pose = self.solver.vector(session.pose_at(self.view_time_s))
            handles = None
            sim_time = self.view_time_s
        self.scene.show_pose(pose, handles, self.solver.balance(pose))
        result = self.preview.result
        self.scene.show_sim(result.body_poses[result.sample_index(sim_time)] if result is not None else None)

    def _keyframe_view(self) -> None:
        self.view_time_s = None
        self._paint()

    # ------------------------------------------------------------------------------------- edits
    def _session(self) -> EditorSession:
        if self.session is None:
            raise EditorError("no motion is open: open a file first", field="path")
        return self.session

    def _index(self, request: dict[str, Any]) -> int:
        session = self._session()
        index = request.get("index", session.selected)
        if isinstance(index, bool) or not isinstance(index, int):
            raise EditorError(f"index must be an integer, got {index!r}", field="index")
        return index

    @staticmethod
    def _number(request: dict[str, Any], key: str) -> float:
        value = request.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise EditorError(f"{key} must be a finite number, got {value!r}", field=key)
        return float(value)

    def _select(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.select(self._index(request))
        self._keyframe_view()

    def _set_joint(self, request: dict[str, Any]) -> dict[str, Any]:
        session = self._session()
        angle = math.radians(self._number(request, "angle_deg"))
        stored = session.set_joint(self._index(request), str(request.get("joint")), angle,
                                        merge_key=_gesture_key("joint", request))
        self._keyframe_view()
        return {"stored_deg": round(math.degrees(stored), 4)}

    def _clear_joint(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.clear_joint(self._index(request), str(request.get("joint")))
        self._keyframe_view()

    def _set_duration(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.set_duration(self._index(request), self._number(request, "duration_ms") / 1000.0,
                                  merge_key=_gesture_key("duration", request))
        self._keyframe_view()

    def _rename(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.rename(self._index(request), str(request.get("name", "")))

    def _set_links(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.set_links(self._index(request), request.get("next") or None, request.get("finalize") or None)

    def _add(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.add_keyframe(self._index(request))
        self._keyframe_view()

    def _duplicate(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.duplicate_keyframe(self._index(request))
        self._keyframe_view()

    def _delete(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.delete_keyframe(self._index(request))
        self._keyframe_view()

    def _move(self, request: dict[str, Any]) -> None:
        session = self._session()
        to = request.get("to")
        if isinstance(to, bool) or not isinstance(to, int):
            raise EditorError(f"to must be an integer index, got {to!r}", field="to")
        session.move_keyframe(self._index(request), to)
        self._keyframe_view()

    def _mirror_keyframe(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.mirror_keyframe(self._index(request))
        self._keyframe_view()

    def _mirror_motion(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.mirror_motion()
        self._keyframe_view()

    def _undo(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.undo()
        self._keyframe_view()

    def _redo(self, request: dict[str, Any]) -> None:
        session = self._session()
        session.redo()
        self._keyframe_view()

    def _scrub(self, request: dict[str, Any]) -> dict[str, Any]:
        t_s = self._number(request, "t_s")
        self.view_time_s = max(0.0, t_s)
        self._paint()
        result = self.preview.result
        return {"t_s": self.view_time_s,
                "sim_index": result.sample_index(self.view_time_s) if result is not None else None}

    def _ik(self, request: dict[str, Any]) -> dict[str, Any]:
        session = self._session()
        handle = request.get("handle")
        if handle not in HANDLES:
            raise SpecError(f"unknown IK handle {handle!r}; known: {', '.join(HANDLES)}", field="handle")
        position = request.get("position_m")
        if position is not None and (not isinstance(position, list) or len(position) != 3):
            raise EditorError(f"position_m must be [x, y, z] in m, got {position!r}", field="position_m")
        rotation_deg = request.get("rotation_deg")
        if rotation_deg is not None and (not isinstance(rotation_deg, list) or len(rotation_deg) != 3):
            raise EditorError(f"rotation_deg must be [about x, about y, about z] in deg, got {rotation_deg!r}",
                              field="rotation_deg")
        index = self._index(request)
        pose = session.keyframe_pose(index)
        rotation = None if rotation_deg is None else rotation_from_xyz_deg(tuple(float(v) for v in rotation_deg))
        solved = self.solver.solve(pose, str(handle), None if position is None else np.array(position, dtype=float),
                                   rotation, keep_com=bool(request.get("keep_com", False)))
        changed = session.set_pose(index, solved, merge_key=_gesture_key("ik", request),
                                   min_change_rad=IK_MIN_CHANGE_RAD)
        self._keyframe_view()
        return {"changed": changed}

    # ------------------------------------------------------------------------------------- files
    def _save(self, request: dict[str, Any]) -> dict[str, Any]:
        session = self._session()
        warning = session.save()
        self.workspace.saved(session.path, self)
        return {"saved": str(session.path), **({"warning": warning} if warning else {})}

    def _save_as(self, request: dict[str, Any]) -> dict[str, Any]:
        session = self._session()
        path = request.get("path")
        if not isinstance(path, str) or not path.strip():
            raise EditorError("save as needs a file path", field="path")
        format = request.get("format") or None
        warning = session.save_as(self._resolve(path), format, lossy=bool(request.get("lossy", False)),
                                       overwrite=bool(request.get("overwrite", False)))
        self.workspace.saved(session.path, self)
        self._keyframe_view()
        return {"saved": str(session.path), **({"warning": warning} if warning else {})}

    def _open(self, request: dict[str, Any]) -> None:
        path = request.get("path")
        if not isinstance(path, str) or not path.strip():
            raise EditorError("open needs a file path", field="path")
        session = EditorSession.open(self._resolve(path), self.robot_type)  # a parse error opens nothing
        self.session, self.open_error = session, None
        self.preview.reset()
        self._keyframe_view()

    def _resolve(self, text: str) -> Path:
        """A path typed in the panel: absolute, or relative to the folder of the workspace's file."""
        path = Path(text.strip()).expanduser()
        return path if path.is_absolute() else self.workspace.path.parent / path

    # ------------------------------------------------------------------------------------- preview
    def _preview_start(self, request: dict[str, Any]) -> None:
        session = self._session()
        self.preview.start(copy_motion(session.motion), session.version)

    def _preview_progress(self, fraction: float) -> None:
        self.notify({"event": "preview_progress", "fraction": round(fraction, 3)})

    def _preview_finished(self) -> None:
        self._paint()
        event: dict[str, Any] = {"event": "preview_done", "state": self.state()}
        if self.preview.result is not None:
            event["series"] = self.preview.series()
        self.notify(event)

    def _preview_cancel(self, request: dict[str, Any]) -> None:
        self.preview.cancel()

    def _preview_series(self, request: dict[str, Any]) -> dict[str, Any]:
        return {"series": self.preview.series()}


def _gesture_key(kind: str, request: dict[str, Any]) -> str | None:
    """Undo merge key: edits of one gesture (one slider drag, one handle drag) share the client's gesture id."""
    gesture = request.get("gesture")
    if gesture is None:
        return None
    return f"{kind}:{request.get('index')}:{request.get('joint', request.get('handle', ''))}:{gesture}"
