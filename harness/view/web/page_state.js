// The page's state (svr view, harness/view/web/): what the page shows and how it is lit, shared
// by the page's scripts, which load in order as classic scripts and share their top-level names.
"use strict";

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
