// Views: orbit by drag, zoom by wheel, each a new render from the server; a quarter-size frame
// first, then full size.
"use strict";

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
