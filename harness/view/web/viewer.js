// The svr view page (issue 20, docs/viewer.md): the light-independent image of the current view,
// relit on every change of the light dial, the sliders or the brightness; orbit by drag and zoom
// by wheel, each a new render from the server (a quarter-size frame first, then full size).
// With window.SVR_EMBEDDED (svr render --html) it runs from one file with no server and a
// fixed camera. window.svr exposes the state and a few actions for tests and scripts.
// Loaded last, after page_state.js, frame.js, relighting.js, weights.js, dial.js, views.js,
// fragment.js and controls.js (index.html's order): the start, and window.svr.
"use strict";

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
