// drillfatigue digital twin web page: talks to the /v1 API of the same server.
"use strict";

const $ = (id) => document.getElementById(id);
const state = { card: null, components: [], autoConstants: true };
// inputs the log or the component list usually carries (not prefilled as constants)
const LOG_STEMS = ["rpm", "wob", "rop", "md", "s_from_bit", "component_type", "location",
                   "hook_load"];

function setStatus(text, kind) {
  const el = $("status");
  el.textContent = text;
  el.className = "status" + (kind ? " " + kind : "");
}

async function api(method, path, body) {
  const opts = { method: method, headers: {} };
  if (body !== undefined) {
    opts.headers["content-type"] = "application/json";
    opts.body = JSON.stringify(body);
  }
  const resp = await fetch(path, opts);
  const data = await resp.json().catch(() => ({ detail: resp.status + " " + resp.statusText }));
  if (!resp.ok) {
    const err = new Error(data.detail || ("HTTP " + resp.status));
    err.status = resp.status;  // 503: the server was started without this part
    throw err;
  }
  return data;
}

function fmt(v, digits) {
  if (v === null || v === undefined) { return "inf"; }
  if (typeof v !== "number") { return String(v); }
  if (Number.isInteger(v) && Math.abs(v) < 1e6) { return String(v); }
  return Number(v).toPrecision(digits || 3);
}

// -- CSV and NAME=VALUE helpers ------------------------------------------------------
function parseCsv(text) {
  const lines = text.split(/\r?\n/).map((l) => l.trim()).filter((l) => l.length > 0);
  if (lines.length === 0) { return []; }
  const head = lines[0].split(",").map((h) => h.trim());
  return lines.slice(1).map((line) => {
    const cells = line.split(",");
    const row = {};
    head.forEach((h, i) => {
      const raw = (cells[i] || "").trim();
      const num = Number(raw);
      row[h] = raw !== "" && !Number.isNaN(num) ? num : raw;
    });
    return row;
  });
}

function parseConstants(text) {
  const out = {};
  text.split(/\r?\n/).forEach((line, i) => {
    const l = line.replace(/#.*/, "").trim();
    if (!l) { return; }
    const k = l.indexOf("=");
    if (k < 1) { throw new Error("constant inputs, line " + (i + 1) + ": '" + l + "' is not NAME=VALUE"); }
    const name = l.slice(0, k).trim();
    const raw = l.slice(k + 1).trim();
    const num = Number(raw);
    out[name] = raw !== "" && !Number.isNaN(num) ? num : raw;
  });
  return out;
}

function acceptedNames() {
  const names = new Set();
  if (!state.card) { return names; }
  state.card.features.concat(state.card.categorical).forEach((f) => f.names.forEach((n) => names.add(n)));
  return names;
}

function stemOf(name) {
  return LOG_STEMS.find((s) => name === s || name.startsWith(s + "_")) || null;
}

// hole-geometry inputs: computed from the survey when one is given
function dropGeometry(values) {
  if (!state.card) { return; }
  state.card.features.forEach((f) => {
    if (/^(local_|bit_|build_to_bit)/.test(f.column)) { f.names.forEach((n) => delete values[n]); }
  });
}

// -- model -----------------------------------------------------------------------------
function prefillConstants(card) {
  const lines = [];
  card.features.forEach((f) => {
    if (stemOf(f.names[0])) { return; }
    const mid = 0.5 * (f.min + f.max);
    lines.push(f.names[0] + "=" + Number(mid.toPrecision(4)));
  });
  card.categorical.forEach((f) => {
    if (stemOf(f.names[0])) { return; }
    lines.push(f.names[0] + "=" + f.levels[0]);
  });
  $("constants-text").value = lines.join("\n");
}

async function loadCard() {
  const name = $("model-select").value;
  const card = await api("GET", "/v1/model?name=" + encodeURIComponent(name));
  state.card = card;
  $("model-info").textContent = card.criterion + " criterion, " + Math.round(100 * card.coverage) +
    " % intervals, " + card.features.length + " numeric + " + card.categorical.length +
    " categorical inputs, generation " + card.generation + ", loaded " + card.loaded_at_utc;
  const fmtSel = $("log-format");
  fmtSel.innerHTML = "";
  card.log_formats.forEach((f) => { const o = document.createElement("option"); o.value = f; o.textContent = f; fmtSel.appendChild(o); });
  if (state.autoConstants) { prefillConstants(card); }
  fillAxes(card);
}

// -- the field example ------------------------------------------------------------------
async function loadExample() {
  setStatus("loading the field example ...");
  const ex = await api("GET", "/v1/example");
  $("log-format").value = ex.log.format;
  $("log-text").value = ex.log.text;
  $("components-text").value = ex.tally_csv;
  $("survey-text").value = "md_m,inc_deg,dls_deg_per_30m\n" +
    ex.survey.map((r) => [r.md_m, r.inc_deg, r.dls_deg_per_30m].join(",")).join("\n");
  // the example's constants replace the prefilled ones of the same input
  const columnOf = (name) => {
    const f = state.card ? state.card.features.find((g) => g.names.includes(name)) : null;
    return f ? f.column : name;
  };
  const given = new Set(Object.keys(ex.constants).map(columnOf));
  const consts = parseConstants($("constants-text").value);
  Object.keys(consts).forEach((k) => { if (given.has(columnOf(k))) { delete consts[k]; } });
  Object.assign(consts, ex.constants);
  $("constants-text").value = Object.entries(consts).map(([k, v]) => k + "=" + v).join("\n");
  state.autoConstants = false;
  await replay();
}

async function loadModels() {
  let data;
  try {
    data = await api("GET", "/v1/models");
  } catch (e) {
    if (e.status !== 503) { throw e; }
    // a server for a ledger alone: the model's sections have nothing to answer with
    ["replay-section", "window-section", "plan-section", "model-select", "reload-button"]
      .forEach((id) => { $(id).hidden = true; });
    $("model-info").textContent = "no model served";
    return;
  }
  const sel = $("model-select");
  sel.innerHTML = "";
  data.models.forEach((m) => {
    const o = document.createElement("option");
    o.value = m.name; o.textContent = m.name;
    if (m.name === data.default) { o.selected = true; }
    sel.appendChild(o);
  });
  await loadCard();
}

// -- replay ----------------------------------------------------------------------------
// columns: [key, heading] pairs; opts.link: [key, onClick(value)] makes that column's cells
// links; opts.blank: a null cell is shown empty (unknown), not as "inf" (an infinite life)
function fillTable(table, columns, rows, empty, opts) {
  const link = opts && opts.link;
  table.innerHTML = "";
  if (rows.length === 0) {
    table.innerHTML = "<tbody><tr><td class='muted'>" + empty + "</td></tr></tbody>";
    return;
  }
  const head = document.createElement("thead");
  head.innerHTML = "<tr>" + columns.map((c) => "<th>" + c[1] + "</th>").join("") + "</tr>";
  const body = document.createElement("tbody");
  rows.forEach((r) => {
    const tr = document.createElement("tr");
    columns.forEach((c) => {
      const td = document.createElement("td");
      if (link && c[0] === link[0] && r[c[0]] !== null) {
        const a = document.createElement("a");
        a.href = "#"; a.className = "serial"; a.textContent = String(r[c[0]]);
        a.addEventListener("click", (ev) => { ev.preventDefault(); link[1](r[c[0]]); });
        td.appendChild(a);
      } else {
        td.textContent = opts && opts.blank && r[c[0]] === null ? "" : fmt(r[c[0]]);
      }
      tr.appendChild(td);
    });
    body.appendChild(tr);
  });
  table.appendChild(head);
  table.appendChild(body);
}

function plotDamage(res) {
  const byLoc = {};
  res.components.forEach((c) => {
    if (!(c.damage > 0)) { return; }
    const key = c.location || c.component_type || "component";
    (byLoc[key] = byLoc[key] || []).push(c);
  });
  const traces = Object.keys(byLoc).sort().map((loc) => {
    const rows = byLoc[loc].sort((a, b) => a.s_from_bit_m - b.s_from_bit_m);
    return {
      type: "scatter", mode: "markers", name: loc,
      x: rows.map((r) => r.s_from_bit_m), y: rows.map((r) => r.damage),
      text: rows.map((r) => r.serial + (r.ood_time_s > 0 ? " (some time out of domain)" : "")),
      marker: { size: 9, symbol: rows.map((r) => (r.ood_time_s > 0 ? "x" : "circle")) },
      error_y: { type: "data", symmetric: false,
                 array: rows.map((r) => r.damage_upper - r.damage),
                 arrayminus: rows.map((r) => r.damage - r.damage_lower) },
      hovertemplate: "%{text}<br>s = %{x} m<br>damage %{y:.3g}<extra></extra>",
    };
  });
  Plotly.newPlot("damage-plot", traces, {
    title: { text: "Accumulated damage along the string (" + fmt(res.duration_h) + " h)", font: { size: 13 } },
    xaxis: { title: { text: "distance from bit (m)" } },
    yaxis: { title: { text: "Miner damage (-), " + Math.round(100 * res.coverage) + " % interval" }, type: "log", exponentformat: "power" },
    margin: { t: 36, r: 10, b: 46, l: 70 }, legend: { orientation: "h", y: 1.08, x: 1, xanchor: "right" },
  }, { displaylogo: false, responsive: true });
}

function setComponents(rows) {
  // the window maps locations the model covers (a replay marks the others covered: false)
  state.components = rows.filter((r) => r.s_from_bit_m !== undefined && r.s_from_bit_m !== "" &&
                                        r.covered !== false);
  const sel = $("window-component");
  sel.innerHTML = "";
  state.components.forEach((c, i) => {
    const o = document.createElement("option");
    o.value = String(i);
    o.textContent = (c.serial || "#" + i) + ": " + (c.component_type || "") + " " + (c.location || "") + ", " + c.s_from_bit_m + " m from bit";
    sel.appendChild(o);
  });
}

async function replay() {
  setStatus("replaying ...");
  const surveyText = $("survey-text").value.trim();
  const listText = $("components-text").value;
  // a tally (Description / Serial columns) or a component list (serial, s_from_bit_m, ...)
  const isTally = /description/i.test(listText.split("\n", 1)[0]);
  const body = {
    model: $("model-select").value,
    log: { format: $("log-format").value || "csv", text: $("log-text").value },
    components_csv: isTally ? null : listText,
    tally_csv: isTally ? listText : null,
    survey: surveyText ? parseCsv(surveyText) : null,
    constants: parseConstants($("constants-text").value),
    retire_at_damage: Number($("retire-damage").value),
    retire_within_h: $("retire-hours").value ? Number($("retire-hours").value) : null,
  };
  if (body.survey) { dropGeometry(body.constants); }
  const res = await api("POST", "/v1/twin/replay", body);
  plotDamage(res);
  $("replay-summary").innerHTML = "<b>" + res.n_locations + "</b> locations over <b>" + fmt(res.duration_h) +
    " h</b>; " + (res.max_damage_serial === null ? "<span class='bad'>no answer: no covered location was in the model's domain</span>" :
    "largest damage in domain " + fmt(res.max_damage_in_domain) + " at <b>" + res.max_damage_serial + "</b>") + "; " +
    (res.n_locations_some_time_ood > 0 ? "<span class='bad'>" + res.n_locations_some_time_ood + " locations spent time out of domain (up to " +
      fmt(res.max_ood_time_h) + " h; no damage counted then)</span>" : "all in the training domain") +
    (res.not_covered.length ? "; <span class='bad'>not covered: " + res.not_covered.map((n) => n.item + " (" + n.reason + ")").join("; ") + "</span>" : "") +
    (res.ignored_log_channels.length ? "; unused log channels: " + res.ignored_log_channels.join(", ") : "");
  const noDamage = res.components.filter((c) => c.covered && !(c.damage > 0)).length;
  if (noDamage) { $("replay-summary").innerHTML += "; " + noDamage + " covered locations without damage (never in the hole, or out of domain the whole time), not plotted"; }
  fillTable($("retire-table"), [["serial", "serial"], ["action", "action"], ["s_from_bit_m", "s from bit (m)"], ["damage", "damage"],
    ["damage_upper", "upper bound"], ["remaining_life_h_lower", "remaining life, lower (h)"], ["reason", "reason"]],
    res.retire, "none: no component reaches the retirement limits");
  const worst = res.components.slice().sort((a, b) => b.damage - a.damage).slice(0, 8);
  fillTable($("damage-table"), [["serial", "serial"], ["component_type", "type"], ["location", "location"],
    ["s_from_bit_m", "s from bit (m)"], ["damage", "damage"], ["remaining_life_h", "remaining life (h)"]],
    worst, "no component");
  setComponents(res.components);
  $("window-bit-md").value = Math.round(res.last_bit_md_m);
  setStatus("replayed " + res.n_locations + " locations with model " + res.model, "ok");
}

// -- operating window ---------------------------------------------------------------------
// the y axes: every numeric input but rpm, in a user unit (kN for a force), from the card
function axisUnit(f) {
  const kn = f.names.find((n) => n.endsWith("_kN"));
  return kn ? [kn, 1000] : [f.names[0], 1];
}

function fillAxes(card) {
  const sel = $("y-name");
  sel.innerHTML = "";
  card.features.forEach((f) => {
    if (stemOf(f.names[0]) === "rpm" || /^(md_m|s_from_bit_m|local_|bit_|build_to_bit)/.test(f.column)) { return; }
    const [name, k] = axisUnit(f);
    const o = document.createElement("option");
    o.value = name; o.textContent = name;
    o.dataset.min = String(f.min / k); o.dataset.max = String(f.max / k);
    if (stemOf(name) === "wob") { o.selected = true; }
    sel.appendChild(o);
  });
  updateAxisRange();
  const rpm = card.features.find((f) => stemOf(f.names[0]) === "rpm");
  if (rpm) { $("x-start").value = Number(rpm.min.toPrecision(4)); $("x-stop").value = Number(rpm.max.toPrecision(4)); }
}

function updateAxisRange() {
  const o = $("y-name").selectedOptions[0];
  if (!o) { return; }
  $("y-start").value = Number(Number(o.dataset.min).toPrecision(4));
  $("y-stop").value = Number(Number(o.dataset.max).toPrecision(4));
}

function cellEdges(v) {
  const e = [v[0] - (v[1] - v[0]) / 2];
  for (let i = 0; i < v.length - 1; i++) { e.push((v[i] + v[i + 1]) / 2); }
  e.push(v[v.length - 1] + (v[v.length - 1] - v[v.length - 2]) / 2);
  return e;
}

function plotWindow(res) {
  const z = res.life_h.map((row) => row.map((v) => (v === null ? null : Math.log10(v))));
  const xe = cellEdges(res.x.values), ye = cellEdges(res.y.values);
  const hx = [], hy = [];
  res.ood.forEach((row, i) => row.forEach((flag, j) => {
    if (!flag) { return; }
    hx.push(xe[j], xe[j + 1], xe[j + 1], xe[j], xe[j], null);
    hy.push(ye[i], ye[i], ye[i + 1], ye[i + 1], ye[i], null);
  }));
  const traces = [{
    type: "heatmap", x: res.x.values, y: res.y.values, z: z, colorscale: "Viridis",
    colorbar: { title: { text: "life, log10(h)", side: "right" } },
    hovertemplate: res.x.name + " %{x}<br>" + res.y.name + " %{y}<br>log10 life %{z:.2f}<extra></extra>",
  }];
  if (hx.length) {
    traces.push({ type: "scatter", mode: "lines", x: hx, y: hy, fill: "toself", name: "outside training domain",
                  line: { width: 0 }, fillcolor: "rgba(255,255,255,0.15)", hoverinfo: "skip",
                  fillpattern: { shape: "/", fgcolor: "white", size: 7, solidity: 0.3 } });
  }
  if (res.best_in_domain) {
    traces.push({ type: "scatter", mode: "markers", name: "longest life in domain",
                  x: [res.best_in_domain[res.x.name]], y: [res.best_in_domain[res.y.name]],
                  marker: { symbol: "star", size: 16, color: "red", line: { color: "white", width: 1 } } });
  }
  Plotly.newPlot("window-plot", traces, {
    title: { text: "Predicted life (" + res.criterion + "), hatched: outside the training domain", font: { size: 13 } },
    xaxis: { title: { text: res.x.name }, range: [xe[0], xe[xe.length - 1]] },
    yaxis: { title: { text: res.y.name }, range: [ye[0], ye[ye.length - 1]] },
    margin: { t: 36, r: 10, b: 46, l: 60 }, legend: { orientation: "h", y: -0.2 },
  }, { displaylogo: false, responsive: true });
}

async function mapWindow() {
  const c = state.components[Number($("window-component").value)];
  if (!c) { throw new Error("window: no component; replay a log or fill in the component list first"); }
  const accepted = acceptedNames();
  const yName = $("y-name").value;
  const fixed = {};
  Object.entries(parseConstants($("constants-text").value)).forEach(([k, v]) => {
    const s = stemOf(k);
    if (s === "rpm" || s === stemOf(yName) || k === yName) { return; }
    fixed[k] = v;
  });
  const bit = Number($("window-bit-md").value);
  const s = Number(c.s_from_bit_m);
  const place = { md_m: bit - s, s_from_bit_m: s, component_type: c.component_type, location: c.location };
  Object.entries(place).forEach(([k, v]) => { if (accepted.has(k) && v !== undefined) { fixed[k] = v; } });
  // a logged input on neither axis (ROP, for a model that has it): held at its domain's centre
  const held = [];
  state.card.features.forEach((f) => {
    const st = stemOf(f.names[0]);
    if (!st || st === "rpm" || st === stemOf(yName) || /^(md_m|s_from_bit_m)$/.test(f.column) ||
        f.names.some((n) => n in fixed)) { return; }
    fixed[f.names[0]] = Number((0.5 * (f.min + f.max)).toPrecision(4));
    held.push(f.names[0] + " " + fixed[f.names[0]]);
  });
  const surveyText = $("survey-text").value.trim();
  const body = {
    model: $("model-select").value,
    x: { name: "rpm", start: Number($("x-start").value), stop: Number($("x-stop").value), n: Number($("x-n").value) },
    y: { name: yName, start: Number($("y-start").value), stop: Number($("y-stop").value), n: Number($("y-n").value) },
    fixed: fixed,
    survey: surveyText ? parseCsv(surveyText) : null,
  };
  if (body.survey) { dropGeometry(body.fixed); }
  setStatus("mapping ...");
  const res = await api("POST", "/v1/window", body);
  plotWindow(res);
  const b = res.best_in_domain;
  $("window-summary").innerHTML = (c.serial || "component") + " at " + fmt(bit - s, 5) + " m MD: " +
    Math.round(100 * res.ood_fraction) + " % of the grid out of domain" +
    (held.length ? " (held at the domain's centre: " + held.join(", ") + ")" : "") +
    (b ? "; longest life in domain at <b>" + fmt(b[res.x.name]) + " " + res.x.name + ", " + fmt(b[res.y.name]) + " " + res.y.name +
         "</b>: " + fmt(b.life_h) + " h (lower bound " + fmt(b.life_h_lower) + " h)" : "");
  setStatus("window map ready", "ok");
}

// -- plan ranking ------------------------------------------------------------------------------
async function rankPlans() {
  setStatus("ranking ...");
  const res = await api("POST", "/v1/plan/rank", { model: $("model-select").value, candidates_yaml: $("plan-text").value });
  const rows = res.rows;
  Plotly.newPlot("plan-plot", [{
    type: "bar", x: rows.map((r) => r.candidate), y: rows.map((r) => r.life_windows_surrogate),
    error_y: { type: "data", symmetric: false,
               array: rows.map((r) => (r.life_windows_surrogate_upper === null ? 0 : r.life_windows_surrogate_upper - r.life_windows_surrogate)),
               arrayminus: rows.map((r) => r.life_windows_surrogate - r.life_windows_surrogate_lower) },
    marker: { color: rows.map((r) => (r.ood_fraction > 0 ? "#d98c2b" : "#2a6fdb")) },
  }], {
    title: { text: "Life of the critical component, drilling windows (best first)", font: { size: 13 } },
    yaxis: { type: "log", title: { text: "windows" } }, margin: { t: 36, r: 10, b: 60, l: 60 },
  }, { displaylogo: false, responsive: true });
  fillTable($("plan-table"), [["rank_surrogate", "rank"], ["candidate", "candidate"], ["life_windows_surrogate", "life (windows)"],
    ["life_windows_surrogate_lower", "lower"], ["life_windows_surrogate_upper", "upper"], ["critical_component", "critical"],
    ["critical_s_from_bit_m", "s from bit (m)"], ["ood_fraction", "OOD share"]], rows, "no candidate");
  $("plan-summary").innerHTML = "best: <b>" + res.best + "</b> (window " + fmt(res.window_s) + " s; orange bars: some rows out of domain)";
  setStatus("ranked " + rows.length + " candidates", "ok");
}

// -- fatigue ledger ----------------------------------------------------------------------------
const ledger = { units: "si", serial: null };

// a ledger table: a serial opens its joint's history; a null cell is unknown or empty
function ledgerTable(table, columns, rows, empty) {
  fillTable(table, columns, rows, empty,
            { link: ["serial", (v) => guarded(() => showHistory(v))()], blank: true });
}

// a length or diameter column in the units asked for ("od_mm" or "od_in"), headed with its unit
function unitColumn(columns, base, heading) {
  const c = columns.find((k) => k.startsWith(base + "_") && !k.slice(base.length + 1).includes("_"));
  return c ? [c, heading + " (" + c.slice(base.length + 1) + ")"] : null;
}

function query(params) {
  return Object.entries(params).map(([k, v]) => k + "=" + encodeURIComponent(v)).join("&");
}

async function loadLedger() {
  let info;
  try {
    info = await api("GET", "/v1/ledger");
  } catch (e) {
    if (e.status !== 503) { throw e; }
    $("ledger-summary").textContent = e.message;
    $("ledger-body").hidden = true;
    return;
  }
  $("ledger-body").hidden = false;
  $("ledger-summary").innerHTML = (info.backend === "sqlite" ? "SQLite" : "PostgreSQL") + " ledger <b>" +
    info.database + "</b> (schema " + info.schema_revision + "): <b>" + info.joints + "</b> joints, " +
    info.runs + " runs (" + info.open_runs + " open), " + info.chunks + " log chunks, " + info.inspections + " inspections";
  ledger.units = $("ledger-units").value;
  const runs = await api("GET", "/v1/ledger/runs");
  ledgerTable($("runs-table"), [["run", "run"], ["well", "well"], ["status", "status"], ["joints", "joints"],
    ["chunks", "chunks"], ["log_h", "log (h)"]], runs.rows, "no run yet");
  await loadInventory();
  await loadLists();
  if (ledger.serial) { await showHistory(ledger.serial); }
  setStatus("ledger: " + info.joints + " joints, " + info.runs + " runs", "ok");
}

function plotInventory(res) {
  const rows = res.rows.filter((r) => r.damage !== null);
  Plotly.newPlot("inventory-plot", [{
    type: "scatter", mode: "markers", name: "governing location",
    x: rows.map((r) => r.serial), y: rows.map((r) => r.damage),
    text: rows.map((r) => r.component_type + ", " + r.governing_location),
    marker: { size: 8, color: "#2a6fdb" },
    error_y: { type: "data", symmetric: false, array: rows.map((r) => r.damage_upper - r.damage),
               arrayminus: rows.map((r) => r.damage - r.damage_lower) },
    hovertemplate: "%{x}: %{text}<br>damage %{y:.3g}<extra></extra>",
  }], {
    title: { text: "Damage by joint, most damaged first (interval as bars)", font: { size: 13 } },
    xaxis: { type: "category", title: { text: "serial" } },
    yaxis: { type: "log", title: { text: "Miner damage (-)" }, exponentformat: "power" },
    margin: { t: 36, r: 10, b: 70, l: 70 },
  }, { displaylogo: false, responsive: true });
}

async function loadInventory() {
  const res = await api("GET", "/v1/ledger/joints?" + query({ units: ledger.units }));
  const cols = [["serial", "serial"], ["component_type", "type"], unitColumn(res.columns, "od", "OD"),
    ["governing_location", "governing"], ["damage", "damage"], ["damage_lower", "lower"], ["damage_upper", "upper"],
    ["remaining_life", "remaining life"], ["remaining_life_lower", "lower"], ["remaining_life_upper", "upper"],
    ["time_in_hole_h", "in hole (h)"], ["ood_h", "out of domain (h)"], ["runs", "runs"],
    ["last_result", "last inspection"], ["not_covered", "not covered"]].filter((c) => c !== null);
  ledgerTable($("inventory-table"), cols, res.rows, "no joint yet: start a run (drillfatigue ledger run start)");
  plotInventory(res);
}

async function loadLists() {
  const params = { units: ledger.units };
  [["retire_at", "rule-retire-at"], ["inspect_at", "rule-inspect-at"], ["reinspect_after", "rule-reinspect-after"],
   ["downgraded_retire_at", "rule-downgraded-retire-at"]].forEach(([k, id]) => {
    if ($(id).value !== "") { params[k] = $(id).value; }
  });
  const res = await api("GET", "/v1/ledger/retire?" + query(params));
  // the rules the lists were made with (the ledger's defaults until changed here)
  $("rule-retire-at").value = res.rules.retire_at;
  $("rule-inspect-at").value = res.rules.inspect_at;
  $("rule-reinspect-after").value = res.rules.reinspect_after;
  $("rule-downgraded-retire-at").value = res.rules.downgraded_retire_at;
  const cols = [["serial", "serial"], ["component_type", "type"], ["damage", "damage"], ["damage_upper", "upper"],
    ["remaining_life", "remaining life"], ["last_result", "last inspection"], ["reason", "reason"]];
  ledgerTable($("ledger-retire-table"), cols, res.retire, "none to retire under these rules");
  ledgerTable($("ledger-inspect-table"), cols, res.inspect, "none to inspect under these rules");
  return res;
}

function plotHistory(h) {
  const runs = [...new Set(h.runs.rows.map((r) => r.run))];
  const locs = [...new Set(h.runs.rows.map((r) => r.location).filter((l) => l))].sort();
  const traces = locs.map((loc) => {
    const rows = runs.map((run) => h.runs.rows.find((r) => r.run === run && r.location === loc) || null);
    return {
      type: "bar", name: loc, x: runs, y: rows.map((r) => (r && r.damage !== null ? r.damage : 0)),
      error_y: { type: "data", symmetric: false,
                 array: rows.map((r) => (r && r.damage !== null ? r.damage_upper - r.damage : 0)),
                 arrayminus: rows.map((r) => (r && r.damage !== null ? r.damage - r.damage_lower : 0)) },
      text: rows.map((r) => (r ? "position " + r.position + " from the bit" : "")), textposition: "none",
      hovertemplate: "%{x}: %{text}<br>damage %{y:.3g}<extra>" + loc + "</extra>",
    };
  });
  Plotly.newPlot("history-plot", traces, {
    title: { text: h.serial + ": damage per run (interval as bars)", font: { size: 13 } },
    barmode: "group", xaxis: { type: "category", title: { text: "run" } },
    yaxis: { title: { text: "Miner damage (-)" }, exponentformat: "power" },
    margin: { t: 36, r: 10, b: 46, l: 70 }, legend: { orientation: "h", y: 1.08, x: 1, xanchor: "right" },
  }, { displaylogo: false, responsive: true });
}

async function showHistory(serial) {
  const h = await api("GET", "/v1/ledger/joints/" + encodeURIComponent(serial) + "?" + query({ units: ledger.units }));
  ledger.serial = h.serial;
  const runs = [...new Set(h.runs.rows.map((r) => r.run))];
  $("history-title").textContent = "Joint history: " + h.serial + " (" + h.component_type + ")";
  $("history-summary").textContent = runs.length + " runs: " + runs.map((run) => {
    const r = h.runs.rows.find((x) => x.run === run);
    return run + " (" + r.well + ", position " + r.position + ")";
  }).join(", ");
  const cols = [["run", "run"], ["well", "well"], ["position", "position"], unitColumn(h.runs.columns, "s_bottom", "bottom from bit"),
    ["location", "location"], ["damage", "damage"], ["damage_lower", "lower"], ["damage_upper", "upper"],
    ["time_in_hole_h", "in hole (h)"], ["revolutions", "revolutions"], ["ood_h", "out of domain (h)"],
    ["not_covered", "not covered"], ["chunks", "chunks"]].filter((c) => c !== null);
  ledgerTable($("history-table"), cols, h.runs.rows, "in no run yet");
  ledgerTable($("history-events"), [["kind", "kind"], ["old_serial", "old serial"], ["new_serial", "new serial"],
    ["reason", "reason"], ["recorded_at", "recorded"]], h.events.rows, "none");
  ledgerTable($("history-inspections"), [["inspected_on", "date"], ["method", "method"], ["standard", "standard"],
    ["result", "result"], unitColumn(h.inspections.columns, "wall", "wall"), unitColumn(h.inspections.columns, "od", "OD"),
    ["connection_condition", "connection"]].filter((c) => c !== null), h.inspections.rows, "none recorded");
  document.querySelectorAll("#inventory-table tbody tr").forEach((tr) => {
    const a = tr.querySelector("a.serial");
    tr.classList.toggle("selected", a !== null && a.textContent === h.serial);
  });
  plotHistory(h);
  setStatus("history of " + h.serial + ": " + runs.length + " runs", "ok");
}

// -- wiring -----------------------------------------------------------------------------------
function readInto(fileInput, textarea, after) {
  fileInput.addEventListener("change", () => {
    const f = fileInput.files[0];
    if (!f) { return; }
    const reader = new FileReader();
    reader.onload = () => { textarea.value = reader.result; if (after) { after(); } };
    reader.readAsText(f);
  });
}

function guarded(fn) {
  return () => fn().catch((e) => setStatus("error: " + e.message, "error"));
}

document.addEventListener("DOMContentLoaded", () => {
  readInto($("log-file"), $("log-text"));
  readInto($("components-file"), $("components-text"), () => setComponents(parseCsv($("components-text").value)));
  readInto($("survey-file"), $("survey-text"));
  readInto($("plan-file"), $("plan-text"));
  $("components-text").addEventListener("change", () => setComponents(parseCsv($("components-text").value)));
  $("constants-text").addEventListener("input", () => { state.autoConstants = false; });
  $("model-select").addEventListener("change", guarded(loadCard));
  $("reload-button").addEventListener("click", guarded(async () => {
    const r = await api("POST", "/v1/model/reload", { model: $("model-select").value });
    await loadCard();
    setStatus("reloaded " + r.reloaded.map((m) => m.name + " (generation " + m.generation + ")").join(", "), "ok");
  }));
  $("replay-button").addEventListener("click", guarded(replay));
  $("window-button").addEventListener("click", guarded(mapWindow));
  $("plan-button").addEventListener("click", guarded(rankPlans));
  $("y-name").addEventListener("change", updateAxisRange);
  $("example-button").addEventListener("click", guarded(loadExample));
  $("ledger-units").addEventListener("change", guarded(loadLedger));
  $("ledger-refresh").addEventListener("click", guarded(loadLedger));
  $("lists-button").addEventListener("click", guarded(async () => {
    const res = await loadLists();
    setStatus("lists: " + res.retire.length + " to retire, " + res.inspect.length + " to inspect", "ok");
  }));
  guarded(loadModels)();
  guarded(loadLedger)();
});
