// The svr view page (issue 20, docs/viewer.md): the light-independent image of the current view,
// relit on every change of the light dial, the sliders or the brightness; orbit by drag and zoom
// by wheel, each a new render from the server (a quarter-size frame first, then full size).
// With window.SVR_EMBEDDED (svr render --html) it runs from one file with no server and a
// fixed camera. window.svr exposes the state and a few actions for tests and scripts.
"use strict";

(() => {
const $ = (id) => document.getElementById(id);
const embedded = window.SVR_EMBEDDED || null;
const SVG = "http://www.w3.org/2000/svg";
const SNAP = 0.06;  // dial units: a handle dropped this close to a lit node snaps onto it

const state = {
  info: null,
  lights: [],      // {name, matrix: 3 × P, library: bool}
  nodes: [],       // {x, y, on}: the dial's light nodes
  handle: {x: 0, y: 0},
  weights: [],     // per light, from the dial or (custom) the sliders
  custom: false,   // the weights were set by the sliders, not the dial
  brightness: 1,
  view: {azimuth: 0, elevation: 0, zoom: 1},
  size: null,      // {width, height} of the full frame
  nodesMoved: false,
};
const stats = {relights: [], lastView: null, frames: 0};
let relighter = null;

function message(text) { $("message").textContent = text || ""; }

// ---- the frame: "SVRI", uint32 n, n bytes of JSON, then the half-float planes ----
function parseFrame(buffer) {
  const bytes = new Uint8Array(buffer);
  if (bytes.length < 8 || String.fromCharCode(...bytes.subarray(0, 4)) !== "SVRI")
    throw new Error("not an svr frame");
  const n = new DataView(buffer).getUint32(4, true);
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(8, 8 + n)));
  const planes = header.channels + header.t_channels;
  const count = planes * header.width * header.height;
  const half = header.samples === "half";
  if (8 + n + (half ? 2 : 4) * count > buffer.byteLength) throw new Error("frame is truncated");
  return {...header, planes, data: half ? new Uint16Array(buffer, 8 + n, count) : new Float32Array(buffer, 8 + n, count)};
}

function base64ToBuffer(text) {
  const s = atob(text), out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out.buffer;
}

// ---- relighting ----
function mixedMatrix() {
  const P = state.info.channels + state.info.t_channels;
  const m = [new Array(P).fill(0), new Array(P).fill(0), new Array(P).fill(0)];
  state.lights.forEach((light, i) => {
    const w = state.weights[i] * state.brightness;
    if (w === 0) return;
    for (let r = 0; r < 3; ++r) for (let p = 0; p < P; ++p) m[r][p] += w * light.matrix[r][p];
  });
  return m;
}

// Everything a weight change redraws (canvas, dial, sliders) is redrawn once per animation
// frame however many changes came in it; the URL fragment at most every 250 ms (browsers
// throttle history updates).
let drawPending = false, dialDirty = false;
function relight() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(() => {
    drawPending = false;
    if (dialDirty) { dialDirty = false; drawDial(); syncSliders(); }
    relightNow();
  });
}

function relightNow() {
  relighter.draw(mixedMatrix());
  const now = performance.now();
  stats.relights.push(now);
  while (stats.relights.length && stats.relights[0] < now - 1000) stats.relights.shift();
  $("fps").textContent = stats.relights.length > 1 ? `${stats.relights.length} (${relighter.kind})` : "–";
}

// Relights the current frame n times back to back, waiting for each: frames per second of the
// relighting alone (the matrix changes every frame, as under a dragged handle).
function benchRelight(n) {
  const t0 = performance.now();
  for (let i = 0; i < n; ++i) {
    const saved = state.brightness;
    state.brightness = saved * (1 + 1e-3 * (i % 2));
    relighter.draw(mixedMatrix());
    state.brightness = saved;
    relighter.finish();
  }
  const seconds = (performance.now() - t0) / 1000;
  relightNow();
  return {fps: n / seconds, width: relighter.frame.width, height: relighter.frame.height, path: relighter.kind};
}

// ---- weights: the dial and the sliders are two views of them ----
function dialWeights() {
  state.weights = mixerWeights(state.nodes, state.handle.x, state.handle.y, state.info.mixer_power);
  state.custom = false;
}

function weightsChanged() {
  dialDirty = true;
  relight();
  saveFragment();
}

function setHandle(x, y) {
  for (const node of state.nodes) {  // snap onto a lit node, so a light can be picked alone
    if (node.on && Math.hypot(node.x - x, node.y - y) < SNAP) { x = node.x; y = node.y; break; }
  }
  state.handle = {x, y};
  dialWeights();
  weightsChanged();
}

function toggleLight(i) {
  state.nodes[i].on = !state.nodes[i].on;
  if (state.custom) { if (!state.nodes[i].on) state.weights[i] = 0; }
  else dialWeights();
  weightsChanged();
}

function setWeight(i, w) {
  state.weights[i] = state.nodes[i].on ? w : 0;
  state.custom = true;
  weightsChanged();
}

function setWeights(ws) {
  state.weights = ws.map((w, i) => (state.nodes[i].on ? w : 0));
  state.custom = true;
  weightsChanged();
}

function buildSliders() {
  const box = $("sliders");
  box.textContent = "";
  state.lights.forEach((light, i) => {
    const row = document.createElement("label");
    row.className = "row";
    const name = document.createElement("span");
    name.className = "name";
    name.textContent = light.name;
    name.title = light.name;
    const input = document.createElement("input");
    Object.assign(input, {type: "range", min: 0, max: 1, step: 0.001, id: `weight-${i}`});
    const out = document.createElement("output");
    out.id = `weight-value-${i}`;
    input.addEventListener("input", () => setWeight(i, Number(input.value)));
    row.append(name, input, out);
    box.append(row);
  });
  syncSliders();
}

function syncSliders() {
  state.lights.forEach((_, i) => {
    const input = $(`weight-${i}`);
    if (!input) return;
    input.value = String(state.weights[i]);
    input.disabled = !state.nodes[i].on;
    $(`weight-value-${i}`).textContent = state.weights[i].toFixed(3);
  });
  $("brightness").value = String(state.brightness);
  $("brightness-value").textContent = state.brightness.toFixed(2);
  $("mix-kind").textContent = state.custom ? "custom mix (set by the sliders; drag the handle to mix by the dial)"
                                           : "mix by the dial: weight ∝ 1/distance²";
}

// ---- the dial (SVG, y up as in the mixer's plane) ----
function drawDial() {
  const svg = $("dial");
  svg.textContent = "";
  const el = (name, attrs) => {
    const e = document.createElementNS(SVG, name);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    svg.append(e);
    return e;
  };
  if (state.nodes.length > 1)
    el("polygon", {class: "outline", points: state.nodes.map((n) => `${n.x},${-n.y}`).join(" ")});
  state.nodes.forEach((n, i) => {
    const c = el("circle", {class: n.on ? "node" : "node off", cx: n.x, cy: -n.y, r: 0.09, "data-node": i});
    c.append(Object.assign(document.createElementNS(SVG, "title"), {textContent: `${state.lights[i].name}: drag to move, click to switch ${n.on ? "off" : "on"}`}));
    const t = el("text", {class: "label", x: n.x, y: -n.y - 0.13});
    t.textContent = state.lights[i].name;
  });
  el("circle", {class: state.custom ? "handle custom" : "handle", cx: state.handle.x, cy: -state.handle.y, r: 0.06, id: "dial-handle"});
}

function dialPoint(event) {
  const svg = $("dial"), p = svg.createSVGPoint();
  p.x = event.clientX; p.y = event.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  return {x: q.x, y: -q.y};
}

// Client coordinates of a point of the dial's plane (for tests driving the mouse).
function dialToClient(x, y) {
  const svg = $("dial"), p = svg.createSVGPoint();
  p.x = x; p.y = -y;
  const q = p.matrixTransform(svg.getScreenCTM());
  return {x: q.x, y: q.y};
}

function wireDial() {
  const svg = $("dial");
  let drag = null;
  svg.addEventListener("pointerdown", (e) => {
    const node = e.target.getAttribute && e.target.getAttribute("data-node");
    svg.setPointerCapture(e.pointerId);
    drag = node !== null && node !== undefined
        ? {kind: "node", index: Number(node), x: e.clientX, y: e.clientY, moved: false}
        : {kind: "handle"};
    if (drag.kind === "handle") { const p = dialPoint(e); setHandle(p.x, p.y); }
  });
  svg.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const p = dialPoint(e);
    if (drag.kind === "handle") return setHandle(p.x, p.y);
    if (Math.hypot(e.clientX - drag.x, e.clientY - drag.y) > 3) drag.moved = true;
    if (!drag.moved) return;
    Object.assign(state.nodes[drag.index], {x: p.x, y: p.y});
    state.nodesMoved = true;
    if (!state.custom) dialWeights();
    weightsChanged();
  });
  const end = () => {
    if (drag && drag.kind === "node" && !drag.moved) toggleLight(drag.index);
    drag = null;
  };
  svg.addEventListener("pointerup", end);
  svg.addEventListener("pointercancel", () => { drag = null; });
}

// ---- views: orbit by drag, zoom by wheel; a quarter-size frame first, then full size ----
// While an orbit drag is held only quarter-size frames are asked for, one at a time, each for the
// newest view: a full frame between two mouse moves would hold the renderer for the next one.
// The full frame follows when the drag ends, or at once for a wheel step or a set view.
let quarterInFlight = false, fullAbort = null, pendingView = null, viewStarted = 0;
let interacting = false;

function renderUrl(view, scale) {
  const w = Math.max(1, Math.round(state.size.width / scale)), h = Math.max(1, Math.round(state.size.height / scale));
  return `api/render?azimuth=${view.azimuth}&elevation=${view.elevation}&zoom=${view.zoom}&width=${w}&height=${h}&samples=${state.samples}`;
}

async function fetchFrame(view, scale, signal) {
  const res = await fetch(renderUrl(view, scale), {signal});
  if (res.status === 409) return null;  // superseded by a newer view
  if (!res.ok) throw new Error((await res.json()).error || `HTTP ${res.status}`);
  return parseFrame(await res.arrayBuffer());
}

function showFrame(frame, kind) {
  relighter.setFrame(frame);
  relightNow();
  stats.frames++;
  const ms = performance.now() - viewStarted;
  stats.lastView = {...(stats.lastView || {}), [kind]: ms, render_ms: frame.render_ms, width: frame.width, height: frame.height};
  $("render-ms").textContent = `${ms.toFixed(0)} (${kind}, ${frame.width}×${frame.height}, render ${frame.render_ms.toFixed(0)})`;
  $("status").textContent = `azimuth ${state.view.azimuth.toFixed(1)}°, elevation ${state.view.elevation.toFixed(1)}°, zoom ${state.view.zoom.toFixed(2)}`;
}

function viewChanged() {
  pendingView = {...state.view};
  viewStarted = performance.now();
  stats.lastView = null;
  if (fullAbort) { fullAbort.abort(); fullAbort = null; }
  saveFragment();
  pump();
}

async function pump() {
  if (quarterInFlight || !pendingView) return;
  const view = pendingView;
  pendingView = null;
  quarterInFlight = true;
  try {
    const quarter = await fetchFrame(view, 4);
    if (quarter) showFrame(quarter, "quarter");
  } catch (e) { message(`render: ${e.message}`); }
  quarterInFlight = false;
  if (pendingView) return pump();  // still dragging: the newest view's quarter frame next
  if (!interacting) requestFull(view);
}

async function requestFull(view) {
  const abort = new AbortController();
  fullAbort = abort;
  try {
    const full = await fetchFrame(view, 1, abort.signal);
    if (fullAbort === abort && full) showFrame(full, "full");
  } catch (e) { if (e.name !== "AbortError") message(`render: ${e.message}`); }
  if (fullAbort === abort) fullAbort = null;
}

function wireOrbit() {
  const canvas = $("image");
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    canvas.setPointerCapture(e.pointerId);
    drag = {x: e.clientX, y: e.clientY, view: {...state.view}, moved: false};
    interacting = true;
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    drag.moved = true;
    state.view.azimuth = drag.view.azimuth - 0.5 * (e.clientX - drag.x);
    state.view.elevation = Math.min(89, Math.max(-89, drag.view.elevation + 0.5 * (e.clientY - drag.y)));
    viewChanged();
  });
  const release = () => {
    const moved = drag && drag.moved;
    drag = null;
    interacting = false;
    // The quarter frame of the last view may still be on its way; pump asks for the full one
    // after it. Otherwise ask now.
    if (moved && !quarterInFlight && !pendingView) requestFull({...state.view});
  };
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    state.view.zoom = Math.min(50, Math.max(0.05, state.view.zoom * Math.exp(-0.001 * e.deltaY)));
    viewChanged();
  }, {passive: false});
}

// ---- the URL fragment: view, size, weights, dial and added lights ----
const round = (v) => Number(v.toFixed(6));
let fragmentTimer = null;
function saveFragment() {
  if (embedded || fragmentTimer) return;
  fragmentTimer = setTimeout(() => { fragmentTimer = null; writeFragment(); }, 250);
}

function writeFragment() {
  const f = new URLSearchParams();
  f.set("view", [state.view.azimuth, state.view.elevation, state.view.zoom].map(round).join(","));
  f.set("size", `${state.size.width}x${state.size.height}`);
  f.set("handle", `${round(state.handle.x)},${round(state.handle.y)}`);
  f.set("brightness", String(round(state.brightness)));
  const added = state.lights.filter((l) => l.library).map((l) => l.name);
  if (added.length) f.set("add", added.join(","));
  const off = state.nodes.map((n, i) => (n.on ? -1 : i)).filter((i) => i >= 0);
  if (off.length) f.set("off", off.join(","));
  if (state.nodesMoved) f.set("nodes", state.nodes.map((n) => `${round(n.x)}:${round(n.y)}`).join(","));
  if (state.custom) f.set("weights", state.weights.map(round).join(","));
  history.replaceState(null, "", "#" + f.toString());
}

async function restoreFragment() {
  const f = new URLSearchParams(location.hash.slice(1));
  const numbers = (key) => (f.get(key) || "").split(",").filter((s) => s !== "").map(Number);
  for (const name of (f.get("add") || "").split(",").filter(Boolean)) await addLight(name, false);
  const v = numbers("view");
  if (v.length === 3 && v.every(Number.isFinite)) state.view = {azimuth: v[0], elevation: v[1], zoom: v[2]};
  const size = /^(\d+)x(\d+)$/.exec(f.get("size") || "");
  if (size) state.size = {width: Number(size[1]), height: Number(size[2])};
  const nodes = (f.get("nodes") || "").split(",").filter(Boolean).map((s) => s.split(":").map(Number));
  if (nodes.length === state.nodes.length && nodes.flat().every(Number.isFinite)) {
    nodes.forEach(([x, y], i) => Object.assign(state.nodes[i], {x, y}));
    state.nodesMoved = true;
  }
  for (const i of numbers("off")) if (state.nodes[i]) state.nodes[i].on = false;
  const h = numbers("handle");
  if (h.length === 2 && h.every(Number.isFinite)) state.handle = {x: h[0], y: h[1]};
  const b = Number(f.get("brightness"));
  if (f.has("brightness") && Number.isFinite(b) && b >= 0) state.brightness = b;
  dialWeights();
  const w = numbers("weights");
  if (w.length === state.lights.length && w.every((x) => Number.isFinite(x) && x >= 0)) {
    state.weights = w.map((x, i) => (state.nodes[i].on ? x : 0));
    state.custom = true;
  }
}

// ---- lights from the library, mixes into the scene file, PNG ----
async function addLight(name, announce = true) {
  const res = await fetch(`api/light?name=${encodeURIComponent(name)}`);
  const body = await res.json();
  if (!res.ok) { message(body.error); return false; }
  state.lights.push({...body, library: true});
  const on = state.nodes.map((n) => n.on);
  if (!state.nodesMoved) {
    state.nodes = regularPolygon(state.lights.length);
    on.forEach((o, i) => { state.nodes[i].on = o; });
  } else {
    const a = Math.PI / 2 + 2 * Math.PI * (state.lights.length - 1) / state.lights.length;
    state.nodes.push({x: Math.cos(a), y: Math.sin(a), on: true});
  }
  state.weights.push(0);
  if (!state.custom) dialWeights();
  buildSliders();
  if (announce) { weightsChanged(); message(""); }
  return true;
}

async function saveMix(name) {
  const weights = {};
  state.lights.forEach((l, i) => { if (state.weights[i] > 0) weights[l.name] = round(state.weights[i] * state.brightness); });
  const res = await fetch(`api/mixes?name=${encodeURIComponent(name)}`, {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify({weights})});
  const body = await res.json();
  message(res.ok ? "" : body.error);
  if (res.ok) $("status").textContent = `saved mix '${body.saved}' in ${body.file}`;
  return res.ok;
}

function savePng() {
  relightNow();
  relighter.canvas.toBlob((blob) => {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = "svr-view.png";
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }, "image/png");
}

function wireControls() {
  $("brightness").addEventListener("input", (e) => { state.brightness = Number(e.target.value); weightsChanged(); });
  $("save-png").addEventListener("click", savePng);
  const mixes = $("scene-mixes");
  for (const mix of state.info.mixes) mixes.append(Object.assign(document.createElement("option"), {value: mix.name, textContent: mix.name}));
  mixes.addEventListener("change", () => {
    const mix = state.info.mixes.find((m) => m.name === mixes.value);
    if (mix) setWeights(state.lights.map((_, i) => mix.weights[i] || 0));
  });
  $("add-light").addEventListener("submit", (e) => { e.preventDefault(); addLight($("light-name").value.trim()); });
  $("save-mix").addEventListener("submit", (e) => { e.preventDefault(); saveMix($("mix-name").value.trim()); });
  if (embedded || state.info.read_only) $("save-mix").hidden = true;
  if (embedded) {
    $("add-light").hidden = true;
    $("image").classList.add("static");
    $("status").textContent = "fixed camera (svr render --html): the light dial, the sliders and relighting work offline";
  } else {
    wireOrbit();
  }
}

async function start() {
  state.info = embedded ? embedded.info : await (await fetch("api/scene")).json();
  const info = state.info;
  $("scene-name").textContent = info.scene.split("/").pop();
  $("model").textContent = `${info.model.name} (k = ${info.model.k}: ${info.model.description}), ${info.renderer}; ${info.samples} samples (half rounding: ${info.half_code_error} code values)`;
  state.lights = info.lights.map((l) => ({...l, library: false}));
  state.nodes = regularPolygon(state.lights.length);
  state.view = {...info.view};
  state.size = {width: info.width, height: info.height};
  // Half samples unless the server measured that their rounding shows under this scene's
  // lights (info.half_code_error); ?samples=half|float overrides.
  state.samples = new URLSearchParams(location.search).get("samples") || info.samples;
  const path = new URLSearchParams(location.search).get("relight") || "auto";
  relighter = new Relighter($("image"), path);
  dialWeights();
  if (!embedded) await restoreFragment();
  buildSliders();
  wireDial();
  wireControls();
  drawDial();
  const canvas = $("image");
  canvas.style.width = `${state.size.width}px`;
  canvas.style.height = `${state.size.height}px`;
  if (embedded) {
    showFrame(parseFrame(base64ToBuffer(embedded.frame)), "full");
  } else {
    viewChanged();
    await new Promise((resolve) => {
      const wait = () => (stats.lastView && stats.lastView.full ? resolve() : setTimeout(wait, 10));
      wait();
    });
  }
  saveFragment();
}

window.svr = {
  state, stats, setHandle, toggleLight, setWeight, setWeights, addLight, saveMix, benchRelight,
  dialToClient, mixerWeights, regularPolygon,
  pixels: () => { relightNow(); return relighter.pixels(); },  // the canvas for the current state
  relighterKind: () => relighter.kind,
  softwareWebGL: () => relighter.software,
  setView: (view) => { Object.assign(state.view, view); viewChanged(); },
  // Resolves once the pending redraw of dial and sliders is done and the fragment is written.
  // One relight with a slightly different brightness and nothing else redrawn (for timing).
  relightOnly: (i) => { const b = state.brightness; state.brightness = b * (1 + 1e-3 * (i % 2)); relightNow(); state.brightness = b; },
  settled: () => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(() => {
    if (fragmentTimer) { clearTimeout(fragmentTimer); fragmentTimer = null; writeFragment(); }
    resolve();
  }))),
  ready: start().catch((e) => { message(e.message); throw e; }),
};
})();
