// SpCoTMHP web page: the learned map (GET /map.png, georeferenced by GET /map.json), click to set the start,
// plan from text (POST /plan) or a WAV file (POST /plan/audio), draw the path as an SVG overlay; teach what the
// clicked spot is called (POST /teach), after which the map, its place words and later plans include it.
"use strict";

const SVG = "http://www.w3.org/2000/svg";
const $ = (id) => document.getElementById(id);
const state = { model: null, info: null, start: null };
let loads = 0;   // loadModel calls so far: an earlier call still loading when a later one starts is dropped
let asked = 0;   // plans asked for, clicks and model loads so far: a plan's answer is stale once any came after it

function toPixel([x, y]) {
  const [x0, x1, y0, y1] = state.info.extent;
  return [(x - x0) / (x1 - x0) * state.info.width, (y1 - y) / (y1 - y0) * state.info.height];
}

function toWorld(px, py) {
  const [x0, x1, y0, y1] = state.info.extent;
  return [x0 + px / state.info.width * (x1 - x0), y1 - py / state.info.height * (y1 - y0)];
}

function svgEl(tag, attrs) {
  const el = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, v);
  return el;
}

function showError(message) { $("error").textContent = message || ""; }

// the shown plan belongs to one start and one instruction: gone when either fails or the start moves
function clearPlan() {
  clearLayer("plan-layer");
  $("explanation").textContent = "";
  $("hypotheses").textContent = "";
}

function showFailure(message) {
  clearPlan();
  showError(message);
}

async function getJSON(url, options) {
  const response = await fetch(url, options);
  let body = null;
  try { body = await response.json(); } catch (e) { body = null; }
  if (!response.ok) {
    const error = new Error((body && body.detail) || `${response.status} ${response.statusText}`);
    error.body = body;   // e.g. the hypotheses heard in a spoken instruction that could not be planned
    throw error;
  }
  return body;
}

function clearLayer(id) {
  const old = $(id);
  if (old) old.remove();
}

function drawStart() {
  clearLayer("start-mark");
  if (!state.start) return;
  const [px, py] = toPixel(state.start);
  // a hollow ring with a dot: the place label drawn in the map under a start stays readable
  const g = svgEl("g", { id: "start-mark", "pointer-events": "none" });
  g.appendChild(svgEl("circle", { class: "ring", cx: px, cy: py, r: 6, fill: "none", stroke: "#fff",
                                  "stroke-width": 3.5 }));
  g.appendChild(svgEl("circle", { class: "ring", cx: px, cy: py, r: 6, fill: "none", stroke: "#00a651",
                                  "stroke-width": 2 }));
  g.appendChild(svgEl("circle", { class: "dot", cx: px, cy: py, r: 1.5, fill: "#00a651" }));
  $("overlay").appendChild(g);
  $("start").textContent = `Start: (${state.start[0].toFixed(2)}, ${state.start[1].toFixed(2)}) m`;
}

function drawPlan(plan) {
  clearLayer("plan-layer");
  const g = svgEl("g", { id: "plan-layer" });
  const points = plan.path.map((p) => toPixel(p).map((v) => v.toFixed(1)).join(",")).join(" ");
  g.appendChild(svgEl("polyline", { points, fill: "none", stroke: "#fff", "stroke-width": 7, "stroke-linejoin": "round" }));
  g.appendChild(svgEl("polyline", { id: "path", points, fill: "none", stroke: "#d00000", "stroke-width": 4,
                                    "stroke-linejoin": "round", "data-points": plan.path.length }));
  for (const place of plan.places) {
    if (!place.point || (place.role !== "waypoint" && place.role !== "goal")) continue;
    const [px, py] = toPixel(place.point);
    const colour = place.role === "goal" ? "#d00000" : "#6a3d9a";
    const mark = svgEl("circle", { class: `mark ${place.role}`, cx: px, cy: py, r: place.role === "goal" ? 9 : 7,
                                   fill: colour, "fill-opacity": 0.2, stroke: colour, "stroke-width": 2.5 });
    const title = svgEl("title", {});
    title.textContent = `${place.role}: ${place.label}`;
    mark.appendChild(title);
    g.appendChild(mark);
  }
  $("overlay").insertBefore(g, $("start-mark"));   // the start stays on top
  $("explanation").textContent = plan.explanation;
}

// The overlay takes the map image's size (an empty box until the image has loaded, which no click reaches), so
// the page takes clicks, and says so with #overlay[data-ready="1"], only once the new map is shown.
async function loadModel(name) {
  const load = ++loads;
  asked++;
  const overlay = $("overlay");
  overlay.dataset.ready = "0";
  Object.assign(state, { model: name, info: null, start: null });
  overlay.replaceChildren();
  clearPlan();
  $("taught").textContent = "";   // what was taught to the model shown before
  $("start").textContent = "Start: not set (click on the map)";
  const query = `model=${encodeURIComponent(name)}`;
  const [info, places] = await Promise.all([getJSON(`/map.json?${query}`), getJSON(`/places?${query}`)]);
  if (load !== loads) return;
  const map = $("map");
  map.src = info.image;
  await map.decode();
  if (load !== loads) return;
  state.info = info;
  overlay.setAttribute("viewBox", `0 0 ${info.width} ${info.height}`);
  $("words").textContent = `Known place words: ${places.place_words.join(", ")}`;
  overlay.dataset.ready = "1";
}

function onMapClick(event) {
  if (!state.info) return;
  const box = $("overlay").getBoundingClientRect();
  const px = (event.clientX - box.left) / box.width * state.info.width;
  const py = (event.clientY - box.top) / box.height * state.info.height;
  state.start = toWorld(px, py);
  asked++;
  showError("");
  clearPlan();
  drawStart();
}

function needStart() {
  if (state.start) return false;
  showFailure("Click on the map to set the start first.");
  return true;
}

// POST a plan request and show its answer (and ``heard(plan)`` as the hypotheses) or its error, unless the start
// moved, the model changed or another plan was asked for while it was planned: a late answer to an old question
// must not draw a path from a start that is no longer the one shown
async function requestPlan(url, options, heard) {
  const ask = ++asked;
  try {
    const plan = await getJSON(url, Object.assign({ method: "POST" }, options));
    if (ask !== asked) return;
    $("hypotheses").textContent = heard(plan);
    drawPlan(plan);
  } catch (err) {
    if (ask !== asked) return;
    showFailure(err.message);
    if (err.body && err.body.hypotheses) $("hypotheses").textContent = heard(err.body);
  }
}

async function planText(event) {
  event.preventDefault();
  if (needStart()) return;
  showError("");
  const body = { instruction: $("instruction").value, start: state.start, model: state.model };
  await requestPlan("/plan", { headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) },
                    () => "");
}

async function planAudio(event) {
  event.preventDefault();
  if (needStart()) return;
  const file = $("wav").files[0];
  if (!file) { showFailure("Choose a WAV file first."); return; }
  showError("");
  const form = new FormData();
  form.append("audio", file);
  form.append("start", state.start.join(","));
  form.append("model", state.model);
  await requestPlan("/plan/audio", { body: form },
                    (plan) => "Heard: " + plan.hypotheses.map((h) => `"${h.text}" (${h.score.toFixed(2)})`).join(", "));
}

async function teach(event) {
  event.preventDefault();
  if (!state.start) { showError("Click on the map to choose the spot first."); return; }
  showError("");
  const body = { utterance: $("utterance").value, x: state.start[0], y: state.start[1], model: state.model };
  try {
    const taught = await getJSON("/teach", { method: "POST", headers: { "Content-Type": "application/json" },
                                             body: JSON.stringify(body) });
    $("taught").textContent = `Learned: place ${taught.place} "${taught.label}"` +
      (taught.new_place ? " (a new place)" : "") + `, ${taught.places} places.`;
    $("taught").dataset.count = String(Number($("taught").dataset.count || 0) + 1);
    $("words").textContent = `Known place words: ${taught.place_words.join(", ")}`;
    $("map").src = `${state.info.image}&v=${Date.now()}`;
  } catch (err) {
    $("taught").textContent = "";
    showError(err.message);
  }
}

async function main() {
  $("overlay").addEventListener("click", onMapClick);
  $("text-form").addEventListener("submit", planText);
  $("audio-form").addEventListener("submit", planAudio);
  $("teach-form").addEventListener("submit", teach);
  try {
    const models = await getJSON("/models");
    const select = $("model");
    for (const m of models.models) select.appendChild(new Option(`${m.name} (${m.places} places)`, m.name));
    select.value = models.default;
    select.addEventListener("change", () => loadModel(select.value).catch((e) => showError(e.message)));
    await loadModel(models.default);
  } catch (err) { showError(err.message); }
}

main();
