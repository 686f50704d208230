// Lights from the library, mixes saved into the scene file, the PNG, and the buttons that ask.
"use strict";

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
