// The n-gon dial (SVG, y up as in the mixer's plane).
"use strict";

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
