// PARE viewer: the episodes table (filters, sorting, pages) and the compare page. No framework, no build.
"use strict";
(function () {
  const script = document.currentScript;
  const ROOT = script ? script.getAttribute("src").replace(/static\/viewer\.js$/, "") : "";
  // Served, the data is given only with the server's key, which only the viewer's own pages carry.
  const KEYED = document.querySelector('meta[name="pare-data-query"]');
  const DATA_QUERY = KEYED ? KEYED.getAttribute("content") : "";
  const PAGE = 50;
  const LISTS = { app: "apps", tag: "tags", decision: "decisions", failures: "failures" };

  function cell(tr, text, href) {
    const td = document.createElement("td");
    if (href) {
      const a = document.createElement("a");
      a.href = href;
      a.textContent = text;
      td.appendChild(a);
    } else {
      td.textContent = text;
    }
    tr.appendChild(td);
    return td;
  }

  function hashParams() {
    return new URLSearchParams(window.location.hash.replace(/^#/, ""));
  }

  function loadRows(cid, done) {
    const all = window.PARE_ROWS || {};
    if (all[cid]) return done(all[cid]);
    const tag = document.createElement("script");
    tag.src = ROOT + "c/" + encodeURIComponent(cid) + "/rows.js" + DATA_QUERY;
    tag.onload = () => done((window.PARE_ROWS || {})[cid] || []);
    tag.onerror = () => done([]);
    document.head.appendChild(tag);
  }

  // -- the episodes table -------------------------------------------------------------------------------
  function matches(row, name, value) {
    if (!value) return true;
    if (name === "scenario") return row.scenario.toLowerCase().includes(value.toLowerCase());
    if (LISTS[name]) return row[LISTS[name]].includes(value);
    return String(row[name]) === value;
  }

  function compare(a, b, key) {
    let x = a[key], y = b[key];
    if (Array.isArray(x)) x = x.join(","), y = y.join(",");
    if (x === null || x === undefined) return 1;
    if (y === null || y === undefined) return -1;
    if (typeof x === "number" && typeof y === "number") return x - y;
    return String(x).localeCompare(String(y));
  }

  function episodesTable() {
    const form = document.getElementById("filters");
    if (!form) return;
    const rows = (window.PARE_ROWS || {})[form.dataset.config] || [];
    const tbody = document.querySelector("#episodes tbody");
    const pager = document.getElementById("pager");
    const state = { sort: "scenario", dir: 1, page: 0 };
    const initial = hashParams();
    for (const field of form.elements) {
      if (field.name && initial.has(field.name)) field.value = initial.get(field.name);
    }
    if (initial.has("sort")) state.sort = initial.get("sort");
    if (initial.get("dir") === "-1") state.dir = -1;
    if (initial.has("page")) state.page = Math.max(0, parseInt(initial.get("page"), 10) || 0);

    function render() {
      const wanted = {};
      for (const field of form.elements) if (field.name) wanted[field.name] = field.value;
      const shown = rows.filter((row) => Object.keys(wanted).every((name) => matches(row, name, wanted[name])));
      shown.sort((a, b) => state.dir * compare(a, b, state.sort) || compare(a, b, "scenario") || a.run - b.run);
      const pages = Math.max(1, Math.ceil(shown.length / PAGE));
      state.page = Math.min(state.page, pages - 1);
      tbody.replaceChildren();
      for (const row of shown.slice(state.page * PAGE, (state.page + 1) * PAGE)) {
        const tr = document.createElement("tr");
        tr.className = row.success === "yes" ? "good-row" : row.success === "no" ? "bad-row" : "missing-row";
        cell(tr, row.scenario, row.href);
        cell(tr, String(row.run));
        cell(tr, row.success);
        cell(tr, row.goals);
        cell(tr, String(row.turns));
        cell(tr, row.ended);
        cell(tr, String(row.proposals));
        cell(tr, row.decisions.join(", "));
        cell(tr, row.difficulty);
        cell(tr, row.apps.join(", "));
        cell(tr, row.failures.join(", "));
        cell(tr, String(row.tokens));
        cell(tr, row.cost_text || "");
        tbody.appendChild(tr);
      }
      document.getElementById("shown-count").textContent = String(shown.length);
      for (const th of document.querySelectorAll("#episodes th[data-sort]")) {
        th.classList.toggle("sorted", th.dataset.sort === state.sort);
        th.classList.toggle("descending", th.dataset.sort === state.sort && state.dir < 0);
      }
      pager.replaceChildren();
      if (pages > 1) {
        for (let i = 0; i < pages; i++) {
          const button = document.createElement("button");
          button.type = "button";
          button.textContent = String(i + 1);
          button.disabled = i === state.page;
          button.addEventListener("click", () => { state.page = i; render(); });
          pager.appendChild(button);
        }
      }
      const params = new URLSearchParams();
      for (const name of Object.keys(wanted)) if (wanted[name]) params.set(name, wanted[name]);
      if (state.sort !== "scenario") params.set("sort", state.sort);
      if (state.dir < 0) params.set("dir", "-1");
      if (state.page) params.set("page", String(state.page));
      history.replaceState(null, "", "#" + params.toString());
    }

    // "change" follows "input" when a field loses focus: render only when the filters really changed,
    // so a click on a row's link just after typing is not lost to a redrawn table.
    let last = "";
    function refilter() {
      const now = new URLSearchParams(new FormData(form)).toString();
      if (now === last) return;
      last = now;
      state.page = 0;
      render();
    }
    form.addEventListener("input", refilter);
    form.addEventListener("change", refilter);
    form.addEventListener("reset", () => setTimeout(refilter));
    for (const th of document.querySelectorAll("#episodes th[data-sort]")) {
      th.addEventListener("click", () => {
        state.dir = state.sort === th.dataset.sort ? -state.dir : 1;
        state.sort = th.dataset.sort;
        render();
      });
    }
    last = new URLSearchParams(new FormData(form)).toString();
    render();
  }

  // -- the episode page ---------------------------------------------------------------------------------
  function episodePage() {
    if (window.self !== window.top) document.body.classList.add("embedded");
    const other = document.getElementById("compare-other");
    const go = document.getElementById("compare-go");
    if (other && go) {
      other.addEventListener("change", () => {
        go.href = go.dataset.base + "&b=" + encodeURIComponent(other.value);
      });
    }
  }

  // -- the compare page ---------------------------------------------------------------------------------
  function comparePage() {
    const form = document.getElementById("compare");
    if (!form) return;
    const configurations = JSON.parse(form.dataset.configurations);
    for (const select of [form.elements.a, form.elements.b]) {
      for (const c of configurations) {
        const option = document.createElement("option");
        option.value = c.id;
        option.textContent = c.label;
        select.appendChild(option);
      }
    }
    const initial = hashParams();
    form.elements.a.value = initial.get("a") || (configurations[0] || {}).id || "";
    form.elements.b.value = initial.get("b") || (configurations[1] || configurations[0] || {}).id || "";
    form.elements.s.value = initial.get("s") || "";
    form.elements.r.value = initial.get("r") || "1";

    function show() {
      const a = form.elements.a.value, b = form.elements.b.value;
      const s = form.elements.s.value, r = parseInt(form.elements.r.value, 10) || 1;
      history.replaceState(null, "", "#" + new URLSearchParams({ a, b, s, r: String(r) }).toString());
      loadRows(a, (left) => loadRows(b, (right) => {
        const list = document.getElementById("compare-scenarios");
        list.replaceChildren();
        for (const name of [...new Set(left.map((row) => row.scenario))].sort()) {
          const option = document.createElement("option");
          option.value = name;
          list.appendChild(option);
        }
        const pick = (rows) => rows.find((row) => row.scenario === s && row.run === r);
        const sides = [[a, pick(left), "left"], [b, pick(right), "right"]];
        const body = document.querySelector("#compare-summary tbody");
        body.replaceChildren();
        const fields = [["configuration", null], ["success", "success"], ["goals", "goals"], ["turns", "turns"],
          ["ended", "ended"], ["decisions", "decisions"], ["failures", "failures"], ["tokens", "tokens"], ["cost", "cost_text"]];
        for (const [title, key] of fields) {
          const tr = document.createElement("tr");
          const th = document.createElement("th");
          th.textContent = title;
          tr.appendChild(th);
          for (const [cid, row] of sides) {
            const label = (configurations.find((c) => c.id === cid) || {}).label || cid;
            const value = key === null ? label : row ? row[key] : "no such episode";
            cell(tr, Array.isArray(value) ? value.join(", ") : String(value ?? ""));
          }
          body.appendChild(tr);
        }
        for (const [cid, row, id] of sides) {
          const frame = document.getElementById(id);
          const src = row ? ROOT + "c/" + encodeURIComponent(cid) + "/" + row.href : "about:blank";
          if (frame.getAttribute("src") !== src) frame.setAttribute("src", src);
        }
      }));
    }
    form.addEventListener("change", show);
    show();
  }

  // -- annotation (served pages only): a person marks proposals and judged texts ----------------------------
  function annotationPanel() {
    const section = document.getElementById("annotate");
    if (!section) return;
    const name = document.getElementById("annotator");
    const NAME_KEY = "pare-annotator";
    try { name.value = window.localStorage.getItem(NAME_KEY) || ""; } catch (e) { /* storage refused */ }
    const items = Array.from(section.querySelectorAll(".annotation-item"));
    function showMine() {
      const who = name.value.trim();
      for (const item of items) {
        const mine = Array.from(item.querySelectorAll(".marks li")).find((li) => li.dataset.annotator === who);
        item.querySelector(".machine").hidden = !mine;
      }
    }
    name.addEventListener("change", () => {
      try { window.localStorage.setItem(NAME_KEY, name.value.trim()); } catch (e) { /* storage refused */ }
      showMine();
    });
    for (const item of items) {
      const status = item.querySelector(".your-mark");
      for (const button of item.querySelectorAll("button.mark")) {
        button.addEventListener("click", () => {
          status.textContent = "saving…";
          const body = {
            configuration: section.dataset.configuration, scenario_id: section.dataset.scenario,
            run: Number(section.dataset.run), kind: item.dataset.kind, item: item.dataset.item,
            label: button.dataset.label, annotator: name.value.trim(),
          };
          fetch(section.dataset.endpoint, {
            method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
          })
            .then((response) => response.json().then((answer) => [response.ok, answer]))
            .then(([ok, answer]) => {
              if (!ok) { status.textContent = "not saved: " + answer.error; return; }
              if (!name.value.trim()) name.value = answer.annotator;
              const marks = item.querySelector(".marks");
              let li = Array.from(marks.querySelectorAll("li")).find((each) => each.dataset.annotator === answer.annotator);
              if (!li) { li = document.createElement("li"); li.dataset.annotator = answer.annotator; marks.appendChild(li); }
              li.textContent = answer.annotator + ": " + answer.label;
              status.textContent = "saved: " + answer.label;
              item.querySelector(".machine").hidden = false;
            })
            .catch((error) => { status.textContent = "not saved: " + error; });
        });
      }
    }
    showMine();
  }

  document.addEventListener("DOMContentLoaded", () => {
    episodesTable();
    episodePage();
    comparePage();
    annotationPanel();
  });
})();
