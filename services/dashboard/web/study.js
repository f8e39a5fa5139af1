"use strict";
// One study, live: its facts, the fitness curve (uPlot), the hall of fame with each gait's
// diagram, the per-generation history with invalid counts and reasons, and the members of
// a generation on demand. Polls progress every second while the study runs and fetches
// only what changed (history?since=N; ETags make unchanged answers empty 304s).
(() => {
  const { api, poll, fmt, num, el, cells, fact, stateName, stateBadge, clock, duration } = GF;

  function skeleton(root, id) {
    const s = {
      title: el("h1", {}, id),
      facts: el("div", { class: "facts", id: "facts" }),
      curve: el("div", { id: "curve", "data-points": "0" }),
      hofNote: el("p", { class: "muted" }, "No generation committed yet."),
      hof: el("div", { class: "hof", id: "hof" }),
      history: el("tbody"),
      members: el("section", { id: "members", hidden: "" }),
    };
    root.append(
      el("section", {}, s.title, s.facts),
      el("section", {}, el("h2", {}, "Fitness per generation"), s.curve),
      el("section", {}, el("h2", {}, "Hall of fame"), s.hofNote, s.hof),
      el("section", {}, el("h2", {}, "History ", el("span", { class: "muted" },
        "(click a generation for its members)")),
        el("div", { class: "scroll" }, el("table", { id: "history" },
          el("thead", {}, el("tr", {}, ...["generation", "best", "mean", "stddev", "diversity",
            "evaluations", "invalid", "commonest invalid reason", "lease expiries", "committed"]
            .map((h) => el("th", h.includes("reason") ? { class: "l" } : {}, h)))),
          s.history))),
      s.members);
    return s;
  }

  function showFacts(s, study, p, robot) {
    const spec = study.spec || {};
    const o = spec.objective || {};
    s.title.textContent = `${spec.name} (${study.study_id})`;
    const items = [fact("state", stateBadge(p.state)),
      fact("generation", `${p.generations_done} / ${p.generations_total}`),
      fact("best", fmt(p.best)), fact("mean", fmt(p.mean)),
      fact("evaluations", fmt(p.evaluations)),
      fact("engine", spec.engine), fact("objective", o.name),
      fact("robot", robot.robot || "none"), fact("population", spec.population)];
    if (stateName(p.state) === "running")
      items.push(fact("rate", fmt(p.evals_per_second, 3) + " ev/s"), fact("ETA", duration(p.eta_seconds)));
    items.push(fact("invalid (latest generation)", num(p.invalid) > 0
      ? `${p.invalid} (${p.invalid_reason || "no reason given"})` : "0",
    { id: "invalid", class: num(p.invalid) > 0 ? "invalid" : "" }));
    if (p.stop_reason) items.push(fact("stopped", p.stop_reason));
    if (p.error) items.push(fact("error", p.error, { class: "invalid" }));
    s.facts.replaceChildren(...items);
  }

  function makeChart(s) {
    const data = [[], [], []];
    const opts = {
      width: Math.max(300, s.curve.clientWidth || 800), height: 280,
      scales: { x: { time: false } },
      // Generations are whole numbers: no tick between two of them.
      axes: [{ label: "generation", incrs: [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000] },
        { label: "fitness" }],
      series: [{ label: "generation" },
        { label: "best", stroke: "#c0392b", width: 2 },
        { label: "mean", stroke: "#2e6fd8", width: 1.5 }],
    };
    const plot = new uPlot(opts, data, s.curve);
    window.addEventListener("resize", () => plot.setSize({ width: Math.max(300, s.curve.clientWidth), height: 280 }));
    return { data, plot };
  }

  // NaN (a generation with no valid member) is a gap in the curve.
  const point = (x) => (Number.isFinite(num(x)) ? num(x) : null);

  function addGenerations(s, chart, gens, onPick) {
    for (const g of gens) {
      chart.data[0].push(g.generation);
      chart.data[1].push(point(g.best));
      chart.data[2].push(point(g.mean));
      const tr = el("tr", { class: "link", "data-generation": g.generation });
      cells(tr, [g.generation, fmt(g.best), fmt(g.mean), fmt(g.stddev, 4), fmt(g.diversity, 4),
        g.evaluations, el("td", num(g.invalid) > 0 ? { class: "invalid" } : {}, g.invalid),
        el("td", { class: "reason" }, g.invalid_reason || ""), fmt(g.lease_expiries),
        clock(g.committed_unix_ms)]);
      tr.addEventListener("click", () => onPick(g.generation));
      s.history.prepend(tr);  // newest first
    }
    chart.plot.setData(chart.data);
    s.curve.dataset.points = String(chart.data[0].length);
  }

  function showHallOfFame(s, hof, study, robot) {
    const bounds = (study.spec || {}).bounds || [];
    s.hofNote.textContent = `After generation ${hof.generation}: ${(hof.entries || []).length} members.`;
    s.hof.replaceChildren(...(hof.entries || []).map((e) => {
      const ind = e.individual || {};
      const ev = ind.evaluation || {};
      return el("div", { class: "gait", "data-rank": e.rank },
        el("div", { class: "head" }, el("b", {}, `#${e.rank}`),
          ` fitness ${ev.valid ? fmt(ev.fitness) : "invalid"}, from generation ${ind.generation} member ${ind.member}`),
        GFGait.diagram(robot.controller, bounds, ind.genes || []));
    }));
  }

  async function showMembers(s, id, generation) {
    const r = await api(`/api/studies/${encodeURIComponent(id)}/individuals?generation=${generation}`);
    const body = el("tbody");
    for (const m of r.individuals || []) {
      const ev = m.evaluation || {};
      const tr = el("tr");
      cells(tr, [m.member, ev.valid ? "yes" : el("td", { class: "invalid" }, "no"), fmt(ev.fitness),
        m.carried ? "carried" : "", el("td", { class: "l" }, m.worker_id || ""), fmt(m.eval_seconds, 3),
        el("td", { class: "reason" }, ev.reason || ""),
        el("td", { class: "l" }, (m.genes || []).map((x) => fmt(x, 4)).join(" "))]);
      body.append(tr);
    }
    s.members.replaceChildren(el("h2", {}, `Members of generation ${generation}`),
      el("div", { class: "scroll" }, el("table", {}, el("thead", {}, el("tr", {},
        ...["member", "valid", "fitness", "", "worker", "seconds", "reason", "genes"].map((h) =>
          el("th", ["worker", "reason", "genes"].includes(h) ? { class: "l" } : {}, h)))), body)));
    s.members.hidden = false;
    s.members.scrollIntoView({ behavior: "smooth" });
  }

  GF.views.study = {
    nav: "studies",
    render(root, [id], alive) {
      const s = skeleton(root, id);
      const base = `/api/studies/${encodeURIComponent(id)}`;
      let study = null, robot = null, chart = null, have = 0;
      const pick = (g) => showMembers(s, id, g).catch(GF.showError);
      poll(async () => {
        if (!study) {
          [study, robot] = await Promise.all([api(base), api(base + "/robot")]);
          chart = makeChart(s);
        }
        const p = await api(base + "/progress");
        showFacts(s, study, p, robot);
        if (num(p.generations_done) > have) {
          const h = await api(`${base}/history?since=${have}`);
          const gens = (h.generations || []).filter((g) => g.generation >= have);
          addGenerations(s, chart, gens, pick);
          if (gens.length) have = gens[gens.length - 1].generation + 1;
          showHallOfFame(s, await api(base + "/hall-of-fame"), study, robot);
        }
        // A study that is over changes no more: look again rarely.
        return stateName(p.state) === "running" ? 1000 : 5000;
      }, 1000, alive);
    },
  };
})();
