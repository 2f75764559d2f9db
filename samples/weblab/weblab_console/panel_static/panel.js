// The WebLab's panel on the console's page (acordcs.console.panels): the on-board and panoramic
// cameras, the navigation map and the teleoperation controls. The page around it (architecture,
// context, policies, events, hands, the token and the socket) is the console's: it calls
// mount(section, console) once, with console.send(command), console.on(type, fn) for the JSON
// messages of this panel's channels, console.onBinary(fn) for binary messages (camera frames:
// first byte 1 on-board, 2 panoramic; 0: several, each a camera byte, a 4-byte big-endian length
// and the JPEG), console.say(text, kind) and console.hello (what the server said first).

const state = { path: null, last: null, manual: false, driveTimer: null, run: null };
const imageUrls = { 1: null, 2: null };
let send = () => {};
let el = {};

function make(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, value);
  node.append(...children);
  return node;
}

function build(section, profiles, attached) {
  const onboard = make("img", { id: "onboard", alt: "on-board camera frame", hidden: "" });
  const panoramic = make("img", { id: "panoramic", alt: "panoramic camera frame", hidden: "" });
  const profile = make("select", { id: "profile" });
  for (const name of profiles) profile.add(new Option(name, name));
  const seed = make("input", { id: "seed", type: "number", min: "0", max: "2147483647", value: "0" });
  const speed = make("input", { id: "speed", type: "range", min: "0", max: "200", value: "0" });
  const turn = make("input", { id: "turn", type: "range", min: "-60", max: "60", value: "0" });
  el = {
    onboard, panoramic, profile, seed, speed, turn,
    map: make("canvas", { id: "map", width: "480", height: "360" }),
    start: make("button", { type: "submit", id: "start" }, "Start"),
    stop: make("button", { type: "button", id: "stop" }, "Stop"),
    take: make("button", { type: "button", id: "take" }, "Take control"),
    release: make("button", { type: "button", id: "release" }, "Hand back to the Navigator"),
    speedOut: make("output", { id: "speed-out" }, "0"),
    turnOut: make("output", { id: "turn-out" }, "0"),
    fps: make("small", { id: "fps-shown" }, "– fps"),
    run: make("span", { id: "profile-shown", class: "muted" }),
    driver: make("p", { id: "driver", class: "muted" }, "Navigator drives."),
    attached: make("p", { id: "attached", class: "muted", hidden: "" }),
  };
  const experiment = make("form", { id: "experiment", autocomplete: "off" },
    make("label", {}, "Network ", profile), make("label", {}, "Seed ", seed), el.start, el.stop, el.run);
  section.append(
    make("div", { class: "weblab" },
      make("figure", { id: "onboard-panel" }, make("figcaption", {}, "On-board camera ", make("small", {}, "the Navigator's view")),
        make("div", { class: "camera" }, onboard, make("p", { id: "onboard-waiting", class: "waiting" }, "no frame yet: the Navigator's first image shows here"))),
      make("figure", { id: "panoramic-panel" }, make("figcaption", {}, "Panoramic camera ", el.fps),
        make("div", { class: "camera" }, panoramic, make("p", { id: "panoramic-waiting", class: "waiting" }, "no frame yet: the room seen from above shows here"))),
      make("figure", { id: "map-panel" }, make("figcaption", {}, "Navigation map ", make("small", {}, "stripe, trajectory, pose, sonar")), el.map),
      make("div", { id: "teleop-panel" }, make("h3", {}, "Teleoperation"), experiment, el.attached,
        make("div", { id: "manual" },
          make("label", {}, "Speed ", speed, " ", el.speedOut, " mm/s"),
          make("label", {}, "Turn ", turn, " ", el.turnOut, " ° (+ left)"),
          el.take, el.release),
        el.driver)));
  experiment.addEventListener("submit", (event) => {
    event.preventDefault();
    send({ cmd: "start", profile: profile.value, seed: Number(seed.value) });
  });
  el.stop.addEventListener("click", () => send({ cmd: "stop" }));
  el.take.addEventListener("click", () => { if (!state.manual) startDriving(); });
  el.release.addEventListener("click", () => { stopDriving(); send({ cmd: "release" }); });
  speed.addEventListener("input", () => (el.speedOut.textContent = speed.value));
  turn.addEventListener("input", () => (el.turnOut.textContent = turn.value));
  if (attached) {  // the application its scripts started: they start and stop it, not the page
    for (const id of ["profile", "seed", "start", "stop"]) el[id].disabled = true;
    el.attached.hidden = false;
    el.attached.textContent = "Attached to the two-process application its scripts started (make live-console): " +
      "Ctrl-C there stops it. Take control to drive; the Navigator waits meanwhile.";
  }
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
  const img = camera === 1 ? el.onboard : camera === 2 ? el.panoramic : null;
  if (!img) return;
  const url = URL.createObjectURL(new Blob([jpeg], { type: "image/jpeg" }));
  if (imageUrls[camera]) URL.revokeObjectURL(imageUrls[camera]);
  imageUrls[camera] = url;
  img.src = url;
  img.dataset.frames = String(Number(img.dataset.frames || 0) + 1);
  if (img.hidden) {  // the first frame replaces the placeholder
    img.hidden = false;
    document.getElementById(`${img.id}-waiting`).hidden = true;
  }
}

function showState(s) {
  state.last = s;
  el.run.textContent = s.profile ? `${s.profile}, seed ${s.seed}${s.running ? "" : " (stopped)"}` : "";
  el.fps.textContent = `${s.fps} fps`;
  el.driver.textContent = s.driver !== "manual" ? "Navigator drives."
    : `You drive (manual control).${s.held ? " The Navigator waits for its next image." : ""}`;
  const run = `${s.profile}|${s.seed}`;  // the running experiment's, however it was started
  if (s.profile && run !== state.run) {
    state.run = run;
    if ([...el.profile.options].some((o) => o.value === s.profile)) el.profile.value = s.profile;
    el.seed.value = String(s.seed);
  }
  const map = el.map;
  map.dataset.held = String(s.held || 0);
  map.dataset.points = String(s.trajectory.length);
  map.dataset.pose = s.pose.join(",");
  map.dataset.driver = s.driver;
  map.dataset.running = String(s.running);
  map.dataset.t = String(s.t);
  drawMap();
}

function drawMap() {
  const canvas = el.map;
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
  line(s.trajectory, "#1f6feb", 2);
  const [x, y, heading] = s.pose;
  const a = (heading * Math.PI) / 180;
  ctx.strokeStyle = "rgba(210, 153, 34, .6)";
  ctx.lineWidth = 1;
  for (const [angle, range] of s.sonar) {
    const b = a + (angle * Math.PI) / 180;
    ctx.beginPath();
    ctx.moveTo(X(x), Y(y));
    ctx.lineTo(X(x + range * Math.cos(b)), Y(y + range * Math.sin(b)));
    ctx.stroke();
  }
  ctx.fillStyle = "#24292f";
  ctx.beginPath();
  ctx.moveTo(X(x + 120 * Math.cos(a)), Y(y + 120 * Math.sin(a)));
  ctx.lineTo(X(x + 70 * Math.cos(a + 2.5)), Y(y + 70 * Math.sin(a + 2.5)));
  ctx.lineTo(X(x + 70 * Math.cos(a - 2.5)), Y(y + 70 * Math.sin(a - 2.5)));
  ctx.closePath();
  ctx.fill();
}

function startDriving() {
  state.manual = true;
  const tick = () => send({ cmd: "drive", speed: Number(el.speed.value), turn: Number(el.turn.value) });
  tick();
  state.driveTimer = setInterval(tick, 100);
}

function stopDriving() {
  state.manual = false;
  if (state.driveTimer) clearInterval(state.driveTimer);
  state.driveTimer = null;
}

export function mount(section, console) {
  send = (command) => console.send(command);
  const panel = (console.hello.panel_state || {}).weblab || {};
  build(section, panel.profiles || [], panel.mode === "attached");
  console.onBinary(showFrames);
  console.on("path", (data) => { state.path = data; drawMap(); });
  console.on("state", showState);
  console.on("disconnected", stopDriving);
}
