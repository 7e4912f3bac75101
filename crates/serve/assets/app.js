// gridplan serve: the page. Maps, planning and results come from the server's JSON API;
// every string from there is put in the page with textContent, never as HTML.
"use strict";

const SLOTS = 4;
// One colour per planner slot: path (opaque), expanded cells (light, drawn under it) and
// OPEN's frontier, the cells generated and not yet expanded (a stronger tone).
const PATH_COLORS = ["#e6194b", "#3c3cdc", "#f58231", "#911eb4"];
const EXPANDED_COLORS = [[255, 205, 210], [200, 210, 255], [255, 225, 190], [230, 205, 240]];
const FRONTIER_COLORS = [[240, 128, 140], [120, 140, 240], [245, 170, 100], [190, 130, 215]];
const FREE_RGB = [255, 255, 255];
const BLOCKED_RGB = [45, 45, 45];
// A ROS map's unknown cells (map_server's -1): grey, as map_server's images and RViz show
// them, between free white and occupied black. They are blocked like walls.
const UNKNOWN_RGB = [160, 160, 160];
const START_COLOR = "#00a03c";
const GOAL_COLOR = "#00b4c8";

const state = {
  planners: [],
  map: null, // {path, name, width, height, blocked: Uint8Array, unknown: Uint8Array, problems}
  // The map load generation: raised by every "Load map", so that a run started on the
  // map before can tell that its answer no longer belongs on the page.
  loadGen: 0,
  edits: new Map(), // cell index -> free (0 or 1)
  start: null,
  goal: null,
  base: null, // offscreen canvas, one pixel per cell
  baseData: null,
  view: { cell: 1, x: 0, y: 0 },
  results: [], // {slot, name, label, plan, expanded: Int32Array, shown, canvas, data, pixels}
  playing: false,
  run: null, // the plan in progress: {gen, id, cancelled}
  // Raised whenever start, goal or walls change: a plan answered for an older query is
  // not drawn, and the plan drawn is cleared (its path was for another query).
  queryGen: 0,
  runs: null, // the open results directory
};

const $ = (id) => document.getElementById(id);

function setStatus(text, isError) {
  const status = $("status");
  status.textContent = text;
  status.className = isError ? "error" : "";
}

async function getJson(url, options) {
  const response = await fetch(url, options);
  let body = null;
  try {
    body = await response.json();
  } catch (_) {
    body = null;
  }
  if (!response.ok) {
    const message = body && body.error ? body.error : `${response.status} ${response.statusText}`;
    const error = new Error(message);
    error.status = response.status;
    error.body = body;
    throw error;
  }
  return body;
}

function option(select, value, text) {
  const o = document.createElement("option");
  o.value = value;
  o.textContent = text;
  select.appendChild(o);
  return o;
}

// ---- planners and their parameters -------------------------------------------------

function tomlValue(value) {
  return typeof value === "string" ? JSON.stringify(value) : String(value);
}

function buildSlots() {
  const box = $("planner-slots");
  for (let i = 0; i < SLOTS; i++) {
    const slot = document.createElement("div");
    slot.className = "slot";
    slot.dataset.slot = String(i);
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = PATH_COLORS[i];
    const select = document.createElement("select");
    select.className = "planner";
    select.setAttribute("aria-label", `planner ${i + 1}`);
    option(select, "", "(none)");
    for (const p of state.planners) option(select, p.name, p.name).title = p.summary;
    const params = document.createElement("div");
    params.className = "params";
    select.addEventListener("change", () => buildParams(params, select.value));
    slot.append(swatch, select, params);
    box.appendChild(slot);
  }
  const first = box.querySelector(".planner");
  if (first && state.planners.some((p) => p.name === "astar")) {
    first.value = "astar";
    buildParams(first.parentElement.querySelector(".params"), "astar");
  }
}

function buildParams(box, name) {
  box.replaceChildren();
  const planner = state.planners.find((p) => p.name === name);
  if (!planner) return;
  for (const param of planner.params) {
    const label = document.createElement("label");
    label.title = param.doc || "";
    label.append(document.createTextNode(`${param.key} `));
    let input;
    if (param.allowed && param.allowed.length > 0) {
      input = document.createElement("select");
      for (const value of param.allowed) {
        const o = option(input, tomlValue(value), String(value));
        if (JSON.stringify(value) === JSON.stringify(param.default)) o.selected = true;
      }
      input.dataset.default = param.default === null ? "" : tomlValue(param.default);
    } else {
      input = document.createElement("input");
      input.type = "text";
      input.placeholder = param.default === null || param.default === undefined ? "unset" : String(param.default);
      input.dataset.default = "";
    }
    input.dataset.key = param.key;
    label.appendChild(input);
    box.appendChild(label);
  }
}

// The slot's `key=value` settings: only values changed from the default.
function slotSettings(slot) {
  const set = [];
  for (const input of slot.querySelectorAll(".params [data-key]")) {
    const value = input.value.trim();
    if (value === "" || value === input.dataset.default) continue;
    set.push(`${input.dataset.key}=${value}`);
  }
  return set;
}

// ---- maps --------------------------------------------------------------------------

async function loadLists() {
  const lists = await getJson("/api/maps");
  for (const path of lists.maps) option($("map-select"), path, path);
  for (const path of lists.results) option($("results-select"), path, path);
}

// The cost options of the map controls, as /api/map and /api/plan take them.
function mapCosts() {
  const weights = $("weights").value.trim();
  const costs = { graded: $("graded").checked };
  if (weights !== "") costs.weights = weights;
  return costs;
}

async function loadMap(path) {
  // A new map ends the plan in progress: its answers are for the map it started on.
  const gen = ++state.loadGen;
  cancelRun();
  state.run = null;
  $("cancel").disabled = true;
  $("run").disabled = false;
  setStatus(`loading ${path} ...`);
  const costs = mapCosts();
  let url = `/api/map?path=${encodeURIComponent(path)}`;
  if (costs.weights) url += `&weights=${encodeURIComponent(costs.weights)}`;
  if (costs.graded) url += "&graded=1";
  const map = await getJson(url);
  // A later "Load map" came first: its map is the one shown.
  if (gen !== state.loadGen) return false;
  // Cells: "0" free, "1" blocked, "2" a ROS map's unknown cell (blocked too).
  const blocked = new Uint8Array(map.width * map.height);
  const unknown = new Uint8Array(map.width * map.height);
  let unknownCount = 0;
  for (let i = 0; i < blocked.length; i++) {
    const c = map.cells.charCodeAt(i);
    blocked[i] = c === 49 || c === 50 ? 1 : 0;
    unknown[i] = c === 50 ? 1 : 0;
    unknownCount += unknown[i];
  }
  // Weighted maps: free cells shaded from white (the least weight) to dark amber (the most).
  const weights = map.weights ? Uint16Array.from(map.weights) : null;
  let range = null;
  if (weights) {
    let low = 65535, high = 1;
    for (let i = 0; i < weights.length; i++) if (!blocked[i]) { low = Math.min(low, weights[i]); high = Math.max(high, weights[i]); }
    range = [low, Math.max(high, low)];
  }
  state.map = { path: map.path, name: map.name, width: map.width, height: map.height, blocked, unknown, unknownCount, problems: map.problems, weights, range, costs, rule: map.cost_rule, frame: map.frame, gen, version: map.version };
  state.edits = new Map();
  state.start = null;
  state.goal = null;
  state.results = [];
  state.playing = false;
  const base = document.createElement("canvas");
  base.width = map.width;
  base.height = map.height;
  state.base = base;
  state.baseData = base.getContext("2d").createImageData(map.width, map.height);
  for (let i = 0; i < blocked.length; i++) paintBase(i);
  base.getContext("2d").putImageData(state.baseData, 0, 0);
  const problems = $("problem-select");
  problems.replaceChildren();
  option(problems, "", `(none of ${map.problems.length})`);
  map.problems.forEach((p, i) => {
    const bucket = p[4] === null ? "" : `, bucket ${p[4]}`;
    option(problems, String(i), `${i + 1}: (${p[0]}, ${p[1]}) -> (${p[2]}, ${p[3]})${bucket}`);
  });
  $("map-select").value = map.path;
  state.viewSize = null;
  layoutViews();
  updateEnds();
  draw();
  const weighted = weights ? `, weights ${range[0]}-${range[1]} (${map.cost_rule} rule; darker costs more)` : "";
  const grey = unknownCount > 0 ? `, ${unknownCount} unknown cells (grey, blocked)` : "";
  setStatus(`${map.name}: ${map.width} x ${map.height}${weighted}${grey}`);
  return true;
}

// A free cell's shade on a weighted map, `t` from 0 (the least weight) to 1 (the most).
function weightRgb(t) {
  return [255 - 80 * t, 255 - 140 * t, 255 - 230 * t].map(Math.round);
}

function paintBase(i) {
  let rgb = state.map.blocked[i] ? (state.map.unknown[i] ? UNKNOWN_RGB : BLOCKED_RGB) : FREE_RGB;
  const { weights, range } = state.map;
  if (weights && !state.map.blocked[i] && range[1] > range[0]) {
    rgb = weightRgb((weights[i] - range[0]) / (range[1] - range[0]));
  }
  const d = state.baseData.data;
  d[4 * i] = rgb[0];
  d[4 * i + 1] = rgb[1];
  d[4 * i + 2] = rgb[2];
  d[4 * i + 3] = 255;
}

function setWall(x, y, blocked) {
  const map = state.map;
  const i = y * map.width + x;
  if (map.blocked[i] === blocked) return;
  if ((state.start && state.start[0] === x && state.start[1] === y) || (state.goal && state.goal[0] === x && state.goal[1] === y)) return;
  map.blocked[i] = blocked;
  queryChanged("The walls");
  // An edited cell is known: a wall or free, as drawn.
  map.unknown[i] = 0;
  state.edits.set(i, blocked ? 0 : 1);
  paintBase(i);
  state.base.getContext("2d").putImageData(state.baseData, 0, 0, x, y, 1, 1);
}

function updateEnds() {
  $("start-out").textContent = state.start ? where(state.start) : "-";
  $("goal-out").textContent = state.goal ? where(state.goal) : "-";
  // The keyboard's way to set them: the cell fields show the cells set by clicks too.
  for (const end of ["start", "goal"]) {
    const cell = state[end];
    $(`${end}-x`).value = cell ? String(cell[0]) : "";
    $(`${end}-y`).value = cell ? String(cell[1]) : "";
    $(`${end}-x`).removeAttribute("aria-invalid");
    $(`${end}-y`).removeAttribute("aria-invalid");
  }
}

// Start, goal or walls changed: the plan drawn (path, search, counters) was for the query
// before, so it is cleared, and a plan under way will not be drawn when it answers.
function queryChanged(what) {
  state.queryGen++;
  if (state.results.length === 0) return;
  state.results = [];
  state.playing = false;
  layoutViews();
  setStatus(`${what} changed: the plan shown was for the query before; Plan again`);
}

// Sets `end` ("start" or "goal") from its x and y fields (the keyboard's way to set them);
// says which field is wrong when they name no free cell of the map.
function endFromFields(end) {
  const name = end === "start" ? "Start" : "Goal";
  if (!state.map) {
    setStatus("load a map first", true);
    return;
  }
  const fields = [$(`${end}-x`), $(`${end}-y`)];
  const texts = fields.map((f) => f.value.trim());
  if (texts.some((t) => t === "") && !fields.some((f) => f.validity.badInput)) return;
  const sides = [state.map.width, state.map.height];
  for (let k = 0; k < 2; k++) {
    const n = Number(texts[k]);
    if (fields[k].validity.badInput || !/^\d+$/.test(texts[k]) || n >= sides[k]) {
      fields[k].setAttribute("aria-invalid", "true");
      setStatus(`${name} ${"xy"[k]}: ${JSON.stringify(texts[k])} is not a whole number from 0 to ${sides[k] - 1}`, true);
      return;
    }
  }
  const cell = texts.map(Number);
  const i = cell[1] * state.map.width + cell[0];
  if (state.map.blocked[i]) {
    fields[0].setAttribute("aria-invalid", "true");
    setStatus(`${name}: (${cell[0]}, ${cell[1]}) is ${state.map.unknown[i] ? "unknown (blocked)" : "a wall"}`, true);
    return;
  }
  if (state[end] && state[end][0] === cell[0] && state[end][1] === cell[1]) return;
  state[end] = cell;
  queryChanged(name);
  updateEnds();
  draw();
}

// A cell as `(x, y)`, and on a ROS map also its centre in the map frame, in metres (as
// `gridplan plan` prints it: nav2's mapToWorld, the image's top row is row 0).
function where(cell) {
  const text = `(${cell[0]}, ${cell[1]})`;
  const frame = state.map && state.map.frame;
  if (!frame) return text;
  const x = frame.origin[0] + frame.resolution * (cell[0] + 0.5);
  const y = frame.origin[1] + frame.resolution * (state.map.height - 1 - cell[1] + 0.5);
  return `${text} = (${metres(x)}, ${metres(y)}) m`;
}

// At most six decimals, trailing zeros left out (`-1.4749999999999996` reads `-1.475`).
function metres(value) {
  const text = value.toFixed(6).replace(/\.?0+$/, "");
  return text === "-0" ? "0" : text;
}

// ---- views: canvases, zoom and pan ---------------------------------------------------

function layout() {
  const checked = document.querySelector('input[name="layout"]:checked');
  return checked ? checked.value : "side";
}

function layoutViews() {
  const views = $("views");
  views.replaceChildren();
  const overlay = layout() === "overlay" || state.results.length <= 1;
  const panels = overlay ? [state.results] : state.results.map((r) => [r]);
  // At most 720, 560 or 420 pixels a side, and no wider than the views' column (less a
  // view's border and padding), so a narrow window shows the canvas whole.
  const room = Math.floor(views.clientWidth) - 12;
  const size = Math.max(120, Math.min(panels.length <= 1 ? 720 : panels.length === 2 ? 560 : 420, room > 0 ? room : 720));
  const resized = state.viewSize !== size;
  state.viewSize = size;
  panels.forEach((results, k) => {
    const view = document.createElement("div");
    view.className = "view";
    view.dataset.view = String(k);
    const title = document.createElement("h3");
    title.textContent = results.length === 0 ? (state.map ? state.map.name : "no map") : results.map((r) => r.label).join(" + ");
    const key = mapKey();
    const canvas = document.createElement("canvas");
    canvas.width = size;
    canvas.height = size;
    canvas.addEventListener("contextmenu", (e) => e.preventDefault());
    canvas.addEventListener("pointerdown", (e) => pointerDown(e, canvas));
    canvas.addEventListener("pointermove", (e) => pointerMove(e, canvas));
    canvas.addEventListener("pointerup", () => pointerUp());
    canvas.addEventListener("wheel", (e) => wheel(e, canvas), { passive: false });
    view.append(title, key, canvas);
    for (const r of results) {
      r.canvasEl = canvas;
      r.viewEl = view;
      view.appendChild(countersTable(r));
    }
    views.appendChild(view);
  });
  if (resized) fitView();
}

// The key of the map's colours: free, wall, and a ROS map's unknown cells when it has any.
function mapKey() {
  const key = document.createElement("p");
  key.className = "map-key";
  const css = (rgb) => `rgb(${rgb.join(",")})`;
  const tones = [["free", css(FREE_RGB)], ["wall", css(BLOCKED_RGB)]];
  if (state.map && state.map.unknownCount > 0) tones.push(["unknown (blocked)", css(UNKNOWN_RGB)]);
  if (state.map && state.map.weights && state.map.range[1] > state.map.range[0]) {
    const [low, high] = state.map.range;
    tones.push([`weight ${low} to ${high}`, `linear-gradient(to right, ${css(weightRgb(0))}, ${css(weightRgb(1))})`]);
  }
  tones.push(["start", START_COLOR], ["goal", GOAL_COLOR], ["path (its planner's colour)", PATH_COLORS[0]]);
  for (const [what, background] of tones) {
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.dataset.tone = what;
    swatch.style.background = background;
    key.append(swatch, document.createTextNode(` ${what} `));
  }
  return key;
}

function canvases() {
  return Array.from(document.querySelectorAll("#views canvas"));
}

function fitView() {
  const canvas = canvases()[0];
  if (!canvas || !state.map) return;
  const { width, height } = state.map;
  let cell = Math.min(canvas.width / width, canvas.height / height);
  if (cell >= 1) cell = Math.floor(cell);
  state.view.cell = cell;
  state.view.x = Math.round((canvas.width - width * cell) / 2);
  state.view.y = Math.round((canvas.height - height * cell) / 2);
}

function cellAt(e) {
  const v = state.view;
  const x = Math.floor((e.offsetX - v.x) / v.cell);
  const y = Math.floor((e.offsetY - v.y) / v.cell);
  if (!state.map || x < 0 || y < 0 || x >= state.map.width || y >= state.map.height) return null;
  return [x, y];
}

let drag = null;

function tool() {
  const checked = document.querySelector('input[name="tool"]:checked');
  return checked ? checked.value : "start";
}

function pointerDown(e, canvas) {
  if (!state.map) return;
  canvas.setPointerCapture(e.pointerId);
  const t = tool();
  if (e.button === 2 || t === "pan") {
    drag = { kind: "pan", x: e.offsetX, y: e.offsetY };
    return;
  }
  const cell = cellAt(e);
  if (!cell) return;
  if (t === "start" || t === "goal") {
    const i = cell[1] * state.map.width + cell[0];
    if (state.map.blocked[i]) {
      setStatus(`(${cell[0]}, ${cell[1]}) is ${state.map.unknown[i] ? "unknown (blocked)" : "a wall"}`, true);
      return;
    }
    const same = state[t] && state[t][0] === cell[0] && state[t][1] === cell[1];
    state[t] = cell;
    if (!same) queryChanged(t === "start" ? "Start" : "Goal");
    updateEnds();
    draw();
    return;
  }
  drag = { kind: t };
  setWall(cell[0], cell[1], t === "wall" ? 1 : 0);
  draw();
}

function pointerMove(e) {
  const under = cellAt(e);
  $("cursor-out").textContent = under ? where(under) : "-";
  if (!drag) return;
  if (drag.kind === "pan") {
    state.view.x += e.offsetX - drag.x;
    state.view.y += e.offsetY - drag.y;
    drag.x = e.offsetX;
    drag.y = e.offsetY;
    draw();
    return;
  }
  const cell = cellAt(e);
  if (cell) {
    setWall(cell[0], cell[1], drag.kind === "wall" ? 1 : 0);
    draw();
  }
}

function pointerUp() {
  drag = null;
}

function wheel(e) {
  e.preventDefault();
  const v = state.view;
  const factor = e.deltaY < 0 ? 1.25 : 0.8;
  let cell = Math.min(64, Math.max(0.05, v.cell * factor));
  if (cell >= 1) cell = Math.round(cell);
  if (cell === v.cell) cell = e.deltaY < 0 ? v.cell + 1 : Math.max(0.05, v.cell - 1);
  v.x = Math.round(e.offsetX - ((e.offsetX - v.x) * cell) / v.cell);
  v.y = Math.round(e.offsetY - ((e.offsetY - v.y) * cell) / v.cell);
  v.cell = cell;
  draw();
}

// ---- drawing -----------------------------------------------------------------------

// The cells a straight segment between two cell centres passes (sampled every quarter
// cell), for any-angle paths.
function segmentCells(a, b) {
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const steps = Math.max(1, Math.ceil(Math.max(Math.abs(dx), Math.abs(dy)) * 4));
  const cells = [];
  for (let i = 0; i <= steps; i++) {
    const t = i / steps;
    cells.push([Math.round(a[0] + dx * t), Math.round(a[1] + dy * t)]);
  }
  return cells;
}

function pathCells(path) {
  if (path.length === 1) return [path[0]];
  const cells = [];
  for (let i = 1; i < path.length; i++) cells.push(...segmentCells(path[i - 1], path[i]));
  return cells;
}

function fillCell(ctx, x, y, color) {
  const v = state.view;
  ctx.fillStyle = color;
  const px = v.x + x * v.cell;
  const py = v.y + y * v.cell;
  const size = Math.max(v.cell, 1);
  ctx.fillRect(px, py, size, size);
}

// The smallest marker drawn for start and goal, in pixels: its radius. On a map whose
// cells are drawn smaller (den520d on the canvas: 2 pixels a cell), the cell is ringed.
const MARKER_RADIUS = 8;

// Start or goal: its cell filled, and when cells are drawn smaller than the marker, a ring
// and a dot in its colour around the cell's centre, so it shows at any zoom.
function marker(ctx, cell, color) {
  fillCell(ctx, cell[0], cell[1], color);
  const v = state.view;
  if (v.cell >= 2 * MARKER_RADIUS) return;
  const cx = v.x + (cell[0] + 0.5) * v.cell;
  const cy = v.y + (cell[1] + 0.5) * v.cell;
  ctx.strokeStyle = color;
  ctx.lineWidth = 3;
  ctx.beginPath();
  ctx.arc(cx, cy, MARKER_RADIUS, 0, 2 * Math.PI);
  ctx.stroke();
  ctx.fillStyle = color;
  ctx.beginPath();
  ctx.arc(cx, cy, 3, 0, 2 * Math.PI);
  ctx.fill();
}

function draw() {
  if (!state.map) return;
  const v = state.view;
  const width = state.map.width * v.cell;
  const height = state.map.height * v.cell;
  for (const canvas of canvases()) {
    const ctx = canvas.getContext("2d");
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.imageSmoothingEnabled = false;
    ctx.fillStyle = "#d8d8d8";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.drawImage(state.base, v.x, v.y, width, height);
    const results = state.results.filter((r) => r.canvasEl === canvas);
    for (const r of results) {
      if (r.dirty) {
        r.search.getContext("2d").putImageData(r.searchData, 0, 0);
        r.dirty = false;
      }
      ctx.drawImage(r.search, v.x, v.y, width, height);
    }
    for (const r of results) {
      if (r.shown >= r.expanded.length && r.plan.path.length > 0) {
        for (const [x, y] of pathCells(r.plan.path)) fillCell(ctx, x, y, PATH_COLORS[r.slot]);
      }
    }
    if (state.start) marker(ctx, state.start, START_COLOR);
    if (state.goal) marker(ctx, state.goal, GOAL_COLOR);
  }
  for (const r of state.results) {
    const done = r.shown >= r.expanded.length;
    r.viewEl.dataset[`done${r.slot}`] = done ? "1" : "0";
    const row = r.viewEl.querySelector(`table[data-slot="${r.slot}"] .shown`);
    if (row) row.textContent = `${r.shown} of ${r.expandedTotal}`;
  }
}

// ---- planning ----------------------------------------------------------------------

function countersTable(r) {
  const table = document.createElement("table");
  table.className = "counters";
  table.dataset.slot = String(r.slot);
  table.dataset.planner = r.name;
  const caption = document.createElement("caption");
  const swatch = document.createElement("span");
  swatch.className = "swatch";
  swatch.style.background = PATH_COLORS[r.slot];
  caption.append(swatch, document.createTextNode(r.label));
  table.appendChild(caption);
  const body = document.createElement("tbody");
  const row = (key, value, cls) => {
    const tr = document.createElement("tr");
    const th = document.createElement("th");
    th.textContent = key;
    const td = document.createElement("td");
    td.textContent = value;
    td.dataset.key = key;
    if (cls) td.className = cls;
    tr.append(th, td);
    body.appendChild(tr);
  };
  const plan = r.plan;
  row("status", plan.status);
  if (plan.metrics) {
    for (const key of ["steps", "turns", "score", "length"]) row(key, String(plan.metrics[key]));
  }
  if (plan.cost !== undefined) row("cost", String(plan.cost));
  for (const [key, value] of Object.entries(plan.counters)) row(key, String(value));
  row("time_ms", r.timeMs.toFixed(3));
  // A run with no expanded cells to draw (a recorded run of a results directory, a search
  // stopped by the time limit) has no playback: no count of it, no key of its tones.
  if (r.expandedTotal === 0) {
    table.appendChild(body);
    return table;
  }
  row("expanded shown", "", "shown");
  // What the search view's two tones are, for planners that record their frontier.
  const tones = [["expanded", EXPANDED_COLORS[r.slot]]];
  if (r.generated.length > 0) tones.push(["generated, not yet expanded", FRONTIER_COLORS[r.slot]]);
  const key = document.createElement("tr");
  const th = document.createElement("th");
  th.textContent = "shading";
  const td = document.createElement("td");
  td.dataset.key = "shading";
  for (const [what, rgb] of tones) {
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = `rgb(${rgb.join(",")})`;
    td.append(swatch, document.createTextNode(` ${what} `));
  }
  key.append(th, td);
  body.appendChild(key);
  table.appendChild(body);
  return table;
}

// A result drawn on `map`, the map its run was planned on; null when that map is no longer
// the one shown (a "Load map" came since): it is dropped, never drawn on another map.
function newResult(map, slot, name, label, response) {
  if (map !== state.map || map.gen !== state.loadGen) return null;
  const { width, height } = map;
  const search = document.createElement("canvas");
  search.width = width;
  search.height = height;
  const searchData = search.getContext("2d").createImageData(width, height);
  return {
    gen: map.gen,
    slot,
    name,
    label,
    plan: response.plan,
    timeMs: response.time_ms,
    expanded: Int32Array.from(response.expanded),
    expandedTotal: response.expanded_total,
    // Cells generated and the number of expansions done when each was (planners that
    // record their steps: A*); empty for the others.
    generated: Int32Array.from(response.generated || []),
    generatedAt: Int32Array.from(response.generated_at || []),
    generatedShown: 0,
    shown: 0,
    search,
    searchData,
    dirty: false,
  };
}

// Shows the first `upto` expanded cells of `r`, and the cells their expansions generated
// (OPEN's frontier: a cell generated by the k-th expansion is coloured from then until its
// own expansion paints over it).
function showUpTo(r, upto) {
  upto = Math.min(upto, r.expanded.length);
  const d = r.searchData.data;
  const alpha = layout() === "overlay" && state.results.length > 1 ? 150 : 255;
  const paint = (cell, rgb) => {
    const i = 4 * cell;
    d[i] = rgb[0];
    d[i + 1] = rgb[1];
    d[i + 2] = rgb[2];
    d[i + 3] = alpha;
  };
  for (let k = r.shown; k < upto; k++) {
    paint(r.expanded[k], EXPANDED_COLORS[r.slot]);
    while (r.generatedShown < r.generated.length && r.generatedAt[r.generatedShown] <= k + 1) {
      paint(r.generated[r.generatedShown], FRONTIER_COLORS[r.slot]);
      r.generatedShown++;
    }
  }
  if (upto > r.shown) r.dirty = true;
  r.shown = upto;
}

function newRunId() {
  return `run-${Date.now()}-${Math.floor(Math.random() * 1e9)}`;
}

// Plans one planner for `run` on the map, start, goal and edits shown when it is called;
// null when the map changed before the answer came (the answer is dropped).
async function planOne(run, slot, name, set) {
  const map = state.map;
  if (run.gen !== state.loadGen || map.gen !== run.gen) return null;
  const edits = Array.from(state.edits, ([i, free]) => [i % map.width, Math.floor(i / map.width), free]);
  const max = maxExpansions();
  run.id = newRunId();
  const request = {
    map: map.path,
    edits,
    start: state.start,
    goal: state.goal,
    planner: name,
    set,
    run: run.id,
    costs: map.costs,
    ignore_costs: $("ignore-costs").checked,
    // The map as drawn: the server refuses the plan (409) if its file changed since.
    map_version: map.version,
  };
  if (max !== null) request.max_expansions = max;
  let response;
  try {
    response = await getJson("/api/plan", {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify(request),
    });
  } catch (error) {
    // The server says `--set KEY=VALUE: ...` as `plan --set` does; on the page the value
    // was typed in the planner's KEY field, so the message names that field.
    const m = /^--set ([^=:]+)(?:=([^:]*))?: (.*)$/s.exec(error.message);
    if (m) {
      const field = document.querySelector(`#planner-slots .slot[data-slot="${slot}"] .params [data-key="${CSS.escape(m[1])}"]`);
      if (field) field.setAttribute("aria-invalid", "true");
      const value = m[2] === undefined ? "" : ` = ${m[2]}`;
      error.message = `planner ${slot + 1} (${name}), field ${m[1]}${value}: ${m[3]}`;
    }
    throw error;
  }
  run.id = null;
  if (run.gen !== state.loadGen) return null;
  const label = set.length ? `${name}[${set.join(", ")}]` : name;
  return newResult(map, slot, name, label, response);
}

async function runAll(options) {
  if (!state.map || !state.start || !state.goal) {
    setStatus("load a map and set start and goal first", true);
    return;
  }
  const jobs = [];
  for (const slot of document.querySelectorAll("#planner-slots .slot")) {
    const name = slot.querySelector(".planner").value;
    if (name) jobs.push([Number(slot.dataset.slot), name, slotSettings(slot)]);
  }
  if (jobs.length === 0) {
    setStatus("choose a planner", true);
    return;
  }
  const maxField = $("max-expansions");
  maxField.removeAttribute("aria-invalid");
  for (const field of document.querySelectorAll("#planner-slots [aria-invalid]")) field.removeAttribute("aria-invalid");
  if (maxExpansions() === undefined) {
    maxField.setAttribute("aria-invalid", "true");
    maxField.focus();
    setStatus(`Max expansions: ${JSON.stringify(maxField.value)} is not a whole number from 1 to ${Number.MAX_SAFE_INTEGER} (empty: the server's default)`, true);
    return;
  }
  const queryGen = state.queryGen;
  // The run belongs to the map shown now: a "Load map" meanwhile cancels it, and every
  // answer for it after that is dropped.
  const run = { gen: state.loadGen, id: null, cancelled: false };
  const current = () => run.gen === state.loadGen;
  state.run = run;
  state.playing = false;
  $("cancel").disabled = false;
  $("run").disabled = true;
  const results = [];
  try {
    for (const [slot, name, set] of jobs) {
      if (run.cancelled || !current()) break;
      setStatus(`planning with ${name} ...`);
      const r = await planOne(run, slot, name, set);
      if (r === null || !current()) break;
      results.push(r);
    }
    if (current()) setStatus(results.map((r) => `${r.label}: ${r.plan.status}`).join("; "));
  } catch (error) {
    // 409 is a cancelled run ({"cancelled": true}), or a map changed on disk since it was
    // loaded (an error to show: the page draws the map as it was).
    const cancelled = error.status === 409 && !(error.body && error.body.error);
    if (current()) setStatus(cancelled ? "cancelled" : `error: ${error.message}`, !cancelled);
  } finally {
    if (state.run === run) {
      state.run = null;
      $("cancel").disabled = true;
      $("run").disabled = false;
    }
  }
  if (!current()) return;
  if (queryGen !== state.queryGen) {
    // Start, goal or walls changed while it ran: its answers are for the query before.
    if (results.length > 0) setStatus("start, goal or walls changed while planning; Plan again", true);
    return;
  }
  state.results = results;
  layoutViews();
  if (options && options.instant) {
    for (const r of results) showUpTo(r, r.expanded.length);
  } else {
    state.playing = true;
  }
  draw();
}

// The Max expansions field: null when empty (the server's default), the number when it
// is a whole number from 1 to 2^53 - 1, undefined otherwise (-5, 1.5, 0, 1e30, text).
function maxExpansions() {
  const field = $("max-expansions");
  const text = field.value.trim();
  if (text === "" && !field.validity.badInput) return null;
  if (!/^\d+$/.test(text)) return undefined;
  const n = Number(text);
  return n >= 1 && Number.isSafeInteger(n) ? n : undefined;
}

// Cancels the plan in progress: the planner running on the server stops, and the
// planners not yet sent are never sent.
async function cancelRun() {
  const run = state.run;
  if (!run) return;
  run.cancelled = true;
  if (run.id) {
    try {
      await getJson(`/api/cancel?run=${encodeURIComponent(run.id)}`, { method: "POST" });
    } catch (_) {
      // The run may have finished meanwhile.
    }
  }
}

// ---- playback ----------------------------------------------------------------------

function perFrame() {
  const speed = Number($("speed").value);
  return Math.max(1, Math.round(Math.pow(10, speed / 25)));
}

function tick() {
  if (state.playing) {
    let busy = false;
    for (const r of state.results) {
      showUpTo(r, r.shown + perFrame());
      if (r.shown < r.expanded.length) busy = true;
    }
    draw();
    if (!busy) state.playing = false;
  }
  requestAnimationFrame(tick);
}

// ---- results directories -----------------------------------------------------------

const FILTERS = ["planner", "map", "status", "bucket"];
const SHOWN_COLUMNS = ["map", "problem", "planner", "repeat", "status", "steps", "turns", "length", "bucket", "n_expanded", "time_ms"];

async function openResults(path) {
  setStatus(`opening ${path} ...`);
  const results = await getJson(`/api/results?path=${encodeURIComponent(path)}`);
  state.runs = results;
  const columns = results.runs.columns;
  const col = (name) => columns.indexOf(name);
  const filters = $("filters");
  filters.replaceChildren();
  for (const name of FILTERS) {
    const c = col(name);
    if (c < 0) continue;
    const values = Array.from(new Set(results.runs.data.map((row) => row[c]))).sort();
    const label = document.createElement("label");
    label.append(document.createTextNode(`${name} `));
    const select = document.createElement("select");
    select.dataset.filter = name;
    option(select, "", "(all)");
    for (const v of values) option(select, JSON.stringify(v), v === null ? "(none)" : String(v));
    select.addEventListener("change", renderRuns);
    label.appendChild(select);
    filters.appendChild(label);
  }
  const head = $("runs-table").querySelector("thead");
  head.replaceChildren();
  const tr = document.createElement("tr");
  for (const name of SHOWN_COLUMNS) {
    if (col(name) < 0) continue;
    const th = document.createElement("th");
    th.textContent = name;
    tr.appendChild(th);
  }
  head.appendChild(tr);
  $("results").hidden = false;
  renderRuns();
  setStatus(`${path}: ${results.runs.data.length} runs`);
}

function renderRuns() {
  const results = state.runs;
  const columns = results.runs.columns;
  const col = (name) => columns.indexOf(name);
  const active = Array.from(document.querySelectorAll("#filters select"))
    .filter((s) => s.value !== "")
    .map((s) => [col(s.dataset.filter), s.value]);
  const body = $("runs-table").querySelector("tbody");
  body.replaceChildren();
  let n = 0;
  for (const row of results.runs.data) {
    if (!active.every(([c, v]) => JSON.stringify(row[c]) === v)) continue;
    n++;
    if (n > 2000) continue;
    const tr = document.createElement("tr");
    for (const name of SHOWN_COLUMNS) {
      const c = col(name);
      if (c < 0) continue;
      const td = document.createElement("td");
      td.textContent = row[c] === null ? "" : String(row[c]);
      tr.appendChild(td);
    }
    tr.addEventListener("click", () => showRun(row, tr));
    // Reached with Tab, opened with Enter or Space, as a button is.
    tr.tabIndex = 0;
    tr.addEventListener("keydown", (e) => {
      if (e.key === "Enter" || e.key === " ") {
        e.preventDefault();
        showRun(row, tr);
      }
    });
    body.appendChild(tr);
  }
  $("results-count").textContent = n > 2000 ? `${n} runs (the first 2000 shown)` : `${n} runs`;
}

async function showRun(row, tr) {
  for (const other of document.querySelectorAll("#runs-table tr.selected")) other.classList.remove("selected");
  tr.classList.add("selected");
  const results = state.runs;
  const columns = results.runs.columns;
  const get = (name) => row[columns.indexOf(name)];
  const mapPath = results.maps[get("map")];
  // How the server located the map, or why it did not (the run is then not drawn: on
  // another map of the same name it would be wrong).
  const note = (results.map_notes || {})[get("map")];
  if (!mapPath) {
    setStatus(note || `map ${get("map")} is not under the served directory`, true);
    return;
  }
  if (!state.map || state.map.path !== mapPath) {
    if (!(await loadMap(mapPath))) return;
  }
  if (state.map.path !== mapPath) return;
  state.start = [get("start_x"), get("start_y")];
  state.goal = [get("goal_x"), get("goal_y")];
  updateEnds();
  const kept = results.paths.find(
    (p) => p.map === get("map") && p.problem === get("problem") && p.planner === get("planner") && p.repeat === get("repeat"),
  );
  const path = kept ? kept.path : [];
  const counters = {};
  // Only the counters this run's planner has: a results directory's table has a column
  // for every planner's counters, null where a planner has none (plan --json leaves them
  // out).
  for (const name of columns) if (name.startsWith("n_") && get(name) !== null) counters[name] = get(name);
  const plan = {
    status: get("status"),
    path,
    metrics: get("steps") === null ? null : { steps: get("steps"), turns: get("turns"), score: get("score"), length: get("length") },
    counters,
  };
  const r = newResult(state.map, 0, get("algorithm"), `${get("planner")} (recorded run)`, {
    plan,
    time_ms: Number(get("time_ms")) || 0,
    expanded: [],
    expanded_total: 0,
  });
  if (r === null) return;
  state.results = [r];
  layoutViews();
  draw();
  const shown = kept ? `${get("planner")} on ${get("map")} problem ${get("problem")}` : "this run's path was not kept (paths.jsonl)";
  setStatus(note ? `${shown}; ${note}` : shown);
}

// ---- wiring ------------------------------------------------------------------------

async function init() {
  try {
    state.planners = await getJson("/api/planners");
    buildSlots();
    await loadLists();
    layoutViews();
  } catch (error) {
    setStatus(`error: ${error.message}`, true);
  }
  $("load-map").addEventListener("click", () => {
    const path = $("map-select").value;
    if (path) loadMap(path).catch((e) => setStatus(`error: ${e.message}`, true));
  });
  $("load-results").addEventListener("click", () => {
    const path = $("results-select").value;
    if (path) openResults(path).catch((e) => setStatus(`error: ${e.message}`, true));
  });
  $("problem-select").addEventListener("change", () => {
    const i = $("problem-select").value;
    if (i === "" || !state.map) return;
    const p = state.map.problems[Number(i)];
    state.start = [p[0], p[1]];
    state.goal = [p[2], p[3]];
    queryChanged("The scenario problem");
    updateEnds();
    draw();
  });
  for (const end of ["start", "goal"]) {
    for (const axis of ["x", "y"]) $(`${end}-${axis}`).addEventListener("change", () => endFromFields(end));
  }
  // The canvases follow the window's width.
  let resizing = null;
  window.addEventListener("resize", () => {
    clearTimeout(resizing);
    resizing = setTimeout(() => {
      layoutViews();
      draw();
    }, 100);
  });
  $("run").addEventListener("click", () => runAll());
  $("cancel").addEventListener("click", () => cancelRun());
  $("play").addEventListener("click", () => {
    state.playing = true;
  });
  $("pause").addEventListener("click", () => {
    state.playing = false;
  });
  $("step").addEventListener("click", () => {
    state.playing = false;
    for (const r of state.results) showUpTo(r, r.shown + 1);
    draw();
  });
  $("to-end").addEventListener("click", () => {
    state.playing = false;
    for (const r of state.results) showUpTo(r, r.expanded.length);
    draw();
  });
  for (const radio of document.querySelectorAll('input[name="layout"]')) {
    radio.addEventListener("change", () => {
      layoutViews();
      for (const r of state.results) {
        const upto = r.shown;
        r.shown = 0;
        r.generatedShown = 0;
        showUpTo(r, upto);
      }
      draw();
    });
  }
  requestAnimationFrame(tick);
}

// What the browser test and a curious user can call from the console.
window.gridplan = {
  state,
  loadMap,
  runAll,
  UNKNOWN_RGB,
  BLOCKED_RGB,
  PATH_COLORS,
  FRONTIER_COLORS,
  START_COLOR,
  GOAL_COLOR,
  // The client coordinates of a cell's centre in the first view's canvas.
  cellToClient(x, y) {
    const canvas = canvases()[0];
    const rect = canvas.getBoundingClientRect();
    const v = state.view;
    return [rect.left + v.x + (x + 0.5) * v.cell, rect.top + v.y + (y + 0.5) * v.cell];
  },
  // Plans start -> goal with one planner and draws the whole search and path at once;
  // the milliseconds from the request to the frame that shows it.
  async timeQuery(name, start, goal) {
    const t0 = performance.now();
    state.start = start;
    state.goal = goal;
    const r = await planOne({ gen: state.loadGen, id: null, cancelled: false }, 0, name, []);
    if (r === null) return null;
    state.results = [r];
    layoutViews();
    showUpTo(r, r.expanded.length);
    draw();
    await new Promise((resolve) => requestAnimationFrame(() => resolve()));
    return { ms: performance.now() - t0, counters: r.plan.counters, status: r.plan.status };
  },
};

init();
