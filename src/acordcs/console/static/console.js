// The console of any application: one WebSocket, JSON {type, data} messages (an array when
// several were pending). What it shows is computed by the server from the descriptor (the
// "application" message: the diagram, the series, the policy sets, the forms); this page draws.
// The console's token comes in the link's fragment (#token=..., never sent to a server): the page
// keeps it in this tab's sessionStorage, takes it out of the address bar and history, and presents
// it when it opens the WebSocket (subprotocol acordcs.token.<token>).

const $ = (id) => document.getElementById(id);
const SVG = "http://www.w3.org/2000/svg";
const TOKEN_KEY = "acordcs-console-token";
const TOKEN_SHAPE = /^[A-Za-z0-9_-]{1,128}$/;
const WINDOW = 60;  // seconds of each plot
const KEPT = 600;  // points of each series
const LOGGED = 40;  // lines of each log

function takeToken() {
  const given = new URLSearchParams(location.hash.slice(1)).get("token");
  if (given !== null) {
    sessionStorage.setItem(TOKEN_KEY, given);
    history.replaceState(null, "", location.pathname + location.search);
  }
  return sessionStorage.getItem(TOKEN_KEY);
}

let token = takeToken();
// The application's panels (acordcs.console.panels): each an ES module of the console's origin,
// mounted once in a section of its own; what they listen to, by message type, and binary messages.
// A panel's message that came before its module loaded is kept (the newest of each type) and
// given to it when it listens.
const panels = { mounted: false, handlers: new Map(), binary: [], last: new Map() };
const state = { socket: null, app: null, series: new Map(), firings: new Map(), now: 0, ref: 0, pending: new Map(), plan: null, drawn: false };

function say(text, kind = "") {
  const el = $("message");
  el.textContent = text;
  el.className = kind;
}

function send(command, then) {
  if (!state.socket || state.socket.readyState !== WebSocket.OPEN) return say("not connected", "refused");
  state.ref += 1;
  if (then) state.pending.set(state.ref, then);
  state.socket.send(JSON.stringify({ ...command, ref: state.ref }));
}

function connect() {
  const protocols = ["acordcs"];
  if (token && TOKEN_SHAPE.test(token)) protocols.push(`acordcs.token.${token}`);
  const socket = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`, protocols);
  socket.binaryType = "arraybuffer";
  state.socket = socket;
  socket.onopen = () => {
    $("connection").textContent = "live";
    $("connection").className = "badge on";
    if (!token) say("watching only: open the link the console printed to use its hands", "refused");
  };
  socket.onclose = (event) => {
    if (socket !== state.socket) return;  // replaced (a new token): the new one is connecting
    $("connection").textContent = event.code === 1013 ? "full" : event.code === 1008 ? "refused" : "disconnected";
    $("connection").className = "badge off";
    (panels.handlers.get("disconnected") || []).forEach((fn) => fn());
    if (event.code !== 1013 && event.code !== 1008) setTimeout(connect, 2000);
  };
  socket.onmessage = (event) => {
    if (event.data instanceof ArrayBuffer) {
      const bytes = new Uint8Array(event.data);
      return panels.binary.forEach((fn) => fn(bytes));
    }
    let message;
    try { message = JSON.parse(event.data); } catch { return; }
    if (Array.isArray(message)) message.forEach(handle);
    else handle(message);
  };
}

function handle(message) {
  const then = message.ref !== undefined ? state.pending.get(message.ref) : undefined;
  if (then) { state.pending.delete(message.ref); return then(message); }
  switch (message.type) {
    case "hello": return mountPanels(message);
    case "done": return say(`${message.cmd}: done`, "ok");
    case "application": return showApplication(message.data);
    case "event": return showEvent(message.data);
    case "refused": return say(`refused: ${message.why}${message.todo ? ` (${message.todo})` : ""}`, "refused");
    case "authorized": return say("holding the token: the hands are yours", "ok");
    case "error": return say(`${message.cmd}: ${message.why}`, "refused");
    default:
      if (message.type && message.type.startsWith("snapshot:")) return showSnapshot(message.data);
      panels.last.set(message.type, message.data);
      (panels.handlers.get(message.type) || []).forEach((fn) => fn(message.data));
  }
}

async function mountPanels(hello) {
  if (panels.mounted) return;
  panels.mounted = true;
  const api = {
    hello,
    send: (command, then) => send(command, then),
    say,
    on: (type, fn) => {
      panels.handlers.set(type, [...(panels.handlers.get(type) || []), fn]);
      if (panels.last.has(type)) fn(panels.last.get(type));
    },
    onBinary: (fn) => panels.binary.push(fn),
  };
  for (const panel of hello.panels || []) {
    const section = document.createElement("section");
    section.className = "panel wide app-panel";
    section.id = `panel-${panel.name}`;
    const h = document.createElement("h2");
    h.textContent = panel.title;
    section.append(h);
    document.querySelector("main").prepend(section);
    if (panel.style) {
      const link = document.createElement("link");
      link.rel = "stylesheet";
      link.href = panel.style;
      document.head.append(link);
    }
    try {
      const module = await import(panel.script);
      module.mount(section, api);
      section.dataset.mounted = "true";
    } catch (err) {
      section.append(waiting(`this panel could not be loaded: ${err}`));
    }
  }
}

// ------------------------------------------------------------------------------ architecture
function showApplication(app) {
  if (state.drawn) return;
  state.app = app;
  state.drawn = true;
  document.title = `${app.name}: acordcs console`;
  $("title").textContent = `${app.name}`;
  const parsed = new DOMParser().parseFromString(app.svg, "image/svg+xml");
  const svg = document.importNode(parsed.documentElement, true);
  $("architecture").replaceChildren(svg);
  svg.querySelectorAll("g.element").forEach((g) => {
    g.addEventListener("click", (e) => { e.stopPropagation(); showDetails(g); });
    g.addEventListener("keydown", (e) => { if (e.key === "Enter") showDetails(g); });
  });
  const plots = $("plots");
  plots.replaceChildren();
  for (const s of app.series) {
    const figure = document.createElement("figure");
    figure.className = "plot";
    figure.dataset.series = s.key;
    const caption = document.createElement("figcaption");
    const range = s.min !== null ? `, ${s.min} to ${s.max} (the model's range)` : ", range from the values";
    caption.textContent = `${s.key} (${s.type}${range}; the model gives no unit)`;
    const value = document.createElement("span");
    value.className = "value";
    caption.append(" ", value);
    figure.append(caption, plotSvg());
    plots.append(figure);
    state.series.set(s.key, { spec: s, points: [], figure, value });
  }
  if (!app.series.length) plots.replaceChildren(waiting("no monitor with a numeric property"));
  const sets = $("policy-sets");
  sets.replaceChildren();
  for (const p of app.policy_sets) {
    const box = document.createElement("div");
    box.className = "policy-set";
    box.dataset.set = p.name;
    const h = document.createElement("h4");
    h.textContent = `${p.name} (${p.engine}, in ${p.container})`;
    const body = document.createElement("div");
    body.className = "firing";
    body.append(waiting("not fired yet"));
    box.append(h, body);
    sets.append(box);
  }
  const select = $("operation");
  select.replaceChildren();
  app.operations.forEach((o, i) => {
    const option = document.createElement("option");
    option.value = String(i);
    option.textContent = `${o.component}.${o.port}.${o.name}(${o.parameters.filter((p) => p.direction !== "out" && p.direction !== "return").map((p) => `${p.name}: ${p.type}`).join(", ")})${o.returns ? `: ${o.returns}` : ""}`;
    select.append(option);
  });
  if (!app.operations.length) {
    const option = document.createElement("option");
    option.textContent = "no provided synchronous port in the model";
    select.append(option);
    select.disabled = true;
    $("call").disabled = true;
  }
  showParameters();
  const props = $("property");
  props.replaceChildren();
  app.properties.forEach((p, i) => {
    const option = document.createElement("option");
    option.value = String(i);
    option.textContent = `${p.element}.${p.attribute}: ${p.type} (default ${p.default})`;
    props.append(option);
  });
  $("set").disabled = props.disabled = !app.properties.length;
  $("update-model").textContent = app.model ? `model file: ${app.model}` : "started without --model FILE: send a changed model below";
  $("plan").disabled = !app.model;
}

function showDetails(g) {
  const d = $("details");
  d.replaceChildren();
  document.querySelectorAll("g.element.selected").forEach((e) => e.classList.remove("selected"));
  g.classList.add("selected");
  const info = (state.app && state.app.elements[g.dataset.name]) || {};
  const rows = [["kind", g.dataset.kind], ["qualified name", g.dataset.qname], ["model id", g.dataset.id]];
  for (const [key, value] of Object.entries(info)) {
    if (["kind", "qname", "id"].includes(key) || value === null || (Array.isArray(value) && !value.length)) continue;
    rows.push([key, typeof value === "object" ? JSON.stringify(value) : String(value)]);
  }
  for (const [key, value] of rows) {
    const dt = document.createElement("dt");
    dt.textContent = key;
    const dd = document.createElement("dd");
    dd.textContent = value;
    dd.dataset.field = key;
    d.append(dt, dd);
  }
  d.hidden = false;
}

// ----------------------------------------------------------------------------------- context
function waiting(text) {
  const p = document.createElement("p");
  p.className = "waiting";
  p.textContent = text;
  return p;
}

function plotSvg() {
  const svg = document.createElementNS(SVG, "svg");
  svg.setAttribute("viewBox", "0 0 400 120");
  svg.setAttribute("class", "series");
  for (const cls of ["axes", "grid", "line"]) {
    const path = document.createElementNS(SVG, "path");
    path.setAttribute("class", cls);
    svg.append(path);
  }
  for (const cls of ["y-max", "y-min", "x-left", "x-right"]) {
    const t = document.createElementNS(SVG, "text");
    t.setAttribute("class", `tick ${cls}`);
    svg.append(t);
  }
  return svg;
}

function showSnapshot(snapshot) {
  if (typeof snapshot.time === "number") tick(snapshot.time);
  for (const [name, props] of Object.entries(snapshot.elements || {})) {
    for (const [attribute, value] of Object.entries(props)) addPoint(`${name}.${attribute}`, snapshot.time, value);
  }
  for (const [name, firing] of Object.entries(snapshot.policy_sets || {})) if (firing) showFiring(firing, false);
}

function tick(time) {
  state.now = Math.max(state.now, time);
  $("clock").textContent = `t = ${state.now.toFixed(1)} s`;
}

function addPoint(key, time, value) {
  const series = state.series.get(key);
  if (!series || typeof value !== "number" || typeof time !== "number") return;
  const points = series.points;
  if (points.length && points[points.length - 1][0] >= time) return;
  points.push([time, value]);
  if (points.length > KEPT) points.shift();
  series.value.textContent = `now ${Number(value.toPrecision(4))}`;
  series.dirty = true;
}

function drawPlots() {
  for (const series of state.series.values()) {
    if (!series.dirty) continue;
    series.dirty = false;
    const { points, spec, figure } = series;
    const svg = figure.querySelector("svg");
    const right = state.now, left = right - WINDOW;
    const shown = points.filter((p) => p[0] >= left);
    if (!shown.length) continue;
    let lo = spec.min, hi = spec.max;
    if (lo === null || hi === null) {
      lo = Math.min(...shown.map((p) => p[1]));
      hi = Math.max(...shown.map((p) => p[1]));
      if (!(hi > lo)) { lo -= 1; hi += 1; }
    }
    const x = (t) => 40 + (360 * (t - left)) / WINDOW;
    const y = (v) => 105 - (95 * (Math.min(Math.max(v, lo), hi) - lo)) / (hi - lo);
    svg.querySelector(".axes").setAttribute("d", "M40,10 V105 H400");
    svg.querySelector(".grid").setAttribute("d", `M40,${y((lo + hi) / 2)} H400`);
    svg.querySelector(".line").setAttribute("d", shown.map((p, i) => `${i ? "L" : "M"}${x(p[0]).toFixed(1)},${y(p[1]).toFixed(1)}`).join(" "));
    figure.dataset.points = String(shown.length);
    const label = (cls, text, tx, ty, anchor) => {
      const t = svg.querySelector(`.${cls}`);
      t.textContent = text;
      t.setAttribute("x", tx);
      t.setAttribute("y", ty);
      t.setAttribute("text-anchor", anchor);
    };
    label("y-max", String(Number(hi.toPrecision(4))), 36, 14, "end");
    label("y-min", String(Number(lo.toPrecision(4))), 36, 105, "end");
    label("x-left", `${left.toFixed(0)} s`, 40, 118, "start");
    label("x-right", `${right.toFixed(0)} s`, 400, 118, "end");
  }
}

// ---------------------------------------------------------------------------------- policies
function showFiring(firing, logged) {
  const box = document.querySelector(`.policy-set[data-set="${CSS.escape(firing.set)}"] .firing`);
  if (box) {
    const table = document.createElement("table");
    const row = (cells, cls) => {
      const tr = document.createElement("tr");
      if (cls) tr.className = cls;
      cells.forEach((c, i) => {
        const td = document.createElement(i ? "td" : "th");
        if (c instanceof Node) td.append(c); else td.textContent = c;
        tr.append(td);
      });
      table.append(tr);
    };
    for (const [name, value] of Object.entries(firing.inputs)) row([`in ${name}`, fmt(value)], "input");
    for (const [policy, label, degree] of firing.rules) {
      const bar = document.createElement("meter");
      bar.min = 0; bar.max = 1; bar.value = degree;
      const span = document.createElement("span");
      span.className = "degree";
      span.textContent = ` ${degree.toFixed(2)}`;
      const cell = document.createElement("span");
      cell.append(bar, span);
      row([`${policy}.${label}`, cell], degree > 0 ? "rule fired" : "rule");
    }
    for (const [name, value] of Object.entries(firing.outputs)) row([`out ${name}`, fmt(value)], "output");
    const when = document.createElement("p");
    when.className = "muted";
    when.textContent = `firing ${firing.fires} at t = ${firing.time.toFixed(2)} s`;
    box.replaceChildren(when, table);
  }
  if (!logged) return;
  const fired = firing.rules.filter((r) => r[2] > 0).map((r) => `${r[1]} ${r[2].toFixed(2)}`).join(", ") || "no rule";
  const outs = Object.entries(firing.outputs).map(([k, v]) => `${k} = ${fmt(v)}`).join(", ") || "nothing written";
  log("firings", `t=${firing.time.toFixed(2)} ${firing.set}: ${fired} → ${outs}`, "fired");
}

function fmt(value) {
  return typeof value === "number" ? String(Number(value.toPrecision(5))) : JSON.stringify(value);
}

function log(id, text, cls) {
  const list = $(id);
  const li = document.createElement("li");
  li.textContent = text;
  li.className = cls;
  list.prepend(li);
  while (list.children.length > LOGGED) list.lastChild.remove();
}

// ------------------------------------------------------------------------------------ events
function showEvent(e) {
  if (typeof e.time === "number") tick(e.time);
  switch (e.kind) {
    case "monitor":
      for (const [attribute, value] of Object.entries(e.values)) addPoint(`${e.element}.${attribute}`, e.time, value);
      return;
    case "property":
      return addPoint(`${e.element}.${e.attribute}`, e.time, e.value);
    case "fired":
      return showFiring(e, true);
    case "model.updated":
      return log("events", `t=${e.time.toFixed(2)} ${e.container}: model.updated: ${e.line}`, "update");
    case "fault":
      return log("events", `t=${Number(e.time).toFixed(2)} ${e.container}: fault ${e.kind} in ${e.where}: ${e.error}`, "fault");
    case "down":
      return log("events", `${e.container} stopped answering: ${e.why}`, "down");
    case "up":
      return log("events", `${e.container} answers (watching)`, "up");
    case "stale":  // a monitor that cannot read keeps its last values, said here
      if (e.stale) return log("events", `t=${Number(e.time).toFixed(2)} ${e.container}: monitor ${e.element} stale, its last values kept: ${e.cause}`, "fault");
      return log("events", `t=${Number(e.time).toFixed(2)} ${e.container}: monitor ${e.element} reads again (stale for ${Number(e.stale_for).toFixed(1)} s)`, "up");
    case "hold":
      return log("events", `${e.container}: hold on ${e.component} (${Number(e.left).toFixed(1)} s left, ${e.waiting} call(s) waiting)`, "hold");
    case "released":
      return log("events", `${e.container}: ${e.component} released${e.why === "expired" ? " (the hold expired)" : ""} (its callers go on)`, "hold");
    case "dropped":
      return log("events", `${e.container}: ${e.count} events missed (the console fell behind)`, "fault");
    case "panel":  // what an application's panel tells (the WebLab's recoveries, the finish...)
      return log("events", `t=${Number(e.time).toFixed(2)} ${e.panel}: ${e.text}`, e.what);
  }
}

// ------------------------------------------------------------------------------------- hands
function showParameters() {
  const box = $("parameters");
  box.replaceChildren();
  const op = state.app && state.app.operations[Number($("operation").value)];
  if (!op) return;
  for (const p of op.parameters) {
    if (p.direction === "out" || p.direction === "return") continue;
    const label = document.createElement("label");
    label.textContent = `${p.name}: ${p.type} `;
    const input = document.createElement("input");
    input.name = p.name;
    input.dataset.type = p.type.toLowerCase();
    if (["int", "integer", "long", "short"].includes(input.dataset.type)) { input.type = "number"; input.step = "1"; input.required = true; }
    else if (["double", "float", "real"].includes(input.dataset.type)) { input.type = "number"; input.step = "any"; input.required = true; }
    else if (["bool", "boolean"].includes(input.dataset.type)) input.type = "checkbox";
    else input.type = "text";
    label.append(input);
    box.append(label);
  }
}

function callOperation(event) {
  event.preventDefault();
  const op = state.app.operations[Number($("operation").value)];
  const args = [...$("parameters").querySelectorAll("input")].map((i) => i.type === "checkbox" ? i.checked : i.type === "number" ? Number(i.value) : i.value);
  $("call-result").textContent = "calling…";
  send({ cmd: "call", component: op.component, port: op.port, operation: op.name, args }, (reply) => {
    const out = $("call-result");
    out.className = reply.type === "done" ? "ok" : "refused";
    out.textContent = reply.type === "done" ? `→ ${JSON.stringify(reply.result ?? null)}` : `fault: ${reply.why}`;
  });
}

function typedValue(type, text) {
  const t = type.toLowerCase();
  if (["int", "integer", "long", "short", "double", "float", "real"].includes(t)) return Number(text);
  if (["bool", "boolean"].includes(t)) return text === "true";
  return text;
}

function setProperty(event) {
  event.preventDefault();
  const p = state.app.properties[Number($("property").value)];
  $("set-result").textContent = "setting…";
  send({ cmd: "set", element: p.element, attribute: p.attribute, value: typedValue(p.type, $("property-value").value) }, (reply) => {
    const out = $("set-result");
    out.className = reply.type === "done" ? "ok" : "refused";
    out.textContent = reply.type === "done" ? `${p.element}.${p.attribute}: ${fmt(reply.result.old)} → ${fmt(reply.result.value)}` : `refused: ${reply.why}`;
  });
}

function plan() {
  $("plan-text").hidden = false;
  $("plan-text").textContent = "planning (acordcs-gen update --dry-run)…";
  $("apply").disabled = true;
  send({ cmd: "plan" }, (reply) => {
    if (reply.type !== "done") { $("plan-text").textContent = `refused: ${reply.why}`; return; }
    const r = reply.result;
    state.plan = r.plan;
    $("plan-text").textContent = `$ ${r.command}\n${r.output}\n(exit ${r.code})`;
    $("apply").disabled = !r.plan;
  });
}

function apply() {
  $("apply").disabled = true;
  $("plan-text").textContent += "\n\napplying…";
  send({ cmd: "apply", plan: state.plan }, (reply) => {
    if (reply.type !== "done") { $("plan-text").textContent += `\nrefused: ${reply.why}`; return; }
    const r = reply.result;
    $("plan-text").textContent = `$ ${r.command}\n${r.output}\n(exit ${r.code})`;
  });
}

$("operation").addEventListener("change", showParameters);
$("call-form").addEventListener("submit", callOperation);
$("set-form").addEventListener("submit", setProperty);
// A changed model from the page: sent over HTTP (a model is larger than a WebSocket message may
// be), with the token in a header; the server plans it as "Plan the update" does.
const MAX_MODEL = 2 * 1024 * 1024;
$("model-file").addEventListener("change", () => {
  const file = $("model-file").files[0];
  if (file) $("model-name").value = file.name;
});
async function planUpload() {
  const file = $("model-file").files[0];
  const body = file ? await file.arrayBuffer() : new TextEncoder().encode($("model-text").value);
  $("plan-text").hidden = false;
  $("apply").disabled = true;
  if (body.byteLength > MAX_MODEL) { $("plan-text").textContent = `refused: a model of more than ${MAX_MODEL} bytes`; return; }
  $("plan-text").textContent = `planning ${$("model-name").value} (acordcs-gen update --dry-run)…`;
  let reply;
  try {
    const response = await fetch("/model", { method: "POST", body, headers: { "X-Acordcs-Token": token || "", "X-Acordcs-Model-Name": $("model-name").value } });
    reply = await response.json();
  } catch (err) { $("plan-text").textContent = `the console did not answer: ${err}`; return; }
  if (reply.type === "refused") { $("plan-text").textContent = `refused: ${reply.why} (${reply.todo})`; return; }
  state.plan = reply.plan;
  $("update-model").textContent = `model: ${reply.model} (sent from this page)`;
  $("plan").disabled = false;
  $("plan-text").textContent = `$ ${reply.command}\n${reply.output}\n(exit ${reply.code})`;
  $("apply").disabled = !reply.plan;
}
$("plan-upload").addEventListener("click", planUpload);
$("plan").addEventListener("click", plan);
$("apply").addEventListener("click", apply);
setInterval(drawPlots, 250);
connect();
// A link opened in a tab that shows the console already changes only the fragment: take its
// token and connect again with it.
window.addEventListener("hashchange", () => {
  if (!new URLSearchParams(location.hash.slice(1)).has("token")) return;
  token = takeToken();
  const old = state.socket;
  (panels.handlers.get("disconnected") || []).forEach((fn) => fn());
  connect();
  if (old) old.close();
});
