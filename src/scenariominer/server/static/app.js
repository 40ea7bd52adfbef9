// scenariominer scenario browser. Plain JavaScript, no build step, nothing loaded from elsewhere.
// Every text that comes from the server (log and track ids, categories, explanations, programs,
// error messages) is put into the page with textContent or as a property, never parsed as HTML.
"use strict";

const COLORS = { ego: "#d62728", key: "#ff7f0e", ref: "#9467bd", other: "#8c8c8c",
  lane: "#e4e4e4", laneEdge: "#c4c4c4", cross: "rgba(144,144,192,0.35)", crossEdge: "#9090c0" };
const TAG_COLORS = ["#8dd3c7", "#ffffb3", "#bebada", "#fb8072", "#80b1d3", "#fdb462", "#b3de69",
  "#fccde5", "#d9d9d9", "#bc80bd", "#ccebc5", "#ffed6f"];

const state = {
  token: sessionStorage.getItem("scenariominer-token") || "",
  scene: null, frame: 0, playing: false, timer: null, highlight: -1, referred: null, view: null,
};

// ------------------------------------------------------------------ helpers
function $(id) { return document.getElementById(id); }

function el(tag, text, cls) {
  const e = document.createElement(tag);
  if (text !== undefined && text !== null) e.textContent = String(text);
  if (cls) e.className = cls;
  return e;
}

function fmt(v, digits = 1) { return v === null || v === undefined ? "–" : Number(v).toFixed(digits); }

function showError(message) {
  const bar = $("error-bar");
  bar.textContent = message;
  bar.hidden = !message;
}

function headers(json) {
  const h = {};
  if (json) h["Content-Type"] = "application/json";
  if (state.token) h.Authorization = "Bearer " + state.token;
  return h;
}

async function request(method, path, body) {
  const resp = await fetch(path, { method, headers: headers(body !== undefined),
    body: body === undefined ? undefined : JSON.stringify(body) });
  if (resp.status === 401) $("token-bar").hidden = false;
  let data = null;
  try { data = await resp.json(); } catch (_) { data = null; }
  if (!resp.ok) throw new Error((data && data.error) || resp.status + " " + resp.statusText);
  return data;
}
const apiGet = (path) => request("GET", path);
const apiPost = (path, body) => request("POST", path, body);

function enc(s) { return encodeURIComponent(s); }

// ------------------------------------------------------------------ views
function showView(name) {
  for (const section of document.querySelectorAll("main > section")) {
    section.hidden = section.id !== "view-" + name;
  }
  for (const b of document.querySelectorAll("nav button")) {
    b.classList.toggle("active", b.dataset.view === name);
  }
  if (name !== "detail") stopPlaying();
  if (name === "logs") loadLogs().catch((e) => showError(e.message));
  if (name === "jobs") loadJobs().catch((e) => showError(e.message));
}

// ------------------------------------------------------------------ scenarios (search)
async function loadSummary() {
  const logs = await apiGet("/api/logs?count=500");
  const categories = new Set();
  let events = 0;
  for (const log of logs) {
    events += log.n_events;
    for (const c of Object.keys(log.event_categories)) categories.add(c);
  }
  $("store-summary").textContent = logs.length + " logs, " + events + " events";
  const select = $("search-category");
  while (select.options.length > 1) select.remove(1);
  for (const c of [...categories].sort()) {
    const option = el("option", c);
    option.value = c;
    select.append(option);
  }
}

async function runSearch(event) {
  if (event) event.preventDefault();
  showError("");
  const params = new URLSearchParams();
  const text = $("search-text").value.trim();
  if (text) params.set("text", text);
  if ($("search-category").value) params.set("category", $("search-category").value);
  if ($("search-decel").value) params.set("min_decel_mps2", $("search-decel").value);
  if ($("search-ttc").value) params.set("max_ttc_s", $("search-ttc").value);
  if ($("search-sort").value) params.set("sort", $("search-sort").value);
  params.set("k", $("search-k").value || "50");
  $("search-status").textContent = "searching…";
  let hits;
  try {
    hits = await apiGet("/api/search?" + params.toString());
  } catch (e) {
    $("search-status").textContent = "";
    showError(e.message);
    return;
  }
  $("search-status").textContent = hits.length + " event(s)";
  const body = $("events-table").tBodies[0];
  body.replaceChildren();
  for (const h of hits) {
    const tr = el("tr", null, "clickable");
    tr.dataset.eventId = h.event_id;
    tr.append(el("td", h.log_id.slice(0, 13), "mono"), el("td", fmt(h.start_s) + "–" + fmt(h.end_s)),
      el("td", h.category), el("td", h.guest_category), el("td", fmt(h.min_ttc_s)),
      el("td", fmt(h.peak_decel_mps2)), el("td", fmt(h.score, 3)),
      el("td", h.explanation || h.description || "(" + h.llm_status + ")", "expl"));
    tr.title = h.event_id;
    tr.addEventListener("click", () => openScene(h.log_id, h.event_id, null));
    body.append(tr);
  }
}

// ------------------------------------------------------------------ logs
async function loadLogs() {
  const logs = await apiGet("/api/logs?count=500");
  const body = $("logs-table").tBodies[0];
  body.replaceChildren();
  for (const log of logs) {
    const tr = el("tr", null, "clickable");
    const cats = Object.entries(log.event_categories).map(([c, n]) => c + " " + n).join(", ");
    tr.append(el("td", log.log_id, "mono"), el("td", log.dataset), el("td", log.has_map ? "yes" : "no"),
      el("td", log.n_tracks), el("td", fmt(log.duration_s)), el("td", log.n_events), el("td", cats));
    tr.addEventListener("click", () => openScene(log.log_id, null, null));
    body.append(tr);
  }
}

// ------------------------------------------------------------------ detail: bird's-eye view
async function openScene(logId, eventId, referred) {
  showError("");
  const params = new URLSearchParams();
  if (eventId) params.set("event_id", eventId);
  let scene;
  try {
    scene = await apiGet("/api/scene/" + enc(logId) + "?" + params.toString());
  } catch (e) {
    showError(e.message);
    return;
  }
  stopPlaying();
  state.scene = scene;
  state.referred = referred;
  state.highlight = -1;
  state.frame = 0;
  state.view = computeView(scene);
  $("detail-title").textContent = (scene.event ? scene.event.category + " — " : "") + "log " + scene.log_id;
  fillFacts(scene);
  fillTracks(scene);
  buildTimeline(scene);
  const scrub = $("scrub");
  scrub.max = String(Math.max(0, scene.t_s.length - 1));
  scrub.value = "0";
  showView("detail");
  window.scrollTo(0, 0);
  drawFrame(0);
}

function fillFacts(scene) {
  const facts = $("event-facts");
  facts.replaceChildren();
  const e = scene.event;
  const rows = e ? [
    ["category", e.category], ["baseline (rules)", e.baseline_category], ["judge", e.judge], ["LLM status", e.llm_status],
    ["key object", e.guest_id + " (" + e.guest_category + ")"], ["time", fmt(e.start_s) + "–" + fmt(e.end_s) + " s"],
    ["min TTC", fmt(e.min_ttc_s) + " s"], ["peak decel", fmt(e.peak_decel_mps2) + " m/s²"],
    ["PET", fmt(e.pet_s) + " s"], ["headway", fmt(e.headway_s) + " s"], ["min distance", fmt(e.min_distance_m) + " m"],
  ] : [["log", scene.log_id], ["tracks", scene.track_ids.length], ["timestamps", scene.t_s.length]];
  for (const [k, v] of rows) facts.append(el("dt", k), el("dd", v));
  $("event-explanation").textContent = e ? (e.explanation || e.description || "(no explanation: " + e.llm_status + ")")
    : "(a whole log: open an event for its explanation)";
}

function fillTracks(scene) {
  const select = $("track-select");
  while (select.options.length > 1) select.remove(1);
  const list = $("track-list");
  list.replaceChildren();
  scene.track_ids.forEach((id, row) => {
    const label = id + " (" + scene.categories[row] + ")" + (row === scene.ego_index ? " ego" : "")
      + (row === scene.key_index ? " key object" : "");
    const option = el("option", label);
    option.value = String(row);
    select.append(option);
    list.append(el("li", label, "mono"));
  });
}

function computeView(scene) {
  const rows = scene.key_index >= 0 ? [scene.ego_index, scene.key_index] : scene.track_ids.map((_, i) => i);
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (const r of rows) {
    scene.x_m[r].forEach((x, t) => {
      const y = scene.y_m[r][t];
      if (x === null || y === null) return;
      x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
    });
  }
  if (!isFinite(x0)) { x0 = -20; x1 = 20; y0 = -20; y1 = 20; }
  const half = Math.max(20, 0.5 * Math.max(x1 - x0, y1 - y0) + 15);
  return { cx: 0.5 * (x0 + x1), cy: 0.5 * (y0 + y1), half };
}

function toCanvas(view, canvas, x, y) {
  const s = canvas.width / (2 * view.half);
  return [(x - view.cx + view.half) * s, canvas.height - (y - view.cy + view.half) * s];
}

function polygon(ctx, view, canvas, points, fill, stroke) {
  ctx.beginPath();
  points.forEach(([x, y], i) => {
    const [px, py] = toCanvas(view, canvas, x, y);
    if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
  });
  ctx.closePath();
  ctx.fillStyle = fill; ctx.fill();
  ctx.strokeStyle = stroke; ctx.lineWidth = 0.8; ctx.stroke();
}

function isReferred(scene, row, frame) {
  if (!state.referred) return false;
  const times = state.referred[scene.track_ids[row]];
  return !!times && times.has(scene.timestamps_ns[frame]);
}

function colorOf(scene, row, frame) {
  if (row === scene.ego_index) return COLORS.ego;
  if (row === scene.key_index || row === state.highlight) return COLORS.key;
  if (isReferred(scene, row, frame)) return COLORS.ref;
  return COLORS.other;
}

function drawFrame(frame) {
  const scene = state.scene;
  const canvas = $("bev");
  const ctx = canvas.getContext("2d");
  const view = state.view;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.fillStyle = "#ffffff";
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  for (const lane of scene.lanes) polygon(ctx, view, canvas, lane, COLORS.lane, COLORS.laneEdge);
  for (const cross of scene.crossings) polygon(ctx, view, canvas, cross, COLORS.cross, COLORS.crossEdge);
  const n = scene.track_ids.length;
  const order = [...Array(n).keys()].sort((a, b) => rank(scene, a) - rank(scene, b));
  for (const row of order) {
    const color = colorOf(scene, row, frame);
    if (color !== COLORS.other) drawTrail(ctx, view, canvas, scene, row, frame, color);
    drawBox(ctx, view, canvas, scene, row, frame, color);
  }
  state.frame = frame;
  canvas.dataset.frame = String(frame);
  $("scrub").value = String(frame);
  $("time-label").textContent = fmt(scene.t_s[frame]) + " s / " + fmt(scene.t_s[scene.t_s.length - 1]) + " s";
  moveTimelineCursor(frame);
}

function rank(scene, row) {
  if (row === scene.ego_index) return 3;
  if (row === scene.key_index || row === state.highlight) return 2;
  return 1;
}

function drawTrail(ctx, view, canvas, scene, row, frame, color) {
  ctx.beginPath();
  let started = false;
  for (let t = 0; t <= frame; t++) {
    const x = scene.x_m[row][t], y = scene.y_m[row][t];
    if (x === null || y === null) { started = false; continue; }
    const [px, py] = toCanvas(view, canvas, x, y);
    if (!started) { ctx.moveTo(px, py); started = true; } else ctx.lineTo(px, py);
  }
  ctx.strokeStyle = color; ctx.lineWidth = 1.5; ctx.stroke();
}

function drawBox(ctx, view, canvas, scene, row, frame, color) {
  const x = scene.x_m[row][frame], y = scene.y_m[row][frame], yaw = scene.yaw_rad[row][frame];
  if (x === null || y === null || yaw === null) return;
  const hl = 0.5 * (scene.length_m[row][frame] || 1), hw = 0.5 * (scene.width_m[row][frame] || 1);
  const c = Math.cos(yaw), s = Math.sin(yaw);
  const corners = [[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]].map(([a, b]) => [x + a * c - b * s, y + a * s + b * c]);
  polygon(ctx, view, canvas, corners, color, "#000000");
  const [fx, fy] = toCanvas(view, canvas, x + hl * c, y + hl * s);
  const [cx, cy] = toCanvas(view, canvas, x, y);
  ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(fx, fy); ctx.strokeStyle = "#000"; ctx.lineWidth = 1; ctx.stroke();
}

// ------------------------------------------------------------------ player
function stopPlaying() {
  state.playing = false;
  if (state.timer !== null) cancelAnimationFrame(state.timer);
  state.timer = null;
  $("play-button").textContent = "Play";
}

function startPlaying() {
  const scene = state.scene;
  if (!scene || scene.t_s.length < 2) return;
  if (state.frame >= scene.t_s.length - 1) drawFrame(0);
  state.playing = true;
  $("play-button").textContent = "Pause";
  const t0Scene = scene.t_s[state.frame];
  const t0Wall = performance.now();
  const step = (now) => {
    if (!state.playing || state.scene !== scene) return;
    const target = t0Scene + (now - t0Wall) / 1000;
    let f = state.frame;
    while (f < scene.t_s.length - 1 && scene.t_s[f + 1] <= target) f++;
    if (f !== state.frame) drawFrame(f);
    if (f >= scene.t_s.length - 1) { stopPlaying(); return; }
    state.timer = requestAnimationFrame(step);
  };
  state.timer = requestAnimationFrame(step);
}

// ------------------------------------------------------------------ tags timeline
function tagColor(value) {
  let h = 0;
  for (const ch of String(value)) h = (h * 31 + ch.charCodeAt(0)) >>> 0;
  return TAG_COLORS[h % TAG_COLORS.length];
}

function buildTimeline(scene) {
  const box = $("tags-timeline");
  box.replaceChildren();
  const families = Object.keys(scene.tags);
  if (families.length === 0) {
    box.append(el("p", scene.event ? "(no tags stored for this log)" : "(open an event to see its tags)"));
    return;
  }
  for (const family of families) {
    const values = scene.tags[family];
    const row = el("div", null, "tagrow");
    row.append(el("span", family.replace("ego_", "ego ").replace("_", " "), "tagname"));
    const strip = el("div", null, "tagstrip");
    let start = 0;
    for (let t = 1; t <= values.length; t++) {
      if (t < values.length && values[t] === values[start]) continue;
      const seg = el("span");
      seg.style.flexGrow = String(t - start);
      seg.style.background = values[start] === null ? "#ffffff" : tagColor(values[start]);
      seg.title = (values[start] === null ? "—" : values[start]) + " (" + fmt(scene.t_s[start]) + "–" + fmt(scene.t_s[t - 1]) + " s)";
      strip.append(seg);
      start = t;
    }
    const cursor = el("div", null, "cursor");
    strip.append(cursor);
    row.append(strip);
    box.append(row);
  }
}

function moveTimelineCursor(frame) {
  const n = state.scene.t_s.length;
  const pct = n > 1 ? (100 * frame) / (n - 1) : 0;
  for (const c of document.querySelectorAll("#tags-timeline .cursor")) c.style.left = pct + "%";
}

// ------------------------------------------------------------------ jobs and mining
async function followJob(jobId, onEvent) {
  // Server-Sent Events read with fetch (EventSource cannot send the bearer token).
  const resp = await fetch("/api/jobs/" + enc(jobId) + "/events", { headers: headers(false) });
  if (!resp.ok) throw new Error("cannot follow job " + jobId + ": " + resp.status);
  const reader = resp.body.getReader();
  const decoder = new TextDecoder();
  let buffer = "";
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    buffer += decoder.decode(value, { stream: true });
    let cut;
    while ((cut = buffer.indexOf("\n\n")) >= 0) {
      const block = buffer.slice(0, cut);
      buffer = buffer.slice(cut + 2);
      let type = "message", data = "";
      for (const line of block.split("\n")) {
        if (line.startsWith("event: ")) type = line.slice(7);
        else if (line.startsWith("data: ")) data += line.slice(6);
      }
      if (data) onEvent(type, JSON.parse(data));
      if (type === "end") return;
    }
  }
}

async function runMine(event) {
  event.preventDefault();
  showError("");
  const body = { description: $("mine-description").value, use_bank: $("mine-bank").checked };
  const program = $("mine-program").value;
  if (program.trim()) body.program = program;
  $("mine-result").hidden = true;
  let job;
  try {
    job = await apiPost("/api/jobs/mine", body);
  } catch (e) {
    showError(e.message);
    return;
  }
  $("mine-status").textContent = "job " + job.id.slice(0, 8) + " queued";
  let final = null;
  try {
    await followJob(job.id, (type, data) => {
      if (type === "state") $("mine-status").textContent = "job " + job.id.slice(0, 8) + ": " + data.state;
      if (type === "progress") $("mine-status").textContent = "job " + job.id.slice(0, 8) + ": " + data.step
        + (data.message ? " (" + data.message + ")" : "");
      if (type === "end") final = data;
    });
  } catch (e) {
    showError(e.message);
    return;
  }
  if (!final) final = await apiGet("/api/jobs/" + enc(job.id));
  if (final.state !== "succeeded") {
    $("mine-status").textContent = "job " + job.id.slice(0, 8) + ": " + final.state;
    showError(final.error || final.state);
    return;
  }
  $("mine-status").textContent = "job " + job.id.slice(0, 8) + ": succeeded";
  showMineResult(final.result);
}

function showMineResult(result) {
  const flags = $("mine-flags");
  flags.replaceChildren();
  const review = result.needs_review === true || result.status === "manual_review";
  const flag = el("span", review ? "needs review" : "no review flag", review ? "flag review" : "flag");
  flags.append(flag, el("span", "  source: " + result.source + ", status: " + result.status
    + ", confidence: " + (result.confidence === null || result.confidence === undefined ? "–" : fmt(result.confidence, 2))
    + ", " + result.summary.n_matching_logs + " of " + result.summary.n_logs + " log(s) match"));
  $("mine-program-shown").textContent = result.program || "(no program: manual review)";
  const body = $("mine-objects").tBodies[0];
  body.replaceChildren();
  const byLog = {};
  for (const o of result.referred_objects) {
    (byLog[o.log_id] = byLog[o.log_id] || {})[o.track_id] = new Set(o.timestamps_ns);
  }
  for (const o of result.referred_objects) {
    const tr = el("tr", null, "clickable");
    tr.append(el("td", o.log_id.slice(0, 13), "mono"), el("td", o.track_id, "mono"), el("td", o.category),
      el("td", o.n_timestamps), el("td", fmt(o.first_ns / 1e9 % 1000)), el("td", fmt(o.last_ns / 1e9 % 1000)));
    tr.title = "show " + o.log_id + " with its referred objects on the map";
    tr.addEventListener("click", () => openScene(o.log_id, null, byLog[o.log_id]));
    body.append(tr);
  }
  for (const f of result.failures) showError("failed on " + f.log_id + ": " + f.error);
  $("mine-result").hidden = false;
}

function progressText(p) {
  if (!p) return "";
  if (p.total === 0) return p.step + ": nothing to do";
  return p.step + " " + p.done + (p.total !== null ? "/" + p.total : "");
}

async function loadJobs() {
  const jobs = await apiGet("/api/jobs?count=100");
  const body = $("jobs-table").tBodies[0];
  body.replaceChildren();
  for (const j of jobs) {
    const tr = el("tr");
    const progress = progressText(j.progress);
    const cell = el("td");
    if (j.state === "queued" || j.state === "running") {
      const b = el("button", "Cancel");
      b.type = "button";
      b.addEventListener("click", async () => {
        try { await apiPost("/api/jobs/" + enc(j.id) + "/cancel"); await loadJobs(); } catch (e) { showError(e.message); }
      });
      cell.append(b);
    }
    tr.append(el("td", j.id.slice(0, 8), "mono"), el("td", j.kind), el("td", j.state), el("td", progress),
      el("td", j.created_at.replace("T", " ").slice(0, 19)), el("td", j.error || ""), cell);
    body.append(tr);
  }
}

async function submitJob(path, body) {
  showError("");
  let job;
  try {
    job = await apiPost(path, body);
  } catch (e) {
    showError(e.message);
    return;
  }
  await loadJobs();
  const label = job.kind + " " + job.id.slice(0, 8);
  try {
    await followJob(job.id, (type, data) => {
      if (type === "progress") {
        $("job-status").textContent = label + ": " + progressText(data);
      }
      if (type === "state") $("job-status").textContent = label + ": " + data.state;
      if (type === "end" && data.error) showError(data.error);
    });
  } catch (e) {
    showError(e.message);
  }
  await loadJobs();
  await loadSummary();
}

// ------------------------------------------------------------------ wiring
function init() {
  for (const b of document.querySelectorAll("nav button")) b.addEventListener("click", () => showView(b.dataset.view));
  $("search-form").addEventListener("submit", runSearch);
  $("mine-form").addEventListener("submit", runMine);
  $("detail-back").addEventListener("click", () => showView("scenarios"));
  $("ingest-form").addEventListener("submit", (e) => {
    e.preventDefault();
    submitJob("/api/jobs/ingest", { paths: [$("ingest-path").value] });
  });
  $("analyze-form").addEventListener("submit", (e) => {
    e.preventDefault();
    submitJob("/api/jobs/analyze", { llm: $("analyze-llm").checked });
  });
  $("jobs-refresh").addEventListener("click", () => loadJobs().catch((e) => showError(e.message)));
  $("play-button").addEventListener("click", () => (state.playing ? stopPlaying() : startPlaying()));
  $("scrub").addEventListener("input", () => { stopPlaying(); drawFrame(Number($("scrub").value)); });
  $("track-select").addEventListener("change", () => { state.highlight = Number($("track-select").value); drawFrame(state.frame); });
  $("token-save").addEventListener("click", () => {
    state.token = $("token-input").value;
    sessionStorage.setItem("scenariominer-token", state.token);
    $("token-bar").hidden = true;
    loadSummary().then(() => runSearch()).catch((e) => showError(e.message));
  });
  loadSummary().then(() => runSearch()).catch((e) => showError(e.message));
}

document.addEventListener("DOMContentLoaded", init);
