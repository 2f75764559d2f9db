// The WebLab console's page: one WebSocket, camera frames as binary messages (first byte: 1 on-board,
// 2 panoramic; 0: several frames, each a camera byte, a 4-byte big-endian length and the JPEG),
// everything else as JSON {type, data}. Commands go back as JSON (see commands.py).
// The session's token comes in the link's fragment (#token=..., never sent to a server): the page
// keeps it in this tab's sessionStorage (this origin only), takes it out of the address bar and
// history, and presents it when it opens the WebSocket (subprotocol weblab.token.<token>).

const $ = (id) => document.getElementById(id);
const TOKEN_KEY = "weblab-console-token";
const TOKEN_SHAPE = /^[A-Za-z0-9_-]{1,128}$/;  // what a subprotocol may carry; the console's are so

function takeToken() {
  const given = new URLSearchParams(location.hash.slice(1)).get("token");
  if (given !== null) {
    sessionStorage.setItem(TOKEN_KEY, given);
    history.replaceState(null, "", location.pathname + location.search);
  }
  return sessionStorage.getItem(TOKEN_KEY);
}

let token = takeToken();
const state = { path: null, last: null, manual: false, driveTimer: null, socket: null, frames: 0, run: null };
const imageUrls = { 1: null, 2: null };

function say(text, kind = "") {
  const el = $("message");
  el.textContent = text;
  el.className = kind;
}

function send(command) {
  if (state.socket && state.socket.readyState === WebSocket.OPEN) {
    state.socket.send(JSON.stringify(command));
  }
}

function connect() {
  const protocols = ["weblab"];
  if (token && TOKEN_SHAPE.test(token)) protocols.push(`weblab.token.${token}`);
  const socket = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`, protocols);
  socket.binaryType = "arraybuffer";
  state.socket = socket;
  socket.onopen = () => {
    $("connection").textContent = "live";
    $("connection").className = "badge on";
    if (!token) say("watching only: open the link with the session's token to drive", "refused");
    else if (!TOKEN_SHAPE.test(token)) say("the link's token is malformed: watching only (open the link the console printed)", "refused");
  };
  socket.onclose = (event) => {
    if (socket !== state.socket) return;  // replaced (a new token): the new one is connecting
    $("connection").textContent = event.code === 1013 ? "full" : "disconnected";
    $("connection").className = "badge off";
    stopDriving();
    if (event.code !== 1013 && event.code !== 1008) setTimeout(connect, 2000);
  };
  socket.onmessage = (event) => {
    if (event.data instanceof ArrayBuffer) return showFrames(new Uint8Array(event.data));
    let message;
    try { message = JSON.parse(event.data); } catch { return; }
    if (Array.isArray(message)) message.forEach(handle);  // several pending at once, in order
    else handle(message);
  };
}

function showFrames(bytes) {
  if (bytes[0] !== 0) return showFrame(bytes[0], bytes.subarray(1));
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  for (let at = 1; at + 5 <= bytes.length;) {
    const length = view.getUint32(at + 1);
    showFrame(bytes[at], bytes.subarray(at + 5, at + 5 + length));
    at += 5 + length;
  }
}

function showFrame(camera, jpeg) {
  const img = camera === 1 ? $("onboard") : camera === 2 ? $("panoramic") : null;
  if (!img) return;
  const url = URL.createObjectURL(new Blob([jpeg], { type: "image/jpeg" }));
  if (imageUrls[camera]) URL.revokeObjectURL(imageUrls[camera]);
  imageUrls[camera] = url;
  img.src = url;
  img.dataset.frames = String(Number(img.dataset.frames || 0) + 1);
  if (img.hidden) {  // the first frame replaces the panel's placeholder
    img.hidden = false;
    $(`${img.id}-waiting`).hidden = true;
  }
}

function handle(message) {
  const { type, data } = message;
  if (type === "hello") return hello(message);
  if (type === "authorized") return say("you hold the session: you may drive");
  if (type === "refused") return say(`refused: ${message.why}${message.todo ? ` (${message.todo})` : ""}`, "refused");
  if (type === "error") return say(`${message.cmd}: ${message.why}`, "refused");
  if (type === "done") return say(`${message.cmd}: done`);
  if (type === "path") { state.path = data; return drawMap(); }
  if (type === "state") return showState(data);
  if (type === "context") return showContext(data);
  if (type === "series") return drawSeries(data);
  if (type === "event") return addEvent(data);
  if (type === "stats") return ($("footer").textContent = `viewers ${data.viewers} · frames dropped for slow viewers ${data.replaced}`);
  if (type.startsWith("policy:")) return showPolicy(data);
}

function hello(message) {
  const select = $("profile");
  if (!select.options.length) for (const name of message.profiles) select.add(new Option(name, name));
  if (message.mode !== "attached") return;
  // Attached to the application its scripts started: they start and stop it, not the page.
  for (const id of ["profile", "seed", "start", "stop"]) $(id).disabled = true;
  $("attached").hidden = false;
  $("attached").textContent = "Attached to the two-process application its scripts started (make live-console): " +
    "Ctrl-C there stops it. Take control to drive; the Navigator waits meanwhile.";
}

function showState(s) {
  state.last = s;
  $("clock").textContent = `t = ${s.t.toFixed(1)} s`;
  $("profile-shown").textContent = s.profile ? `${s.profile}, seed ${s.seed}${s.running ? "" : " (stopped)"}` : "";
  $("fps-shown").textContent = `${s.fps} fps`;
  $("driver").textContent = s.driver !== "manual" ? "Navigator drives."
    : `You drive (manual control).${s.held ? " The Navigator waits for its next image." : ""}`;
  // The running experiment's network and seed in the form (a run started elsewhere: --start,
  // another tab, or the application the console is attached to), once per run.
  const run = `${s.profile}|${s.seed}`;
  if (s.profile && run !== state.run) {
    state.run = run;
    if ([...$("profile").options].some((o) => o.value === s.profile)) $("profile").value = s.profile;
    $("seed").value = String(s.seed);
  }
  const map = $("map");
  map.dataset.held = String(s.held || 0);
  map.dataset.points = String(s.trajectory.length);
  map.dataset.pose = s.pose.join(",");
  map.dataset.driver = s.driver;
  map.dataset.running = String(s.running);
  map.dataset.t = String(s.t);
  drawMap();
}

function showContext(values) {
  const body = $("context").tBodies[0];
  body.replaceChildren(...Object.entries(values).map(([name, value]) => {
    const row = document.createElement("tr");
    const label = document.createElement("td");
    const cell = document.createElement("td");
    label.textContent = name;
    cell.className = "value";
    cell.textContent = typeof value !== "number" ? String(value) : Number.isInteger(value) ? String(value) : value.toFixed(2);
    row.append(label, cell);
    return row;
  }));
}

function showPolicy(p) {
  const id = `policy-${p.set}`;
  let box = document.getElementById(id);
  if (!box) {
    box = document.createElement("div");
    box.id = id;
    box.className = "policy";
    $("policies").append(box);
  }
  const head = document.createElement("div");
  head.className = "head";
  const title = document.createElement("b");
  title.textContent = p.set;
  const info = document.createElement("span");
  info.textContent = `${p.engine} · t = ${p.t.toFixed(1)} s · ${p.fires} firings`;
  head.append(title, info);
  const outs = document.createElement("div");
  outs.className = "out";
  outs.textContent = Object.entries(p.outputs).map(([k, v]) => `${k} = ${typeof v === "number" && !Number.isInteger(v) ? v.toFixed(1) : v}`).join(", ") || "no output";
  // The rules that fired, strongest first (at most 4); a set where none did lists its rules dimmed.
  const fired = p.rules.filter((r) => r.degree > 0).sort((a, b) => b.degree - a.degree);
  const shown = fired.length ? fired.slice(0, 4) : p.rules.slice(0, 4);
  const rules = shown.map((r) => {
    const row = document.createElement("div");
    row.className = `rule${p.engine === "fuzzy" ? "" : " crisp"}${r.degree > 0 ? "" : " zero"}`;
    const name = document.createElement("span");
    const bar = document.createElement("div");
    const value = document.createElement("span");
    name.textContent = r.label;
    bar.className = "bar";
    bar.style.width = `${Math.round(100 * r.degree)}%`;
    value.textContent = r.degree.toFixed(2);
    row.dataset.degree = String(r.degree);
    row.append(name, bar, value);
    return row;
  });
  box.replaceChildren(head, outs, ...rules);
  box.dataset.fires = String(p.fires);
}

function addEvent(e) {
  const item = document.createElement("li");
  item.className = e.kind;
  item.textContent = `${e.t.toFixed(1)} s  ${e.text}`;
  const list = $("timeline");
  list.prepend(item);
  while (list.children.length > 200) list.lastChild.remove();
}

function drawMap() {
  const canvas = $("map");
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const path = state.path;
  if (!path) return;
  const [w, h] = path.floor;
  const scale = Math.min(canvas.width / w, canvas.height / h);
  const X = (x) => x * scale;
  const Y = (y) => canvas.height - y * scale;
  const line = (points, color, width) => {
    if (!points.length) return;
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    ctx.beginPath();
    points.forEach(([x, y], i) => (i ? ctx.lineTo(X(x), Y(y)) : ctx.moveTo(X(x), Y(y))));
    ctx.stroke();
  };
  line(path.points, "#c0392b", Math.max(2, 50 * scale));
  const [fx, fy] = path.finish;
  ctx.fillStyle = "#3fb950";
  ctx.fillRect(X(fx) - 4, Y(fy) - 4, 8, 8);
  const s = state.last;
  if (!s) return;
  line(s.trajectory, "#4fb3ff", 2);
  const [x, y, heading] = s.pose;
  const a = (heading * Math.PI) / 180;
  ctx.strokeStyle = "rgba(210, 153, 34, .45)";
  ctx.lineWidth = 1;
  for (const [angle, range] of s.sonar) {
    const b = a + (angle * Math.PI) / 180;
    ctx.beginPath();
    ctx.moveTo(X(x), Y(y));
    ctx.lineTo(X(x + range * Math.cos(b)), Y(y + range * Math.sin(b)));
    ctx.stroke();
  }
  ctx.fillStyle = "#e6edf3";
  ctx.beginPath();
  ctx.moveTo(X(x + 120 * Math.cos(a)), Y(y + 120 * Math.sin(a)));
  ctx.lineTo(X(x + 70 * Math.cos(a + 2.5)), Y(y + 70 * Math.sin(a + 2.5)));
  ctx.lineTo(X(x + 70 * Math.cos(a - 2.5)), Y(y + 70 * Math.sin(a - 2.5)));
  ctx.closePath();
  ctx.fill();
}

function drawSeries(series) {
  plot($("plot-speed"), series.t, series.max_speed, "speed limit, mm/s", "#4fb3ff");
  plot($("plot-fps"), series.t, series.fps, "panoramic frame rate, fps", "#d29922");
}

// Seconds between the time axis's ticks: the first step giving at most 6 ticks over the span.
const TICK_STEPS = [1, 2, 5, 10, 15, 30, 60, 120, 300, 600, 1200, 1800, 3600];

function plot(canvas, t, values, label, color) {
  const ctx = canvas.getContext("2d");
  const { width, height } = canvas;
  const left = 5, right = width - 5, top = 20, bottom = height - 18;  // the plot's area
  ctx.clearRect(0, 0, width, height);
  ctx.fillStyle = "#8b98a5";
  ctx.font = "12px system-ui";
  ctx.fillText(label, 6, 14);
  if (!t.length) return;
  const t0 = t[0], t1 = Math.max(t[t.length - 1], t0 + 1);
  const most = Math.max(...values, 1) * 1.1;
  ctx.textAlign = "right";
  ctx.fillText(`max ${Math.max(...values).toFixed(0)}`, width - 6, 14);
  // The time axis: the run's clock, in seconds.
  const X = (ti) => left + ((ti - t0) / (t1 - t0)) * (right - left);
  const step = TICK_STEPS.find((s) => (t1 - t0) / s <= 6) || 7200;
  const ticks = [];
  ctx.strokeStyle = "#2a3642";
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(left, bottom + 0.5);
  ctx.lineTo(right, bottom + 0.5);
  ctx.textAlign = "center";
  for (let s = Math.ceil(t0 / step) * step; s <= t1; s += step) {
    const x = Math.round(X(s)) + 0.5;
    ctx.moveTo(x, bottom);
    ctx.lineTo(x, bottom + 4);
    const text = `${s} s`;
    ctx.fillText(text, Math.min(Math.max(x, left + 14), right - 14), height - 3);
    ticks.push(text);
  }
  ctx.stroke();
  ctx.textAlign = "left";
  ctx.strokeStyle = color;
  ctx.lineWidth = 2;
  ctx.beginPath();
  t.forEach((ti, i) => {
    const y = bottom - 2 - (values[i] / most) * (bottom - top);
    if (i) ctx.lineTo(X(ti), y); else ctx.moveTo(X(ti), y);
  });
  ctx.stroke();
  canvas.dataset.points = String(t.length);
  canvas.dataset.ticks = ticks.join(",");
}

function startDriving() {
  state.manual = true;
  const tick = () => send({ cmd: "drive", speed: Number($("speed").value), turn: Number($("turn").value) });
  tick();
  state.driveTimer = setInterval(tick, 100);
}

function stopDriving() {
  state.manual = false;
  if (state.driveTimer) clearInterval(state.driveTimer);
  state.driveTimer = null;
}

$("experiment").addEventListener("submit", (event) => {
  event.preventDefault();
  send({ cmd: "start", profile: $("profile").value, seed: Number($("seed").value) });
});
$("stop").addEventListener("click", () => send({ cmd: "stop" }));
$("take").addEventListener("click", () => { if (!state.manual) startDriving(); });
$("release").addEventListener("click", () => { stopDriving(); send({ cmd: "release" }); });
for (const id of ["speed", "turn"]) {
  $(id).addEventListener("input", () => ($(`${id}-out`).textContent = $(id).value));
}
// A link opened in a tab that shows the console already changes only the fragment: take its
// token and connect again with it.
window.addEventListener("hashchange", () => {
  if (!new URLSearchParams(location.hash.slice(1)).has("token")) return;
  token = takeToken();
  const old = state.socket;
  stopDriving();
  connect();
  if (old) old.close();
});
setInterval(() => send({ cmd: "ping" }), 15000);
connect();
