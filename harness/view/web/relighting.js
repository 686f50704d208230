// Relighting the current frame under the mixed light, once per animation frame.
"use strict";

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
