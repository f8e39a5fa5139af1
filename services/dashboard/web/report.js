"use strict";
// A completed diagnosis's report (diagnosis.json; its fields in docs/effects.md, "What the
// gap finder reports"), worded as `gaitforge diagnosis ID` words it
// (services/diagnosis/words.cc): the verdict, the errors before and after, where it showed,
// the named effects' fitted parameters with their ranges, the located and before/after
// figures, the candidates and why they lost, the screening, the experiment and the
// corrected model. The fits' study ids open their study pages.
const GFReport = (() => {
  const { file, fmt, num, el, cells, showError } = GF;
  const mm = (m) => fmt(1000 * num(m), 4);  // the report's errors are in metres
  const studyLink = (id) => (id ? el("a", { href: "#/study/" + encodeURIComponent(id), class: "study" }, id) : "–");
  const UNPINNED_SHARE = 0.9;  // services/diagnosis/range.h kUndeterminedShare

  function verdictWords(r) {
    const ids = (r.effects || []).map((e) => e.id).join(" and ");
    if (r.verdict === "found") return `found ${ids}`;
    if (r.verdict === "ambiguous") return `ambiguous between ${ids}`;
    return "no missing physics found";
  }

  function errorsLine(r) {
    const e = r.errors || {};
    if (r.verdict === "none") {
      const rule = r.rule || {};
      return `no candidate beat the baseline by the BIC margin (${fmt(rule.margin)}) and cut its ` +
        `held-out error (${mm(e.baseline_held_out)} mm ± ${fmt(1000 * num(e.noise_floor_held_out), 2)} mm ` +
        `over numerically irrelevant variants) by ${Math.round(100 * num(rule.held_out_gain))}% with a ` +
        `paired t above ${fmt(rule.paired_t)} across the variants; training error ${mm(e.baseline_train)} mm`;
    }
    const first = (r.effects || [])[0] || e;
    return `held-out error ${mm(e.baseline_held_out)} → ${mm(first.held_out)} mm, training ` +
      `${mm(e.baseline_train)} → ${mm(first.train)} mm, ΔBIC ${fmt(first.delta_bic, 4)}`;
  }

  function showVerdict(sec, base, r, files) {
    const p = (label, value, attrs) => el("p", attrs || {}, el("b", {}, label + ": "), value);
    sec.replaceChildren(el("h2", {}, "Verdict"),
      el("p", { class: "verdict-line", id: "verdict-words" }, verdictWords(r)),
      el("p", { id: "errors" }, errorsLine(r)));
    if (r.none_reading) sec.append(p("what the located spread says", r.none_reading, { id: "none-reading" }));
    if (r.numerics_note) sec.append(p("caution", r.numerics_note, { id: "numerics-note" }));
    const where = (r.located || {}).summary;
    if (where) sec.append(p("where it showed", where, { id: "where" }));
    if (r.experiment)
      sec.append(p(r.verdict === "ambiguous" ? "to tell them apart" : "experiment", r.experiment, { id: "experiment" }));
    sec.append(p("corrected model", correctedModelLink(base, files)),
      p("baseline fit (no effect)", studyLink(r.baseline_study_id)));
    sec.hidden = false;
  }

  // A parameter's range in words, as words.cc gives it.
  function rangeWords(name, p, tolerance) {
    if (name.startsWith("nuisance.")) return "(the time offset: not a magnitude)";
    if (!Number.isFinite(num(tolerance)) || !Array.isArray(p.range))
      return "(no range: the model failed under a numeric variant, so no floor)";
    const end = (v) => (Number.isFinite(num(v)) ? fmt(v, 4) : "open");
    let words = `${end(p.range[0])} .. ${end(p.range[1])}`;
    if (num(p.range_share) >= UNPINNED_SHARE)
      words += ` (${Math.round(100 * num(p.range_share))}% of its allowed values: not pinned)`;
    return words;
  }

  function effectTable(e) {
    const body = el("tbody");
    const params = Object.entries(e.params || {}).sort((a, b) => num(a[1].index) - num(b[1].index));
    for (const [name, p] of params) {
      const tr = el("tr", { "data-param": name });
      cells(tr, [el("td", { class: "l" }, name), fmt(p.value, 5), fmt(p.sd, 3),
        el("td", { class: "l" }, rangeWords(name, p, e.range_tolerance)),
        el("td", { class: "l" }, `${fmt(p.lo, 4)} .. ${fmt(p.hi, 4)}`)]);
      body.append(tr);
    }
    const note = Number.isFinite(num(e.range_tolerance))
      ? `range: where the training error stays within ${fmt(1000 * num(e.range_tolerance), 3)} mm of its ` +
        `least, the model's own spread; ${e.range_accepted} of ${e.range_evaluations} evaluations` : "";
    return el("div", { class: "effect", "data-effect": e.id },
      el("h3", {}, e.id, " ", el("span", { class: "muted" }, "fitted in study "), studyLink(e.study_id)),
      // Its name and meaning from the report (a robot's own suspects are in no catalog).
      e.name ? el("p", {}, el("b", {}, e.name), ": ", e.meaning || "") : "",
      el("table", {}, el("thead", {}, el("tr", {}, ...["parameter", "value", "sd", "range", "allowed"]
        .map((h) => el("th", ["parameter", "range", "allowed"].includes(h) ? { class: "l" } : {}, h)))), body),
      el("p", { class: "muted" }, note));
  }

  function showEffects(sec, r) {
    const effects = r.effects || [];
    sec.replaceChildren(el("h2", {}, effects.length > 1 ? "The named effects" : "The named effect"),
      ...effects.map(effectTable));
    sec.hidden = !effects.length;
  }

  // A stored figure, fetched with the token and shown as an image (never inlined: an SVG
  // from the database is data, not page). A failure stays visible in its place.
  function figure(base, name, files, caption) {
    const box = el("figure", {});
    if (!files.includes(name)) {
      box.append(el("p", { class: "muted" }, `No ${name} was kept with this diagnosis.`));
      return box;
    }
    const img = el("img", { id: name.replace(".svg", "-figure"), alt: caption, "data-file": name });
    box.append(img, el("figcaption", { class: "muted" }, `${caption} (${name})`));
    file(`${base}/files/${name}`).then((blob) => {
      const url = URL.createObjectURL(blob);
      img.addEventListener("load", () => URL.revokeObjectURL(url), { once: true });
      img.src = url;
    }).catch((e) => {
      box.append(el("p", { class: "invalid" }, `Could not load ${name}: ${e.message}`));
      showError(e);
    });
    return box;
  }

  // The corrected model as a download of the stored file (fetched with the token).
  function correctedModelLink(base, files) {
    if (!files.includes("corrected-model.yaml")) return "none";
    const a = el("a", { href: "#", id: "corrected-model" }, "corrected-model.yaml");
    a.addEventListener("click", (ev) => {
      ev.preventDefault();
      file(`${base}/files/corrected-model.yaml`).then((blob) => {
        const url = URL.createObjectURL(blob);
        el("a", { href: url, download: "corrected-model.yaml" }).click();
        setTimeout(() => URL.revokeObjectURL(url), 10000);
      }).catch(showError);
    });
    return a;
  }

  function showFigures(sec, base, files) {
    sec.replaceChildren(el("h2", {}, "Figures"),
      figure(base, "located.svg", files, "Where the mismatch lives: the baseline's residuals by slice"),
      figure(base, "diagnosis.svg", files, "Held-out errors and overlays, before and after"));
    sec.hidden = false;
  }

  function candidatesTable(r) {
    const body = el("tbody");
    for (const c of r.runners_up || []) {
      const tr = el("tr", { "data-candidate": c.id });
      cells(tr, [el("td", { class: "l" }, c.id), fmt(c.delta_bic, 4), mm(c.held_out), mm(c.train),
        el("td", { class: "l" }, (c.at_bound || []).join(", ")), el("td", { class: "reason why" }, c.why_not || ""),
        el("td", { class: "l" }, studyLink(c.study_id))]);
      body.append(tr);
    }
    if (!(r.runners_up || []).length)
      body.append(el("tr", {}, el("td", { class: "l muted", colspan: 7 }, "No other candidate was refitted.")));
    return el("table", { id: "candidates" }, el("thead", {}, el("tr", {}, ...["candidate", "ΔBIC",
      "held-out mm", "training mm", "at the edge of its range", "why not", "fit"]
      .map((h) => el("th", ["candidate", "at the edge of its range", "why not", "fit"].includes(h) ? { class: "l" } : {}, h)))), body);
  }

  function screeningTable(r) {
    const body = el("tbody");
    for (const c of r.screening || []) {
      const tr = el("tr", { "data-candidate": c.id });
      cells(tr, [el("td", { class: "l" }, c.id), mm(c.train), el("td", { class: "l" }, studyLink(c.study_id))]);
      body.append(tr);
    }
    return el("table", { id: "screening" }, el("thead", {}, el("tr", {},
      el("th", { class: "l" }, "candidate"), el("th", {}, "training mm (short fit)"), el("th", { class: "l" }, "fit"))), body);
  }

  function showCandidates(sec, r) {
    sec.replaceChildren(el("h2", {}, "Candidates ", el("span", { class: "muted" },
      "(every fully refitted candidate but the named one, and why it lost)")), candidatesTable(r),
    el("h3", {}, "Screening ", el("span", { class: "muted" },
      `(every candidate's short fit, best first; the first ${fmt(r.refitted_singles ?? r.top)} were refitted)`)), screeningTable(r));
    sec.hidden = false;
  }

  // s: the diagnosis view's sections; base: /api/diagnoses/ID.
  function show(s, base, r, files) {
    showVerdict(s.verdict, base, r, files);
    showEffects(s.effects, r);
    showFigures(s.figures, base, files);
    showCandidates(s.candidates, r);
  }

  return { show };
})();
