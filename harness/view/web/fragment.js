// The URL fragment: view, size, weights, dial and added lights, so a link restores the page.
"use strict";

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
