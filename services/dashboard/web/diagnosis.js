"use strict";
// Stored diagnoses (docs/diagnosis.md, "Stored diagnoses"): the list with state, verdict and
// progress, and one diagnosis: its facts, live while it runs (stage and progress every
// second), then its report (report.js).
(() => {
  const { api, poll, num, el, cells, fact, stateName, stateBadge, when } = GF;

  const path = (id) => "/api/diagnoses/" + encodeURIComponent(id);
  const running = (d) => stateName(d.state) === "running";

  // "screening: 1/2 fits done, 20/32 evaluations, ETA 0m04s", or why it stopped.
  function progressText(d) {
    if (!running(d)) return d.error || "";
    if (!d.stage) return "no progress yet (starting, or run by another coordinator)";
    return d.progress.startsWith(d.stage) ? d.progress : `${d.stage}: ${d.progress}`;
  }

  function diagnosisRow(d) {
    const spec = d.spec || {};
    const tr = el("tr", { class: "link", "data-diagnosis": d.diagnosis_id });
    cells(tr, [el("td", { class: "l" }, el("a", { href: "#/diagnosis/" + encodeURIComponent(d.diagnosis_id) }, d.diagnosis_id)),
      el("td", { class: "l" }, spec.name || ""), el("td", { class: "l" }, spec.robot || ""),
      el("td", { class: "l" }, stateBadge(d.state)), el("td", { class: "l verdict" }, d.verdict || ""),
      el("td", { class: d.error ? "reason" : "l" }, progressText(d)), when(d.created_ms), when(d.updated_ms)]);
    tr.addEventListener("click", (ev) => {
      if (ev.target.tagName !== "A") location.hash = "#/diagnosis/" + encodeURIComponent(d.diagnosis_id);
    });
    return tr;
  }

  GF.views.diagnoses = {
    render(root, _params, alive) {
      const tbody = el("tbody");
      root.append(el("section", {}, el("h1", {}, "Diagnoses"),
        el("table", { id: "diagnoses" },
          el("thead", {}, el("tr", {}, ...["diagnosis", "name", "robot", "state", "verdict", "progress",
            "created", "updated"].map((h, i) => el("th", i < 6 ? { class: "l" } : {}, h)))),
          tbody)));
      poll(async () => {
        const list = (await api("/api/diagnoses")).diagnoses || [];
        tbody.replaceChildren(...list.slice().reverse().map(diagnosisRow));
        if (!list.length)
          tbody.append(el("tr", {}, el("td", { class: "l muted", colspan: 8 },
            "No diagnosis yet: gaitforge diagnose SPEC.yaml starts one.")));
        return list.some(running) ? 1000 : 2000;
      }, 1000, alive);
    },
  };

  function skeleton(root, id) {
    const s = {
      title: el("h1", {}, id),
      facts: el("div", { class: "facts", id: "diagnosis-facts" }),
      bar: el("progress", { max: "1", value: "0" }),
      line: el("span", { id: "diagnosis-progress" }),
      pending: el("p", { class: "muted" }, "The report appears here when the diagnosis completes."),
      verdict: el("section", { id: "verdict", hidden: "" }),
      effects: el("section", { id: "effects", hidden: "" }),
      figures: el("section", { id: "figures", hidden: "" }),
      candidates: el("section", { id: "candidates-section", hidden: "" }),
    };
    s.progress = el("div", { class: "progress" }, s.bar, " ", s.line);
    root.append(el("section", {}, s.title, s.facts, s.progress, s.pending),
      s.verdict, s.effects, s.figures, s.candidates);
    return s;
  }

  function showFacts(s, d) {
    const spec = d.spec || {};
    s.title.textContent = `${spec.name} (${d.diagnosis_id})`;
    const items = [fact("state", stateBadge(d.state)), fact("robot", spec.robot || "–"),
      fact("recordings", `${(spec.training || []).length} training, ${(spec.held_out || []).length} held out`),
      fact("candidates", (spec.candidates || []).join(", ") || "the whole catalog"),
      fact("created", when(d.created_ms)), fact("updated", when(d.updated_ms))];
    if (d.verdict) items.push(fact("verdict", d.verdict));
    if (d.error) items.push(fact("error", d.error, { class: "invalid" }));
    s.facts.replaceChildren(...items);
    s.progress.hidden = !running(d);
    s.bar.value = Math.min(1, Math.max(0, num(d.fraction) || 0));
    s.line.textContent = progressText(d);
    s.pending.hidden = !running(d);
  }

  GF.views.diagnosis = {
    nav: "diagnoses",
    render(root, [id], alive) {
      const s = skeleton(root, id);
      let shown = null;  // the updated_ms whose report is on the page
      poll(async () => {
        const g = await api(path(id));
        const d = g.diagnosis || {};
        showFacts(s, d);
        if (g.report_error) throw new Error(g.report_error);
        if (g.report && shown !== d.updated_ms) {
          shown = d.updated_ms;
          GFReport.show(s, path(id), g.report, g.files || []);
        }
        // Once it has ended it changes no more: look again rarely.
        return running(d) ? 1000 : 5000;
      }, 1000, alive);
    },
  };
})();
