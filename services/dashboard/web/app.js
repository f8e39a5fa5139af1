"use strict";
// The dashboard's core: API calls carrying the token, the error banner, number formats,
// polling, and the router that shows one view at a time. Views register themselves in
// GF.views (studies here, study in study.js, diagnoses and diagnosis in diagnosis.js); a new
// view is one more entry and one more nav link.
const GF = (() => {
  const TOKEN_KEY = "gaitforge.token";
  const etags = new Map();  // API path -> {etag, data}: unchanged answers come back as 304

  // A ?token=T in the address is kept for this tab only and removed from the address bar
  // (and so from the history): it travels as an Authorization header from then on.
  (function takeTokenFromAddress() {
    const u = new URL(location.href);
    const t = u.searchParams.get("token");
    if (t === null) return;
    sessionStorage.setItem(TOKEN_KEY, t);
    u.searchParams.delete("token");
    history.replaceState(null, "", u.pathname + u.search + u.hash);
  })();

  class ApiError extends Error {
    constructor(status, message) { super(message); this.status = status; }
  }

  // GET with the tab's token as the Authorization header.
  async function send(path, headers) {
    const token = sessionStorage.getItem(TOKEN_KEY);
    if (token) headers.Authorization = "Bearer " + token;
    try {
      return await fetch(path, { headers, cache: "no-store" });
    } catch (e) {
      throw new ApiError(0, `cannot reach the coordinator at ${location.host} (${e.message})`);
    }
  }

  async function api(path) {
    const known = etags.get(path);
    const r = await send(path, known ? { "If-None-Match": known.etag } : {});
    if (r.status === 304 && known) return known.data;
    let body = null;
    try { body = await r.json(); } catch (e) { /* reported below */ }
    if (!r.ok) {
      const why = body && body.error ? body.error : `HTTP ${r.status} ${r.statusText}`;
      throw new ApiError(r.status, why);
    }
    if (body === null) throw new ApiError(r.status, `GET ${path}: the answer is not JSON`);
    const etag = r.headers.get("ETag");
    if (etag) etags.set(path, { etag, data: body });
    return body;
  }

  // A stored file as a Blob (for a blob: URL or its text): the token travels as a header,
  // which <img src> and <a href> cannot send.
  async function file(path) {
    const r = await send(path, {});
    if (!r.ok) {
      let why = `HTTP ${r.status} ${r.statusText}`;
      try { why = (await r.json()).error || why; } catch (e) { /* not JSON: the status */ }
      throw new ApiError(r.status, `GET ${path}: ${why}`);
    }
    return r.blob();
  }

  const banner = () => document.getElementById("banner");
  const authForm = () => document.getElementById("auth");

  // Never silent: every failed call shows why, until a call succeeds again.
  function showError(e) {
    if (e.status === 401 || e.status === 403) {
      authForm().hidden = false;
      banner().textContent = `The coordinator refused the token: ${e.message}`;
    } else {
      banner().textContent = `Could not load from the coordinator: ${e.message}`;
    }
    banner().hidden = false;
  }

  function clearError() {
    banner().hidden = true;
    authForm().hidden = true;
    document.getElementById("live").textContent =
      "updated " + new Date().toLocaleTimeString();
  }

  // Runs step() now and then every `ms` while alive(); step may return a new interval.
  async function poll(step, ms, alive) {
    while (alive()) {
      let next = ms;
      try {
        const r = await step();
        if (typeof r === "number") next = r;
        if (alive()) clearError();
      } catch (e) {
        if (alive()) showError(e);
      }
      await new Promise((done) => setTimeout(done, next));
    }
  }

  // Protobuf JSON gives int64 as strings and NaN/Infinity as "NaN"/"Infinity".
  const num = (x) => (x === undefined || x === null ? NaN : Number(x));
  function fmt(x, digits = 6) {
    const v = num(x);
    if (!Number.isFinite(v)) return "–";
    if (Number.isInteger(v) && Math.abs(v) < 1e9) return String(v);
    return v.toPrecision(digits).replace(/\.?0+(e|$)/, "$1");
  }
  // STUDY_STATE_RUNNING, DIAGNOSIS_STATE_RUNNING -> running
  const stateName = (s) => (s || "STATE_UNSPECIFIED").replace(/^([A-Z]+_)?STATE_/, "").toLowerCase();
  const when = (ms) => (num(ms) > 0 ? new Date(num(ms)).toLocaleString() : "–");
  const clock = (ms) => (num(ms) > 0 ? new Date(num(ms)).toLocaleTimeString() : "–");
  // As the CLI's progress bar: 45s, 3m05s, 2h10m.
  function duration(s) {
    const t = Math.round(num(s));
    if (!Number.isFinite(t) || t < 0) return "–";
    const two = (x) => String(x).padStart(2, "0");
    if (t >= 3600) return `${Math.floor(t / 3600)}h${two(Math.floor(t / 60) % 60)}m`;
    return t >= 60 ? `${Math.floor(t / 60)}m${two(t % 60)}s` : `${t}s`;
  }

  // el("td", {class: "l"}, "text", child, ...)
  function el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    for (const c of children) e.append(c instanceof Node ? c : String(c));
    return e;
  }
  const cells = (row, values) => values.forEach((v) => row.append(v instanceof Node ? v : el("td", {}, v)));
  // "name: value" in a facts line.
  const fact = (name, value, attrs) => el("span", attrs || {}, el("b", {}, name + ": "), value);
  const stateBadge = (s) => el("span", { class: "state " + stateName(s) }, stateName(s));

  const views = {};
  let shown = 0;  // which render is current: an older view's polls stop

  function route() {
    const hash = location.hash.replace(/^#\/?/, "");
    const [name, ...rest] = hash.split("/");
    const view = views[name || "studies"] || views.missing;
    const mine = ++shown;
    const root = document.getElementById("view");
    root.replaceChildren();
    banner().hidden = true;
    for (const a of document.querySelectorAll("header nav a"))
      a.classList.toggle("active", a.dataset.view === (view.nav || name || "studies"));
    view.render(root, rest.map(decodeURIComponent), () => mine === shown);
  }

  views.missing = {
    render(root) { root.append(el("p", {}, "No such page. ", el("a", { href: "#/" }, "Studies"))); },
  };

  views.studies = {
    render(root, _params, alive) {
      const tbody = el("tbody");
      root.append(el("section", {},
        el("h1", {}, "Studies"),
        el("table", { id: "studies" },
          el("thead", {}, el("tr", {}, ...["study", "name", "state", "objective", "engine",
            "generations", "best", "evaluations", "updated"].map((h, i) =>
              el("th", i < 5 ? { class: "l" } : {}, h)))),
          tbody)));
      poll(async () => {
        const list = (await api("/api/studies")).studies || [];
        tbody.replaceChildren(...list.slice().reverse().map(studyRow));
        if (!list.length)
          tbody.append(el("tr", {}, el("td", { class: "l muted", colspan: 9 },
            "No study yet: gaitforge local SPEC.yaml starts one.")));
      }, 2000, alive);
    },
  };

  function studyRow(s) {
    const spec = s.spec || {};
    const tr = el("tr", { class: "link", "data-study": s.study_id });
    cells(tr, [el("td", { class: "l" }, el("a", { href: "#/study/" + encodeURIComponent(s.study_id) }, s.study_id)),
      el("td", { class: "l" }, spec.name || ""), el("td", { class: "l" }, stateBadge(s.state)),
      el("td", { class: "l" }, (spec.objective || {}).name || ""), el("td", { class: "l" }, spec.engine || ""),
      `${s.generations_done} / ${spec.generations}`, fmt(s.best_fitness), fmt(s.evaluations),
      when(s.updated_unix_ms)]);
    tr.addEventListener("click", (ev) => {
      if (ev.target.tagName !== "A") location.hash = "#/study/" + encodeURIComponent(s.study_id);
    });
    return tr;
  }

  document.addEventListener("DOMContentLoaded", () => {
    authForm().addEventListener("submit", (ev) => {
      ev.preventDefault();
      sessionStorage.setItem(TOKEN_KEY, document.getElementById("token").value.trim());
      etags.clear();
      route();
    });
    window.addEventListener("hashchange", route);
    route();
  });

  return { api, file, poll, fmt, num, el, cells, fact, stateName, stateBadge, when, clock, duration, views,
    showError };
})();
