// motion-studio editor page: the panel, the meshcat view, the timeline and the preview plot.
// Talks to the server over one WebSocket: JSON requests/replies/events (text), meshcat commands (binary).
"use strict";

const $ = (id) => document.getElementById(id);

const GROUPS = [
  ["Head", /^hj/], ["Left arm", /^laj/], ["Left leg", /^llj/], ["Right leg", /^rlj/], ["Right arm", /^raj/],
];

const app = {
  ws: null,
  nextId: 1,
  pending: new Map(),        // request id -> {resolve, op, sentAt}
  joints: [],                // [{wire, effector, nao, min_deg, max_deg}]
  handles: [],
  orientedHandles: [],
  state: null,
  series: null,
  viewer: null,
  gesture: 0,
  playing: false,
  timeInFlight: false,
  pendingTime: null,
  jointQueue: new Map(),     // wire -> {value, t0} waiting for the request in flight
  jointInFlight: new Set(),
  drag: null,
  keyframesKey: "",
};

// What tests and benchmarks read: slider-to-view latencies and the server's share of them.
window.motionStudio = {
  // syncGpu: wait for the GPU to finish the frame (1-pixel readPixels) before taking the time, so the
  // latency covers the pixels, not only the draw calls; set by benchmarks and tests, off for users.
  metrics: { sliderLatenciesMs: [], replyMs: [], serverMs: [], syncGpu: false, playFrames: 0, playWallS: null },
  get state() { return app.state; },
  get viewer() { return app.viewer; },
  get playing() { return app.playing; },
  ready: null,
  idle: () => waitIdle(),
};

// ------------------------------------------------------------------------------------------ transport
function connect() {
  return new Promise((resolve) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.binaryType = "arraybuffer";
    app.ws = ws;
    ws.onmessage = (message) => {
      if (typeof message.data === "string") onJson(JSON.parse(message.data), resolve);
      else applySceneFrame(message.data);
    };
    ws.onclose = () => {
      showMessage("error", "Connection to the editor server lost. Restart `motion-studio edit` and reload.");
      for (const { resolve: r } of app.pending.values()) r({ ok: false, error: { message: "disconnected" } });
      app.pending.clear();
    };
  });
}

// A scene frame: repeated (uint32 big-endian length, msgpack command), applied in order.
function applySceneFrame(buffer) {
  const view = new DataView(buffer);
  let offset = 0;
  while (offset + 4 <= buffer.byteLength) {
    const length = view.getUint32(offset);
    offset += 4;
    app.viewer.handle_command_bytearray(new Uint8Array(buffer.slice(offset, offset + length)));
    offset += length;
  }
}

function onJson(message, onHello) {
  if (message.id !== undefined && message.id !== null && app.pending.has(message.id)) {
    const entry = app.pending.get(message.id);
    app.pending.delete(message.id);
    entry.resolve(message);
    return;
  }
  switch (message.event) {
    case "hello":
      app.joints = message.joints;
      app.handles = message.handles;
      app.orientedHandles = message.oriented_handles;
      buildJointRows();
      buildHandleSelect();
      render(message.state);
      onHello();
      break;
    case "preview_progress":
      $("preview-progress").hidden = false;
      $("preview-progress").value = message.fraction;
      break;
    case "preview_done":
      if (message.series) app.series = message.series;
      render(message.state);
      drawPlot();
      break;
    case "file_saved_elsewhere":
      showMessage("warning", message.message);
      break;
    default:
      if (message.id !== undefined) break;  // a reply nobody waits for
      console.warn("unknown message", message);
  }
}

// quiet: the caller shows errors itself (IK drags report in the IK section, not in the message list).
function request(op, args = {}, quiet = false) {
  const id = app.nextId++;
  return new Promise((resolve) => {
    app.pending.set(id, { resolve, op, sentAt: performance.now() });
    app.ws.send(JSON.stringify({ id, op, ...args }));
  }).then((reply) => {
    if (reply.state) render(reply.state);
    if (!reply.ok && reply.error && !quiet) showError(reply.error, op);
    if (reply.warning) showMessage("warning", reply.warning);
    if (reply.notice) showMessage("notice", reply.notice);
    return reply;
  });
}

function waitIdle() {
  return new Promise((resolve) => {
    const check = () => {
      if (app.pending.size === 0 && app.jointQueue.size === 0 && !app.playing && !app.timeInFlight &&
          app.pendingTime === null) resolve();
      else setTimeout(check, 10);
    };
    check();
  });
}

// ------------------------------------------------------------------------------------------ messages
function showMessage(kind, text) {
  const box = document.createElement("div");
  box.className = `msg ${kind}`;
  const close = document.createElement("button");
  close.textContent = "×";
  close.title = "dismiss";
  close.onclick = () => box.remove();
  box.append(close, document.createTextNode(text));
  $("messages").prepend(box);
  while ($("messages").children.length > 6) $("messages").lastChild.remove();
}

function showError(error, op) {
  let where = "";
  if (error.path) where = error.line ? `${error.path}, line ${error.line}: ` : `${error.path}: `;
  showMessage("error", `${op ? op + ": " : ""}${where}${error.message}`);
}

// ------------------------------------------------------------------------------------------ panel
function buildJointRows() {
  const list = $("joint-list");
  list.textContent = "";
  for (const [title, pattern] of GROUPS) {
    const joints = app.joints.filter((j) => pattern.test(j.wire));
    if (!joints.length) continue;
    const heading = document.createElement("div");
    heading.className = "joint-group";
    heading.textContent = title;
    list.append(heading);
    for (const joint of joints) list.append(jointRow(joint));
  }
}

function jointRow(joint) {
  const row = document.createElement("div");
  row.className = "joint-row";
  row.id = `row-${joint.wire}`;
  const label = document.createElement("label");
  label.textContent = `${joint.wire} ${joint.nao}`;
  label.title = `${joint.nao} (${joint.effector}), ${joint.min_deg}…${joint.max_deg}°`;
  label.htmlFor = `slider-${joint.wire}`;
  const slider = document.createElement("input");
  Object.assign(slider, { type: "range", id: `slider-${joint.wire}`, min: joint.min_deg, max: joint.max_deg,
                          step: 0.1 });
  slider.dataset.joint = joint.wire;
  const number = document.createElement("input");
  Object.assign(number, { type: "number", id: `number-${joint.wire}`, min: joint.min_deg, max: joint.max_deg,
                          step: 0.1 });
  const clear = document.createElement("button");
  clear.textContent = "×";
  clear.id = `clear-${joint.wire}`;
  clear.title = "stop commanding this joint in this keyframe (XML: hold; Webots: *)";
  const newGesture = () => { app.gesture += 1; };
  slider.addEventListener("pointerdown", newGesture);
  slider.addEventListener("keydown", newGesture);
  slider.addEventListener("input", (event) => {
    number.value = slider.value;
    queueJoint(joint.wire, parseFloat(slider.value), event.timeStamp);
  });
  number.addEventListener("change", (event) => {
    newGesture();
    const value = Math.min(joint.max_deg, Math.max(joint.min_deg, parseFloat(number.value)));
    if (Number.isFinite(value)) queueJoint(joint.wire, value, event.timeStamp);
  });
  clear.addEventListener("click", () => request("clear_joint", { index: app.state.selected, joint: joint.wire }));
  row.append(label, slider, number, clear);
  return row;
}

// One request per joint in flight; a newer value waits and replaces older waiting ones (a drag).
function queueJoint(wire, value, t0) {
  if (app.jointInFlight.has(wire)) {
    app.jointQueue.set(wire, { value, t0 });
    return;
  }
  sendJoint(wire, value, t0);
}

function sendJoint(wire, value, t0) {
  app.jointInFlight.add(wire);
  const index = app.state.selected;
  request("set_joint", { index, joint: wire, angle_deg: value, gesture: app.gesture }).then((reply) => {
    app.jointInFlight.delete(wire);
    if (reply.ok) {
      const metrics = window.motionStudio.metrics;
      metrics.replyMs.push(performance.now() - t0);
      metrics.serverMs.push(reply.server_ms);
      // The reply comes after its scene frame: in the next animation frame the viewer draws the new pose
      // (its own frame callback was queued before this one).
      requestAnimationFrame(() => {
        if (metrics.syncGpu) {
          const gl = app.viewer.renderer.getContext();
          gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        }
        metrics.sliderLatenciesMs.push(performance.now() - t0);
      });
    }
    const next = app.jointQueue.get(wire);
    if (next) {
      app.jointQueue.delete(wire);
      sendJoint(wire, next.value, next.t0);
    }
  });
}

function buildHandleSelect() {
  const select = $("ik-handle");
  select.textContent = "";
  for (const name of app.handles) select.append(new Option(name, name));
  select.onchange = () => showHandleFields(true);
}

function render(state) {
  app.state = state;
  $("app").classList.toggle("closed", !state.open);
  if (!state.open) {
    $("file-name").textContent = "no motion open";
    if (state.open_error) showError(state.open_error, "open");
    return;
  }
  $("file-name").textContent = state.path || state.name;
  $("dirty-mark").textContent = state.dirty ? "● unsaved" : "";
  $("format-tag").textContent = state.format === "xml" ? "XML phase" : "Webots";
  document.title = `${state.dirty ? "● " : ""}${state.name} — motion-studio`;
  $("undo").disabled = !state.can_undo;
  $("redo").disabled = !state.can_redo;
  renderKeyframes(state);
  renderJoints(state);
  showHandleFields(false);
  renderBalance(state.balance);
  renderTimeline(state);
  renderPreview(state.preview);
}

function renderKeyframes(state) {
  const key = JSON.stringify([state.keyframes, state.selected]);
  if (key !== app.keyframesKey) {
    app.keyframesKey = key;
    const list = $("keyframe-list");
    list.textContent = "";
    state.keyframes.forEach((kf, index) => {
      const item = document.createElement("li");
      item.id = `kf-${index}`;
      item.className = index === state.selected ? "selected" : "";
      const number = document.createElement("span");
      number.className = "kf-index";
      number.textContent = index + 1;
      const name = document.createElement("span");
      name.className = "kf-name";
      name.textContent = kf.name;
      const meta = document.createElement("span");
      meta.className = "kf-meta";
      meta.textContent = `${kf.duration_ms} ms · ${kf.listed} joints${kf.next ? " → " + kf.next : ""}`;
      item.append(number, name, meta);
      item.onclick = () => request("select", { index });
      list.append(item);
    });
    const selected = list.children[state.selected];
    if (selected) selected.scrollIntoView({ block: "nearest" });
  }
  const kf = state.keyframes[state.selected];
  if (document.activeElement !== $("kf-name")) $("kf-name").value = kf.name;
  if (document.activeElement !== $("kf-duration")) $("kf-duration").value = kf.duration_ms;
  $("xml-links").hidden = state.format !== "xml";
  $("kf-up").disabled = state.selected === 0;
  $("kf-down").disabled = state.selected === state.keyframes.length - 1;
  $("kf-delete").disabled = state.keyframes.length < 2;
  if (state.format === "xml") {
    for (const [id, value] of [["kf-next", kf.next], ["kf-finalize", kf.finalize]]) {
      const select = $(id);
      select.textContent = "";
      select.append(new Option("(none)", ""));
      for (const other of state.keyframes) select.append(new Option(other.name, other.name));
      select.value = value || "";
    }
    $("kf-flags").textContent = Object.entries(kf.flags).map(([k, v]) => `${k}=${v}`).join("  ");
  }
}

function renderJoints(state) {
  for (const joint of app.joints) {
    const value = state.pose_deg[joint.wire];
    const slider = $(`slider-${joint.wire}`);
    const number = $(`number-${joint.wire}`);
    const waiting = app.jointInFlight.has(joint.wire) || app.jointQueue.has(joint.wire);
    if (!waiting && document.activeElement !== slider) slider.value = value;
    if (!waiting && document.activeElement !== number) number.value = Math.round(value * 100) / 100;
    const listed = joint.wire in state.listed;
    $(`row-${joint.wire}`).classList.toggle("listed", listed);
    $(`clear-${joint.wire}`).disabled = !listed;
  }
}

function showHandleFields(force) {
  const state = app.state;
  if (!state || !state.open) return;
  const handle = $("ik-handle").value || app.handles[0];
  const info = state.handles[handle];
  const oriented = app.orientedHandles.includes(handle);
  const fields = [["ik-x", info.position_m[0]], ["ik-y", info.position_m[1]], ["ik-z", info.position_m[2]],
                  ["ik-rx", info.rotation_deg[0]], ["ik-ry", info.rotation_deg[1]], ["ik-rz", info.rotation_deg[2]]];
  for (const [id, value] of fields) {
    const input = $(id);
    if (force || document.activeElement !== input) input.value = Math.round(value * 10000) / 10000;
  }
  for (const id of ["ik-rx", "ik-ry", "ik-rz"]) $(id).disabled = !oriented;
}

function renderBalance(balance) {
  const [x, y, z] = balance.com_m.map((v) => v.toFixed(3));
  const where = balance.inside ? `<span class="inside">inside</span>` : `<span class="outside">outside</span>`;
  $("balance").innerHTML = `CoM (${x}, ${y}, ${z}) m · ground projection ${where} the support polygon ` +
    `(margin ${(balance.margin_m * 1000).toFixed(1)} mm)`;
}

function timelineEnd() {
  const state = app.state;
  let end = state.duration_s;
  if (app.series && state.preview.summary) end = Math.max(end, app.series.t_s[app.series.t_s.length - 1]);
  return Math.max(end, 0.001);
}

function renderTimeline(state) {
  const slider = $("time");
  const end = timelineEnd();
  slider.max = end;
  const ticks = $("time-ticks");
  ticks.textContent = "";
  for (const kf of state.keyframes) {
    const tick = document.createElement("span");
    tick.style.left = `${(100 * kf.end_s) / end}%`;
    ticks.append(tick);
  }
  if (!app.playing) {
    const t = state.view_time_s !== null ? state.view_time_s : state.keyframes[state.selected].end_s;
    slider.value = t;
    $("time-label").textContent = `${t.toFixed(3)} s`;
  }
  drawPlot();
}

function renderPreview(preview) {
  const running = preview.status === "running";
  $("preview").disabled = running;
  $("preview-cancel").hidden = !running;
  $("preview-progress").hidden = !running;
  if (running) $("preview-progress").value = preview.fraction;
  const result = $("preview-result");
  result.className = "";
  if (preview.status === "failed") result.textContent = `preview failed: ${preview.error}`;
  else if (preview.status === "cancelled") result.textContent = "preview cancelled";
  else if (running) result.textContent = "simulating…";
  else if (preview.summary) {
    const s = preview.summary;
    result.className = s.fell ? "fell" : "stood";
    result.textContent = s.fell ? `fell at ${s.fall_time_s.toFixed(2)} s` :
      `stayed up (torso min ${s.min_torso_height_m.toFixed(3)} m)`;
    if (preview.stale) {
      const stale = document.createElement("span");
      stale.className = "stale";
      stale.textContent = " (motion edited since)";
      result.append(stale);
    }
  } else result.textContent = "";
}

// ------------------------------------------------------------------------------------------ plot
function drawPlot() {
  const canvas = $("plot");
  const width = canvas.clientWidth, height = canvas.clientHeight;
  if (canvas.width !== width) canvas.width = width;
  canvas.height = height;
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, width, height);
  ctx.font = "11px system-ui, sans-serif";
  const series = app.series;
  if (!series || !series.t_s.length) {
    ctx.fillStyle = "#889";
    ctx.fillText("Physics preview: torso height and CoM over time appear here.", 12, 20);
    return;
  }
  const left = 46, right = width - 10, top = 18, bottom = height - 22;
  const tEnd = timelineEnd();
  const x0 = series.com_x_m[0], y0 = series.com_y_m[0];
  const lines = [
    ["torso height", "#2060d0", series.torso_height_m, []],
    ["CoM height", "#d03030", series.com_z_m, []],
    ["CoM x − start (right)", "#e08a10", series.com_x_m.map((v) => v - x0), [5, 3]],
    ["CoM y − start (forward)", "#209040", series.com_y_m.map((v) => v - y0), [2, 2]],
  ];
  let lo = Infinity, hi = -Infinity;
  for (const [, , values] of lines) for (const v of values) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  lo = Math.min(lo, 0); hi = Math.max(hi, 0.1);
  const sx = (t) => left + ((right - left) * t) / tEnd;
  const sy = (v) => bottom - ((bottom - top) * (v - lo)) / (hi - lo);
  ctx.strokeStyle = "#ccd"; ctx.fillStyle = "#556"; ctx.lineWidth = 1;
  ctx.beginPath(); ctx.moveTo(left, top); ctx.lineTo(left, bottom); ctx.lineTo(right, bottom); ctx.stroke();
  let lastLabelY = Infinity;  // bottom-up, skipping labels that would overlap
  for (const v of [lo, 0, hi]) {
    if (lastLabelY - sy(v) < 12) continue;
    ctx.fillText(`${v.toFixed(2)} m`, 2, sy(v) + 4);
    lastLabelY = sy(v);
  }
  ctx.fillText("0 s", left - 4, height - 6);
  ctx.fillText(`${tEnd.toFixed(2)} s`, right - 34, height - 6);
  ctx.beginPath(); ctx.setLineDash([1, 3]); ctx.moveTo(sx(series.motion_duration_s), top);
  ctx.lineTo(sx(series.motion_duration_s), bottom); ctx.stroke(); ctx.setLineDash([]);
  let legendX = left + 4;
  for (const [name, colour, values, dash] of lines) {
    ctx.strokeStyle = colour; ctx.lineWidth = 1.6; ctx.setLineDash(dash);
    ctx.beginPath();
    values.forEach((v, i) => (i ? ctx.lineTo(sx(series.t_s[i]), sy(v)) : ctx.moveTo(sx(series.t_s[i]), sy(v))));
    ctx.stroke(); ctx.setLineDash([]);
    ctx.fillStyle = colour; ctx.fillText(name, legendX, 12);
    legendX += ctx.measureText(name).width + 14;
  }
  if (series.fall_time_s !== null && series.fall_time_s !== undefined) {
    ctx.strokeStyle = "#000"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(sx(series.fall_time_s), top); ctx.lineTo(sx(series.fall_time_s), bottom); ctx.stroke();
    ctx.fillStyle = "#000"; ctx.fillText("fell", sx(series.fall_time_s) + 3, top + 10);
  }
  const t = parseFloat($("time").value);
  ctx.strokeStyle = "#889"; ctx.lineWidth = 1;
  ctx.beginPath(); ctx.moveTo(sx(t), top); ctx.lineTo(sx(t), bottom); ctx.stroke();
}

// ------------------------------------------------------------------------------------------ timeline
function scrubTo(t) {
  $("time").value = t;
  $("time-label").textContent = `${t.toFixed(3)} s`;
  if (app.timeInFlight) { app.pendingTime = t; return; }
  app.timeInFlight = true;
  request("scrub", { t_s: t }).then(() => {
    app.timeInFlight = false;
    drawPlot();
    if (app.pendingTime !== null) { const next = app.pendingTime; app.pendingTime = null; scrubTo(next); }
  });
}

function play() {
  if (app.playing) { app.playing = false; $("play").textContent = "▶ Play"; return; }
  const end = timelineEnd();
  let start = parseFloat($("time").value);
  if (start >= end - 1e-6) start = 0;
  const wallStart = performance.now();
  window.motionStudio.metrics.playFrames = 0;
  app.playing = true;
  $("play").textContent = "■ Stop";
  const frame = () => {
    if (!app.playing) return;
    const t = Math.min(end, start + (performance.now() - wallStart) / 1000);  // real speed
    if (!app.timeInFlight) { scrubTo(t); window.motionStudio.metrics.playFrames += 1; }
    if (t >= end) {
      window.motionStudio.metrics.playWallS = (performance.now() - wallStart) / 1000;
      app.playing = false;
      $("play").textContent = "▶ Play";
      scrubTo(end);  // the last pose, sent after the request in flight if there is one
      return;
    }
    requestAnimationFrame(frame);
  };
  requestAnimationFrame(frame);
}

// ------------------------------------------------------------------------------------------ IK drag
function setupDrag() {
  const viewer = app.viewer;
  const THREE = MeshCat.THREE;
  const canvas = viewer.renderer.domElement;
  const raycaster = new THREE.Raycaster();
  const pointer = new THREE.Vector2();
  const handlesNode = () => viewer.scene_tree.find(["meshcat", "handles"]).object;
  const rootNode = () => viewer.scene_tree.find(["meshcat"]).object;

  const ray = (event) => {
    const rect = canvas.getBoundingClientRect();
    pointer.set(((event.clientX - rect.left) / rect.width) * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
    raycaster.setFromCamera(pointer, viewer.camera);
  };

  canvas.addEventListener("pointerdown", (event) => {
    if (!app.state || !app.state.open || app.state.view_time_s !== null || event.button !== 0) return;
    ray(event);
    const hits = raycaster.intersectObject(handlesNode(), true);
    if (!hits.length) return;
    let node = hits[0].object;
    while (node.parent && node.parent !== handlesNode()) node = node.parent;
    const name = node.name;
    if (!app.handles.includes(name)) return;
    const normal = new THREE.Vector3();
    viewer.camera.getWorldDirection(normal);
    app.drag = { name, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hits[0].point),
                 offset: hits[0].point.clone().sub(node.getWorldPosition(new THREE.Vector3())),
                 node, busy: false, last: null, sent: null };
    app.gesture += 1;
    viewer.controls.enabled = false;
    $("ik-handle").value = name;
    showHandleFields(true);
    canvas.setPointerCapture(event.pointerId);
    event.preventDefault();
    event.stopImmediatePropagation();
  }, true);

  canvas.addEventListener("pointermove", (event) => {
    const drag = app.drag;
    if (!drag) return;
    ray(event);
    const point = new THREE.Vector3();
    if (!raycaster.ray.intersectPlane(drag.plane, point)) return;
    point.sub(drag.offset);
    const local = rootNode().worldToLocal(point.clone());  // meshcat root = our z-up display frame
    drag.node.position.copy(drag.node.parent.worldToLocal(point.clone()));
    viewer.set_dirty();
    drag.last = [local.x, local.y, local.z];
    sendDrag();
  });

  const end = (event) => {
    if (!app.drag) return;
    const drag = app.drag;
    app.drag = null;
    viewer.controls.enabled = true;
    if (drag.last && drag.last !== drag.sent) sendIk(drag.name, drag.last, null);  // where the pointer let go
  };
  canvas.addEventListener("pointerup", end);
  canvas.addEventListener("pointercancel", end);

  function sendDrag() {
    const drag = app.drag;
    if (!drag || drag.busy || !drag.last) return;
    drag.busy = true;
    const target = drag.last;
    drag.sent = target;
    sendIk(drag.name, target, null).then(() => {
      drag.busy = false;
      if (app.drag === drag && drag.last !== target) sendDrag();
    });
  }
}

function sendIk(handle, position, rotation) {
  const args = { index: app.state.selected, handle, position_m: position, keep_com: $("ik-keep-com").checked,
                 gesture: app.gesture };
  if (rotation) args.rotation_deg = rotation;
  return request("ik", args, true).then((reply) => {
    const status = $("ik-status");
    status.className = reply.ok ? "" : "error";
    status.textContent = reply.ok ? (reply.changed.length ? `moved ${reply.changed.join(", ")}` : "no change") :
      `${reply.error.message} — the pose stays as it was`;
    return reply;
  });
}

// ------------------------------------------------------------------------------------------ wiring
function wire() {
  const selected = () => app.state.selected;
  $("save").onclick = () => request("save");
  $("undo").onclick = () => request("undo");
  $("redo").onclick = () => request("redo");
  $("open").onclick = () => {
    const path = $("open-path").value.trim();
    if (!path) return;
    if (app.state && app.state.dirty && !confirm("Discard the unsaved changes of this tab and open another file?")) return;
    request("open", { path });
  };
  $("saveas").onclick = async () => {
    const path = $("saveas-path").value.trim();
    if (!path) return;
    const args = { path, format: $("saveas-format").value, lossy: $("saveas-lossy").checked };
    let reply = await request("save_as", args);
    if (!reply.ok && reply.error.field === "overwrite" && confirm(`${path} exists. Replace it?`)) {
      reply = await request("save_as", { ...args, overwrite: true });
    }
  };
  $("kf-add").onclick = () => request("add", { index: selected() });
  $("kf-duplicate").onclick = () => request("duplicate", { index: selected() });
  $("kf-delete").onclick = () => request("delete", { index: selected() });
  $("kf-up").onclick = () => request("move", { index: selected(), to: selected() - 1 });
  $("kf-down").onclick = () => request("move", { index: selected(), to: selected() + 1 });
  $("kf-mirror").onclick = () => request("mirror_keyframe", { index: selected() });
  $("motion-mirror").onclick = () => request("mirror_motion");
  $("kf-name").onchange = () => request("rename", { index: selected(), name: $("kf-name").value });
  $("kf-duration").onchange = () => request("set_duration", { index: selected(),
                                                              duration_ms: parseFloat($("kf-duration").value) });
  const links = () => request("set_links", { index: selected(), next: $("kf-next").value,
                                             finalize: $("kf-finalize").value });
  $("kf-next").onchange = links;
  $("kf-finalize").onchange = links;
  $("ik-apply").onclick = () => {
    app.gesture += 1;
    const handle = $("ik-handle").value;
    const position = ["ik-x", "ik-y", "ik-z"].map((id) => parseFloat($(id).value));
    const rotation = app.orientedHandles.includes(handle) ? ["ik-rx", "ik-ry", "ik-rz"].map((id) => parseFloat($(id).value)) : null;
    sendIk(handle, position, rotation);
  };
  $("time").addEventListener("input", () => { app.playing = false; $("play").textContent = "▶ Play"; scrubTo(parseFloat($("time").value)); });
  $("play").onclick = play;
  $("preview").onclick = () => { $("preview-progress").value = 0; request("preview_start"); };
  $("preview-cancel").onclick = () => request("preview_cancel");
  window.addEventListener("keydown", (event) => {
    if (!(event.ctrlKey || event.metaKey)) return;
    const key = event.key.toLowerCase();
    if (key === "s") { event.preventDefault(); request("save"); }
    else if (key === "z" && !event.shiftKey && !isTextField(event.target)) { event.preventDefault(); request("undo"); }
    else if ((key === "y" || (key === "z" && event.shiftKey)) && !isTextField(event.target)) {
      event.preventDefault(); request("redo");
    }
  });
  // Closing or reloading with unsaved changes asks first.
  window.addEventListener("beforeunload", (event) => {
    if (app.state && app.state.dirty) { event.preventDefault(); event.returnValue = ""; }
  });
  // After meshcat's own load/resize handlers (which size the view to the whole window height).
  window.addEventListener("resize", () => { resizeView(); drawPlot(); });
  window.addEventListener("load", resizeView);
}

function isTextField(target) {
  return target && target.tagName === "INPUT" && (target.type === "text" || target.type === "number" || !target.type);
}

function resizeView() {
  const view = $("view");
  app.viewer.set_3d_pane_size(view.clientWidth, view.clientHeight);
}

// Software WebGL (SwiftShader, llvmpipe: headless browsers, machines without a GPU driver) takes ~70 ms
// per frame with multisampling and shadow maps and ~35 ms without (measured, 970x650 px): drop both there.
function softwareRenderer() {
  const gl = document.createElement("canvas").getContext("webgl");
  const info = gl && gl.getExtension("WEBGL_debug_renderer_info");
  const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
  if (!/SwiftShader|llvmpipe|softpipe|Software/i.test(name)) return undefined;
  const renderer = new MeshCat.THREE.WebGLRenderer({ antialias: false, alpha: true });
  $("view").appendChild(renderer.domElement);
  return renderer;
}

function main() {
  app.viewer = new MeshCat.Viewer($("view"), true, softwareRenderer());
  new ResizeObserver(resizeView).observe($("view"));
  resizeView();
  wire();
  setupDrag();
  window.motionStudio.ready = connect();
}

main();
