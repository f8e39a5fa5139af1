"use strict";
// A genotype drawn as a gait, in SVG, from the robot's controller as its descriptor states
// it (GET /api/studies/ID/robot): the kind says how genes become actuator commands, the
// actuators and gene names come from the descriptor. One drawing per controller kind
// (robots/controllers.cc); genes of no robot (analytic objectives) as positions within
// their bounds.
const GFGait = (() => {
  const NS = "http://www.w3.org/2000/svg";
  const W = 340, LABEL = 44, ROW = 16;

  function svg(tag, attrs, ...children) {
    const e = document.createElementNS(NS, tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    for (const c of children) e.append(c);
    return e;
  }
  const text = (x, y, s, attrs) => svg("text", { x, y, "font-size": 10, fill: "#1d2330", ...attrs }, s);

  // Gene values by name (the study's bounds name them in order).
  function byName(bounds, genes) {
    const m = {};
    bounds.forEach((b, i) => { m[b.name] = Number(genes[i]); });
    return m;
  }

  // The phase axis under `rows` rows: ticks at 0, 1/4, 1/2, 3/4, 1.
  function phaseAxis(root, rows, caption) {
    const y = rows * ROW + 4, span = W - LABEL - 6;
    for (const f of [0, 0.25, 0.5, 0.75, 1]) {
      const x = LABEL + f * span;
      root.append(svg("line", { x1: x, x2: x, y1: 0, y2: y, stroke: "#dde2ea" }),
        text(x, y + 10, String(f), { "text-anchor": "middle" }));
    }
    root.append(text(W / 2, y + 22, caption, { "text-anchor": "middle", fill: "#6b7485" }));
    return y + 28;
  }

  // phase_onoff (paper 000 Fig. 8): actuator j is ON while the phase lies in [a_j, d_j),
  // wrapping round when d_j < a_j; T is the period.
  function phaseOnOff(c, g) {
    const root = svg("g");
    const span = W - LABEL - 6;
    c.actuators.forEach((a, j) => {
      const on = g["a_" + a] % 1, off = g["d_" + a] % 1, y = j * ROW;
      root.append(text(2, y + 12, a));
      const windows = on === off ? [] : on < off ? [[on, off - on]] : [[on, 1 - on], [0, off]];
      for (const [s, w] of windows)
        root.append(svg("rect", { x: LABEL + s * span, y: y + 3, width: w * span, height: ROW - 6,
          fill: j * 2 < c.actuators.length ? "#c0392b" : "#2e6fd8", class: "on" }));
    });
    const h = phaseAxis(root, c.actuators.length, `phase of the period T = ${fmtS(g.T)} s: actuator ON`);
    return [root, h];
  }

  // sine (paper 001): actuator j's target is off_j + amp_j sin(2 pi (f t + phase_j)).
  function sine(c, g) {
    const root = svg("g");
    const span = W - LABEL - 6;
    const lim = Math.max(...c.genes.filter((x) => /^(amp|off)_/.test(x.name)).map((x) => Math.abs(x.hi)), 1e-9);
    c.actuators.forEach((a, j) => {
      const y0 = j * ROW * 2 + ROW, amp = g["amp_" + a], off = g["off_" + a], ph = g["phase_" + a];
      const pts = [];
      for (let i = 0; i <= 60; i++) {
        const t = i / 60, v = off + amp * Math.sin(2 * Math.PI * (t + ph));
        pts.push(`${(LABEL + t * span).toFixed(1)},${(y0 - (v / (2 * lim)) * ROW * 1.8).toFixed(1)}`);
      }
      root.append(text(2, y0 + 4, a), svg("line", { x1: LABEL, x2: LABEL + span, y1: y0, y2: y0, stroke: "#eef0f4" }),
        svg("polyline", { points: pts.join(" "), fill: "none", stroke: "#2e6fd8", "stroke-width": 1.5, class: "on" }));
    });
    const h = phaseAxis(root, c.actuators.length * 2, `one cycle at f = ${fmtS(g.f)} Hz: target angle`);
    return [root, h];
  }

  // No controller: each gene's place within its bounds.
  function geneBars(bounds, genes) {
    const root = svg("g");
    const span = W - LABEL - 6, shown = bounds.slice(0, 40);
    shown.forEach((b, i) => {
      const f = (Number(genes[i]) - b.lo) / (b.hi - b.lo || 1), y = i * ROW;
      root.append(text(2, y + 12, b.name.slice(0, 8)),
        svg("rect", { x: LABEL, y: y + 5, width: span, height: ROW - 10, fill: "#eef0f4" }),
        svg("rect", { x: LABEL + Math.min(1, Math.max(0, f)) * span - 2, y: y + 2, width: 4, height: ROW - 4, fill: "#2e6fd8", class: "on" }));
    });
    return [root, shown.length * ROW + 6];
  }

  const fmtS = (x) => (Number.isFinite(x) ? x.toPrecision(3) : "?");
  const kinds = { phase_onoff: phaseOnOff, sine };

  function diagram(controller, bounds, genes) {
    const draw = controller && kinds[controller.kind];
    const [body, height] = draw ? draw(controller, byName(bounds, genes)) : geneBars(bounds, genes);
    const root = svg("svg", { viewBox: `0 0 ${W} ${height}`, class: "diagram",
      "data-kind": draw ? controller.kind : "genes" }, body);
    root.append(svg("title", {}, bounds.map((b, i) => `${b.name} = ${Number(genes[i]).toPrecision(4)}`).join("\n")));
    return root;
  }

  return { diagram };
})();
