// The lights' weights: the dial and the sliders are two views of them.
"use strict";

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
