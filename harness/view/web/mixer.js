// The n-gon light mixer of Bergner et al. 2002 §3.3, exactly as spectral/light_mixer.cpp
// computes it: each lit node weighs 1/d^p, normalised to sum 1; a handle on a lit node (within
// 1e-9) selects that light alone; a node that is off keeps its place and weighs 0.
"use strict";

function mixerWeights(nodes, x, y, power) {
  const w = nodes.map(() => 0);
  for (let i = 0; i < nodes.length; ++i) {
    if (nodes[i].on && Math.hypot(nodes[i].x - x, nodes[i].y - y) < 1e-9) {
      w[i] = 1;
      return w;
    }
  }
  let sum = 0;
  for (let i = 0; i < nodes.length; ++i) {
    if (!nodes[i].on) continue;
    w[i] = 1 / Math.pow(Math.hypot(nodes[i].x - x, nodes[i].y - y), power);
    sum += w[i];
  }
  if (sum === 0) return w;  // every light off: a dark mix
  return w.map((v) => v / sum);
}

// n nodes on the unit circle, node 0 at the top, counter-clockwise (LightMixer::regularPolygon).
function regularPolygon(n) {
  const nodes = [];
  for (let i = 0; i < n; ++i) {
    const a = Math.PI / 2 + 2 * Math.PI * i / n;
    nodes.push({x: Math.cos(a), y: Math.sin(a), on: true});
  }
  return nodes;
}
