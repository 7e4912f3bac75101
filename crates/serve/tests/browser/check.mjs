// The browser test of `gridplan serve` (run by .ci/run): Debian's Chromium driven by
// Playwright (playwright-core, never downloading a browser).
//
//   node check.mjs GRIDPLAN_BINARY SERVED_DIR
//
// SERVED_DIR holds a copy of the repository's maps/ as maps/ and a link `escape.map` to
// /etc/passwd. The test starts `gridplan serve SERVED_DIR --port 0`, then: loads
// maps/paper/map10.map, clicks start and goal, runs A* and BFS, checks that the counters
// shown equal `gridplan plan --json`'s, that both animations reach the goal, and that a
// screenshot's path-coloured pixels lie on the path's cells; checks that a ROS map's
// unknown cells are drawn grey, apart from its walls; that loading another map while
// planners run on a 1024 x 1024 map cancels them and draws none of their results; that a
// results directory's run is drawn on the map its config read, not on another of the same
// file name (and says why when the map is ambiguous); checks the path-traversal and
// body-size refusals; and measures in the page the den520d A* scenario queries planned
// and drawn (performance.now()), printing the median. Also: the map key and the page's
// icon; that a new start clears the plan drawn; that bad Max expansions and planner field
// values are refused naming the field; start and goal typed in their cell fields; that a
// map changed on disk since it was loaded is refused, not planned; a recorded run opened
// from the keyboard shows only its own counters; the canvas in a 700-pixel window, a
// weighted map's key, weight files not listed; den520d's start and goal markers' size.
// The files it adds to SERVED_DIR (under check-tmp/) are removed at the end.
import { spawn, spawnSync } from "node:child_process";
import { createRequire } from "node:module";
import { inflateSync } from "node:zlib";
import net from "node:net";
import fs from "node:fs";
import path from "node:path";

const require = createRequire(path.join(process.env.PLAYWRIGHT_DIR || process.cwd(), "noop.js"));
const { chromium } = require("playwright-core");

const [binary, served] = process.argv.slice(2);
if (!binary || !served) {
  console.error("usage: node check.mjs GRIDPLAN_BINARY SERVED_DIR");
  process.exit(2);
}

let passed = 0;
let failed = 0;
function check(condition, what) {
  if (condition) {
    passed++;
    console.log(`ok: ${what}`);
  } else {
    failed++;
    console.log(`FAILED: ${what}`);
  }
}

// ---- files of the checks: a 1024 x 1024 random map, and a results directory whose map
// has a namesake of another size ----
const scratch = path.join(served, "check-tmp");
fs.rmSync(scratch, { recursive: true, force: true });
fs.mkdirSync(path.join(scratch, "rp", "aa"), { recursive: true });
{
  // mulberry32: the same map on every run.
  let seed = 1;
  const random = () => {
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
  const W = 1024;
  const rows = [];
  for (let y = 0; y < W; y++) {
    let row = "";
    for (let x = 0; x < W; x++) row += y === 0 || y === W - 1 || random() >= 0.2 ? "." : "@";
    rows.push(row);
  }
  fs.writeFileSync(path.join(scratch, "big1024.map"), `type octile\nheight ${W}\nwidth ${W}\nmap\n${rows.join("\n")}\n`);
}
fs.copyFileSync(path.join(served, "maps/movingai/arena.map"), path.join(scratch, "rp/arena.map"));
fs.copyFileSync(path.join(served, "maps/paper/map10.map"), path.join(scratch, "rp/aa/arena.map"));
const probeConfig = 'name = "r"\n[[maps]]\nfiles = ["arena.map"]\npairs = [{ start = [3, 1], goal = [46, 47] }]\n[planners.a]\nplanner = "astar"\n[planners.b]\nplanner = "bfs"\n';
fs.writeFileSync(path.join(scratch, "rp/c.toml"), probeConfig);
{
  // Run from the served directory's parent, as a user runs `experiment` from elsewhere:
  // the results record the config's path as given.
  const from = path.dirname(served);
  const rel = path.relative(from, path.join(scratch, "rp"));
  const run = spawnSync(binary, ["experiment", path.join(rel, "c.toml"), "--output", path.join(rel, "res"), "--quiet"], { cwd: from, encoding: "utf8" });
  if (run.status !== 0) throw new Error(`gridplan experiment: ${run.stderr}`);
}

// ---- the server ----
const server = spawn(binary, ["serve", served, "--port", "0"], { stdio: ["ignore", "pipe", "inherit"] });
const base = await new Promise((resolve, reject) => {
  let out = "";
  const timer = setTimeout(() => reject(new Error(`no address printed: ${out}`)), 20000);
  server.stdout.on("data", (chunk) => {
    out += chunk;
    const m = out.match(/at (http:\/\/127\.0\.0\.1:\d+\/)/);
    if (m) {
      clearTimeout(timer);
      resolve(m[1]);
    }
  });
  server.on("exit", (code) => reject(new Error(`gridplan serve exited with ${code}`)));
});
console.log(`server: ${base}`);

function planJson(args) {
  const run = spawnSync(binary, ["plan", ...args, "--json"], { cwd: served, encoding: "utf8" });
  if (run.status !== 0) throw new Error(`gridplan plan ${args.join(" ")}: ${run.stderr}`);
  return JSON.parse(run.stdout);
}

// A PNG (8-bit RGB or RGBA, not interlaced, as Chromium writes them) as RGBA pixels.
function decodePng(buffer) {
  let offset = 8;
  let width = 0, height = 0, channels = 0;
  const idat = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString("ascii", offset + 4, offset + 8);
    const data = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === "IHDR") {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      const depth = data[8], color = data[9], interlace = data[12];
      if (depth !== 8 || interlace !== 0 || (color !== 2 && color !== 6)) throw new Error(`unsupported PNG ${depth}/${color}/${interlace}`);
      channels = color === 6 ? 4 : 3;
    } else if (type === "IDAT") {
      idat.push(data);
    }
    offset += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const out = Buffer.alloc(width * height * 4);
  let prev = Buffer.alloc(stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = Buffer.from(raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1)));
    for (let i = 0; i < stride; i++) {
      const a = i >= channels ? line[i - channels] : 0;
      const b = prev[i];
      const c = i >= channels ? prev[i - channels] : 0;
      let add = 0;
      if (filter === 1) add = a;
      else if (filter === 2) add = b;
      else if (filter === 3) add = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        add = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      line[i] = (line[i] + add) & 255;
    }
    for (let x = 0; x < width; x++) {
      for (let k = 0; k < 4; k++) out[(y * width + x) * 4 + k] = k < channels ? line[x * channels + k] : 255;
    }
    prev = line;
  }
  return { width, height, pixels: out };
}

function hexRgb(hex) {
  return [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
}

const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1600, height: 1200 }, deviceScaleFactor: 1 });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  // Every answer of 400 or more to a request the page made by itself (the favicon's 404
  // showed as a console error on every load).
  const failedLoads = [];
  page.on("response", (response) => {
    if (response.status() >= 400 && !response.url().includes("/api/")) failedLoads.push(`${response.status()} ${response.url()}`);
  });
  await page.goto(base);
  await page.waitForSelector('#map-select option[value="maps/paper/map10.map"]', { state: "attached" });
  await page.selectOption("#map-select", "maps/paper/map10.map");
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.name === "map10.map");

  // Start and goal by clicking their cells.
  const [start, goal] = [[0, 0], [11, 11]];
  await page.check('input[name="tool"][value="start"]');
  let [cx, cy] = await page.evaluate(([x, y]) => window.gridplan.cellToClient(x, y), start);
  await page.mouse.click(cx, cy);
  await page.check('input[name="tool"][value="goal"]');
  [cx, cy] = await page.evaluate(([x, y]) => window.gridplan.cellToClient(x, y), goal);
  await page.mouse.click(cx, cy);
  check((await page.textContent("#start-out")) === "(0, 0)" && (await page.textContent("#goal-out")) === "(11, 11)", "start and goal set by clicks");

  // A* in slot 1, BFS in slot 2, side by side; play at full speed.
  await page.selectOption('.slot[data-slot="0"] select.planner', "astar");
  await page.selectOption('.slot[data-slot="1"] select.planner', "bfs");
  await page.$eval("#speed", (e) => { e.value = "0"; });
  await page.click("#run");
  await page.waitForFunction(() => window.gridplan.state.results.length === 2, null, { timeout: 30000 });
  // At the slowest speed the playback is still under way a moment later.
  const early = await page.evaluate(() => window.gridplan.state.results.map((r) => [r.shown, r.expanded.length]));
  await page.$eval("#speed", (e) => { e.value = "100"; });
  await page.waitForFunction(() => window.gridplan.state.results.every((r) => r.shown >= r.expanded.length), null, { timeout: 30000 });
  check(early.every(([shown, total]) => shown < total), `the playback is under way at the slowest speed (${JSON.stringify(early)} shown of expanded)`);

  for (const [slot, name] of [[0, "astar"], [1, "bfs"]]) {
    const cli = planJson(["maps/paper/map10.map", "--planner", name, "--start", start.join(","), "--goal", goal.join(",")]);
    const shown = await page.$$eval(`table.counters[data-slot="${slot}"] td[data-key]`, (tds) => Object.fromEntries(tds.map((td) => [td.dataset.key, td.textContent])));
    const want = { status: cli.status };
    for (const key of ["steps", "turns", "score", "length"]) want[key] = String(cli.metrics[key]);
    for (const [key, value] of Object.entries(cli.counters)) want[key] = String(value);
    const mismatched = Object.entries(want).filter(([k, v]) => shown[k] !== v);
    check(mismatched.length === 0, `${name}: the counters shown equal plan --json's (${Object.keys(want).length} values${mismatched.length ? `; differ: ${JSON.stringify(mismatched)} vs ${JSON.stringify(shown)}` : ""})`);
    const result = await page.evaluate((s) => {
      const r = window.gridplan.state.results.find((q) => q.slot === s);
      return { shown: r.shown, total: r.expandedTotal, path: r.plan.path, done: r.viewEl.dataset[`done${s}`] };
    }, slot);
    const last = result.path[result.path.length - 1];
    check(result.done === "1" && result.shown === cli.counters.n_expanded && last[0] === goal[0] && last[1] === goal[1],
      `${name}: the animation plays all ${result.shown} expansions and its path reaches the goal`);

    // The screenshot: path-coloured pixels lie on the path's cells, and every path cell
    // between start and goal shows them.
    const canvas = page.locator(`#views .view:nth-child(${slot + 1}) canvas`);
    const shot = await canvas.screenshot();
    if (process.env.SCREENSHOT_DIR) fs.writeFileSync(path.join(process.env.SCREENSHOT_DIR, `${name}.png`), shot);
    const png = decodePng(shot);
    const view = await page.evaluate(() => window.gridplan.state.view);
    const color = hexRgb(await page.evaluate((s) => window.gridplan.PATH_COLORS[s], slot));
    const cells = new Set(result.path.map(([x, y]) => `${x},${y}`));
    const seen = new Set();
    // Pixels within a pixel of a cell's edge are not classified: the element's screenshot
    // may sit a fraction of a pixel off the canvas grid.
    let off = 0, on = 0;
    for (let py = 0; py < png.height; py++) {
      for (let px = 0; px < png.width; px++) {
        const i = 4 * (py * png.width + px);
        if (png.pixels[i] !== color[0] || png.pixels[i + 1] !== color[1] || png.pixels[i + 2] !== color[2]) continue;
        const fx = (px + 0.5 - view.x) / view.cell, fy = (py + 0.5 - view.y) / view.cell;
        const margin = 1.5 / view.cell;
        if (fx - Math.floor(fx) < margin || Math.ceil(fx) - fx < margin || fy - Math.floor(fy) < margin || Math.ceil(fy) - fy < margin) continue;
        const x = Math.floor(fx), y = Math.floor(fy);
        if (cells.has(`${x},${y}`)) {
          on++;
          seen.add(`${x},${y}`);
        } else off++;
      }
    }
    check(on > 0 && off === 0 && seen.size === cells.size - 2,
      `${name}: screenshot path pixels on path cells (${on} on, ${off} off; ${seen.size} of ${cells.size - 2} cells between start and goal)`);
  }
  if (process.env.SCREENSHOT_DIR) await page.screenshot({ path: path.join(process.env.SCREENSHOT_DIR, "page.png") });
  // The key of the search view's tones: A* records its frontier, BFS does not.
  const tones = await page.$$eval('td[data-key="shading"]', (tds) => tds.map((td) => td.querySelectorAll(".swatch").length));
  check(JSON.stringify(tones) === "[2,1]", `the shading key shows the frontier's tone for A* only (${JSON.stringify(tones)} swatches)`);
  const mapKeyTones = await page.$$eval("#views .view:first-child .map-key .swatch", (s) => s.map((e) => e.dataset.tone));
  check(["free", "wall", "start", "goal"].every((t) => mapKeyTones.includes(t)) && mapKeyTones.some((t) => t.startsWith("path")),
    `the map key names the start, goal and path colours (${JSON.stringify(mapKeyTones)})`);
  // The page names its icon, and it is served (headless Chromium asks for none; a browser
  // asked for /favicon.ico on every load, a 404 in its console).
  const icon = await page.evaluate(async () => {
    const link = document.querySelector('link[rel="icon"]');
    return link ? (await fetch(link.href)).status : "no icon link";
  });
  check(icon === 200 && failedLoads.length === 0, `the page's icon is served (${icon}; failed loads: ${failedLoads.join(", ")})`);

  // ---- a new start (or goal, or wall) clears the plan drawn for the query before ----
  await page.check('input[name="tool"][value="start"]');
  // The first free cell after the start (0, 0) in row-major order.
  const newStart = await page.evaluate(() => {
    const { map } = window.gridplan.state;
    const i = map.blocked.findIndex((b, k) => k > 0 && b === 0);
    return [i % map.width, Math.floor(i / map.width)];
  });
  [cx, cy] = await page.evaluate(([x, y]) => window.gridplan.cellToClient(x, y), newStart);
  await page.mouse.click(cx, cy);
  const cleared = await page.evaluate(() => {
    const { state, PATH_COLORS } = window.gridplan;
    let pathPixels = 0;
    for (const canvas of document.querySelectorAll("#views canvas")) {
      const d = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
      const colours = PATH_COLORS.map((hex) => [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16)));
      for (let i = 0; i < d.length; i += 4) if (colours.some((c) => d[i] === c[0] && d[i + 1] === c[1] && d[i + 2] === c[2])) pathPixels++;
    }
    return { results: state.results.length, tables: document.querySelectorAll("table.counters").length, pathPixels, start: state.start, status: document.querySelector("#status").textContent };
  });
  check(cleared.results === 0 && cleared.tables === 0 && cleared.pathPixels === 0 && String(cleared.start) === String(newStart),
    `a new start clears the path and counters of the plan before (${JSON.stringify(cleared)})`);

  // ---- the page's number fields are checked, and the field at fault named ----
  let sent = 0;
  const countPlans = (request) => { if (request.url().endsWith("/api/plan")) sent++; };
  page.on("request", countPlans);
  for (const bad of ["-5", "1.5", "1e30", "0", "99999999999999999999"]) {
    await page.fill("#max-expansions", bad);
    await page.click("#run");
    const said = await page.evaluate(() => ({ status: document.querySelector("#status").textContent, invalid: document.querySelector("#max-expansions").getAttribute("aria-invalid") }));
    check(said.status.startsWith("Max expansions:") && said.status.includes("whole number") && said.invalid === "true",
      `Max expansions ${bad} is refused naming the field (${said.status})`);
  }
  check(sent === 0, `no plan is sent with a bad Max expansions (${sent} sent)`);
  page.off("request", countPlans);
  await page.fill("#max-expansions", "");
  await page.fill('.slot[data-slot="0"] .params [data-key="weight"]', "1e400");
  await page.click("#run");
  await page.waitForFunction(() => window.gridplan.state.run === null && document.querySelector("#status").className === "error", null, { timeout: 30000 });
  const fieldError = await page.textContent("#status");
  check(fieldError.includes("planner 1 (astar), field weight = 1e400: not a number") && !fieldError.includes("--set"),
    `a planner field's bad number names the field, not --set (${fieldError})`);
  await page.fill('.slot[data-slot="0"] .params [data-key="weight"]', "");

  // ---- a map changed on disk after it was loaded: the plan is refused, not drawn ----
  const smallMap = (width, height, walls) => {
    const rows = [];
    for (let y = 0; y < height; y++) {
      let row = "";
      for (let x = 0; x < width; x++) row += walls.some(([wx, wy]) => wx === x && wy === y) ? "@" : ".";
      rows.push(row);
    }
    fs.writeFileSync(path.join(scratch, "e.map"), `type octile\nheight ${height}\nwidth ${width}\nmap\n${rows.join("\n")}\n`);
  };
  smallMap(8, 5, []);
  await page.reload();
  await page.waitForSelector('#map-select option[value="check-tmp/e.map"]', { state: "attached" });
  await page.selectOption("#map-select", "check-tmp/e.map");
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.name === "e.map");
  // Start and goal from the keyboard alone (the map has no .scen): the cell fields.
  const cellFields = (await page.$("#start-x")) !== null;
  if (!cellFields) {
    await page.evaluate(() => { window.gridplan.state.start = [0, 0]; window.gridplan.state.goal = [7, 4]; });
  }
  check(cellFields, "the page has start and goal cell fields");
  if (cellFields) {
  await page.focus("#start-x");
  await page.keyboard.type("0");
  await page.keyboard.press("Tab");
  await page.keyboard.type("0");
  await page.keyboard.press("Tab");
  await page.keyboard.type("7");
  await page.keyboard.press("Tab");
  await page.keyboard.type("9");
  await page.keyboard.press("Tab");
  const badGoal = await page.evaluate(() => ({ goal: window.gridplan.state.goal, status: document.querySelector("#status").textContent }));
  await page.fill("#goal-y", "4");
  await page.focus("#goal-y");
  await page.keyboard.press("Tab");
  const typed = await page.evaluate(() => [window.gridplan.state.start, window.gridplan.state.goal]);
  check(JSON.stringify(typed) === "[[0,0],[7,4]]" && badGoal.goal === null && badGoal.status.startsWith("Goal y:"),
    `start and goal are set from the keyboard, a cell off the map refused naming the field (${JSON.stringify(typed)}; ${badGoal.status})`);
  }
  for (const [width, height, walls] of [[12, 6, [[3, 3], [4, 3]]], [8, 5, [[3, 0], [3, 1], [3, 2], [3, 3]]]]) {
    smallMap(width, height, walls);
    await page.click("#run");
    await page.waitForFunction(() => window.gridplan.state.run === null, null, { timeout: 30000 });
    const stale = await page.evaluate(() => ({
      status: document.querySelector("#status").textContent,
      error: document.querySelector("#status").className,
      results: window.gridplan.state.results.length,
      size: [window.gridplan.state.map.width, window.gridplan.state.map.height],
    }));
    check(stale.status.includes("the map file changed on disk since it was loaded; load it again") && stale.error === "error" && stale.results === 0 && stale.size.join("x") === "8x5",
      `a plan on a map changed on disk since it was loaded (now ${width} x ${height}) is refused and nothing drawn (${JSON.stringify(stale)})`);
  }
  // Loaded again, it plans on the new walls.
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.blocked[3] === 1);
  await page.evaluate(() => { window.gridplan.state.start = [0, 0]; window.gridplan.state.goal = [7, 4]; });
  await page.click("#run");
  await page.waitForFunction(() => window.gridplan.state.run === null && window.gridplan.state.results.length > 0, null, { timeout: 30000 });
  const replanned = await page.evaluate(() => window.gridplan.state.results[0].plan.path);
  check(replanned.length > 0 && !replanned.some(([x, y]) => x === 3 && y < 4), `the map loaded again plans around its new walls (${JSON.stringify(replanned)})`);

  // ---- a ROS map: cells shown with their map-frame position, as `plan` prints it ----
  await page.selectOption("#map-select", "maps/ros-nav2/tb3_sandbox.yaml");
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.name === "tb3_sandbox.yaml");
  const rosStart = [170, 193], rosGoal = [230, 173];
  const ros = planJson(["maps/ros-nav2/tb3_sandbox.yaml", "--planner", "astar", "--start", rosStart.join(","), "--goal", rosGoal.join(",")]);
  await page.check('input[name="tool"][value="start"]');
  [cx, cy] = await page.evaluate(([x, y]) => window.gridplan.cellToClient(x, y), rosStart);
  await page.mouse.click(cx, cy);
  [cx, cy] = await page.evaluate(([x, y]) => window.gridplan.cellToClient(x, y), rosGoal);
  await page.mouse.move(cx, cy);
  const startText = await page.textContent("#start-out");
  const cursorText = await page.textContent("#cursor-out");
  // plan --json's cell centres (-1.4749999999999996, ...) at six decimals: what both print.
  const shown = ([x, y]) => `(${+x.toFixed(6)}, ${+y.toFixed(6)}) m`;
  check(startText === `(170, 193) = ${shown(ros.map_frame.start)}` && startText === "(170, 193) = (-1.475, -0.475) m",
    `a ROS map's start shows its map-frame position (${startText})`);
  check(cursorText === `(230, 173) = ${shown(ros.map_frame.goal)}` && cursorText === "(230, 173) = (1.525, 0.525) m",
    `the cell under the pointer shows its map-frame position (${cursorText})`);
  // Unknown cells (map_server's -1) are grey, walls dark, in the drawn view and its key;
  // both stay blocked (a start there is refused).
  const rosCells = await page.evaluate(async () => (await (await fetch("/api/map?path=maps%2Fros-nav2%2Ftb3_sandbox.yaml")).json()).cells);
  const rosTones = await page.evaluate((cells) => {
    // (A page without the unknown tone matches none: the check fails rather than throws.)
    const { state, UNKNOWN_RGB = [-1, -1, -1], BLOCKED_RGB = [45, 45, 45] } = window.gridplan;
    const canvas = document.querySelector("#views canvas");
    const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
    const v = state.view;
    const count = { unknown: 0, wall: 0, wrong: 0 };
    const same = (i, rgb) => pixels[i] === rgb[0] && pixels[i + 1] === rgb[1] && pixels[i + 2] === rgb[2];
    for (let y = 0; y < state.map.height; y++) {
      for (let x = 0; x < state.map.width; x++) {
        const c = cells[y * state.map.width + x];
        if (c === "0") continue;
        const px = Math.floor(v.x + (x + 0.5) * v.cell), py = Math.floor(v.y + (y + 0.5) * v.cell);
        if (px < 0 || py < 0 || px >= canvas.width || py >= canvas.height) continue;
        // The start's marker covers its cell and, on cells this small, a ring around it.
        if (state.start && Math.hypot(px - (v.x + (state.start[0] + 0.5) * v.cell), py - (v.y + (state.start[1] + 0.5) * v.cell)) <= 11) continue;
        if (state.start && x === state.start[0] && y === state.start[1]) continue;
        const i = 4 * (py * canvas.width + px);
        if (c === "2" && same(i, UNKNOWN_RGB)) count.unknown++;
        else if (c === "1" && same(i, BLOCKED_RGB)) count.wall++;
        else count.wrong++;
      }
    }
    const key = Array.from(document.querySelectorAll("#views .map-key .swatch")).map((s) => s.dataset.tone);
    return { count, key, blockedUnknown: cells.split("").every((c, i) => c !== "2" || state.map.blocked[i] === 1) };
  }, rosCells);
  check(rosTones.count.unknown > 1000 && rosTones.count.wall > 100 && rosTones.count.wrong === 0 && rosTones.blockedUnknown,
    `a ROS map's unknown cells are drawn grey and its walls dark (${JSON.stringify(rosTones.count)})`);
  check(rosTones.key.includes("unknown (blocked)") && rosTones.key.includes("wall"), `the map key names the unknown cells' grey (${JSON.stringify(rosTones.key)})`);
  const unknownCell = rosCells.indexOf("2");
  [cx, cy] = await page.evaluate((i) => {
    const width = window.gridplan.state.map.width;
    return window.gridplan.cellToClient(i % width, Math.floor(i / width));
  }, unknownCell);
  await page.mouse.click(cx, cy);
  const refusedStart = await page.textContent("#status");
  check(refusedStart.endsWith("is unknown (blocked)") && (await page.textContent("#start-out")).startsWith("(170, 193)"),
    `an unknown cell is refused as a start (${refusedStart})`);
  check(errors.length === 0, `no page errors ${errors.join("; ")}`);

  // ---- another map while planners run: their runs are cancelled, their results dropped ----
  let pending = 0;
  page.on("request", (request) => { if (request.url().endsWith("/api/plan")) pending++; });
  page.on("requestfinished", (request) => { if (request.url().endsWith("/api/plan")) pending--; });
  page.on("requestfailed", (request) => { if (request.url().endsWith("/api/plan")) pending--; });
  await page.selectOption("#map-select", "check-tmp/big1024.map");
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.name === "big1024.map");
  const bigGen = await page.evaluate(() => {
    window.gridplan.state.start = [0, 0];
    window.gridplan.state.goal = [1023, 1023];
    // Each plan request as the page sends it, with the map load generation then.
    window.sentPlans = [];
    const send = window.fetch;
    window.fetch = (url, options) => {
      if (String(url).endsWith("/api/plan")) window.sentPlans.push({ gen: window.gridplan.state.loadGen, map: JSON.parse(options.body).map });
      return send(url, options);
    };
    return window.gridplan.state.loadGen;
  });
  await page.selectOption('.slot[data-slot="0"] select.planner', "bfs");
  await page.selectOption('.slot[data-slot="1"] select.planner', "astar");
  await page.selectOption('.slot[data-slot="2"] select.planner', "lexastar");
  const firstPlan = page.waitForRequest((r) => r.url().endsWith("/api/plan"));
  await page.click("#run");
  await firstPlan;
  await page.waitForTimeout(100);
  const pendingAtLoad = pending;
  await page.selectOption("#map-select", "maps/movingai/arena.map");
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.name === "arena.map");
  // Every plan request answered (or failed), and a moment for the page to act on the last.
  const settled = Date.now() + 60000;
  while (pending > 0 && Date.now() < settled) await page.waitForTimeout(50);
  await page.waitForTimeout(300);
  const after = await page.evaluate(() => {
    const { state, PATH_COLORS } = window.gridplan;
    const canvas = document.querySelector("#views canvas");
    const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
    // Only the map's own tones (and the backdrop) may be drawn: no search or path colour.
    const allowed = new Set(["255,255,255", "45,45,45", "216,216,216"]);
    let foreign = 0;
    for (let i = 0; i < pixels.length; i += 4) if (!allowed.has(`${pixels[i]},${pixels[i + 1]},${pixels[i + 2]}`)) foreign++;
    return {
      results: state.results.length,
      size: [state.map.width, state.map.height],
      running: state.run !== null,
      runEnabled: !document.querySelector("#run").disabled,
      status: document.querySelector("#status").textContent,
      foreign,
      colours: PATH_COLORS.length,
    };
  });
  check(pendingAtLoad > 0, `a plan on the 1024 x 1024 map was running when another map was loaded (${pendingAtLoad} request(s) open)`);
  const plans = await page.evaluate(() => window.sentPlans);
  const lateOld = plans.filter((p) => p.gen !== bigGen && p.map === "check-tmp/big1024.map");
  const onArena = plans.filter((p) => p.map === "maps/movingai/arena.map");
  check(lateOld.length === 0 && onArena.length === 0,
    `no planner is sent after the map changed (${lateOld.length} for the old map, ${onArena.length} on the new one with the old start and goal)`);
  check(after.results === 0 && after.foreign === 0 && after.size.join("x") === "49x49",
    `no result of the old map is drawn on the new one (${after.results} results, ${after.foreign} search or path pixels on the ${after.size.join(" x ")} map)`);
  check(!after.running && after.runEnabled && after.status.startsWith("arena.map: 49 x 49"),
    `the page is ready to plan on the new map (${JSON.stringify(after.status)})`);
  // It plans there as usual.
  await page.selectOption('.slot[data-slot="1"] select.planner', "");
  await page.selectOption('.slot[data-slot="2"] select.planner', "");
  await page.evaluate(() => {
    window.gridplan.state.start = [3, 1];
    window.gridplan.state.goal = [46, 47];
  });
  await page.click("#run");
  const planned = await page
    .waitForFunction(() => window.gridplan.state.results.length === 1 && window.gridplan.state.run === null, null, { timeout: 30000 })
    .then(() => true, () => false);
  const arenaRun = !planned ? { planned } : await page.evaluate(() => {
    const r = window.gridplan.state.results[0];
    return { status: r.plan.status, last: r.plan.path[r.plan.path.length - 1], width: r.search.width };
  });
  check(arenaRun.status === "found" && String(arenaRun.last) === "46,47" && arenaRun.width === 49,
    `a plan on the new map afterwards is drawn on it (${JSON.stringify(arenaRun)})`);
  await page.selectOption('.slot[data-slot="0"] select.planner', "astar");

  // ---- a results directory: the run is drawn on the map its config read ----
  await page.reload();
  await page.waitForSelector('#results-select option[value="check-tmp/rp/res"]', { state: "attached" });
  const openRun = async () => {
    await page.selectOption("#results-select", "check-tmp/rp/res");
    await page.click("#load-results");
    await page.waitForSelector("#runs-table tbody tr");
    await page.click("#runs-table tbody tr");
    await page.waitForTimeout(500);
    return page.evaluate(() => {
      const { state } = window.gridplan;
      return {
        map: state.map && state.map.path,
        size: state.map && [state.map.width, state.map.height],
        results: state.results.length,
        status: document.querySelector("#status").textContent,
      };
    });
  };
  const located = await openRun();
  check(located.map === "check-tmp/rp/arena.map" && located.size.join("x") === "49x49" && located.results === 1,
    `a recorded run is drawn on the map its config read (${JSON.stringify(located)})`);
  // The BFS run, opened from the keyboard: its counters are its own (no astar column as
  // null), and no playback count or shading key for cells it does not draw.
  const rows = await page.$$eval("#runs-table tbody tr", (trs) => {
    const planner = Array.from(document.querySelectorAll("#runs-table thead th")).findIndex((th) => th.textContent === "planner");
    return trs.map((tr) => [tr.tabIndex, tr.cells[planner].textContent]);
  });
  const bfsRow = rows.findIndex(([, label]) => label === "b");
  await page.focus(`#runs-table tbody tr:nth-child(${bfsRow + 1})`);
  await page.keyboard.press("Enter");
  await page.waitForFunction(() => window.gridplan.state.results.length === 1 && window.gridplan.state.results[0].label.startsWith("b "), null, { timeout: 5000 }).catch(() => {});
  const recorded = await page.$$eval("table.counters td[data-key]", (tds) => tds.map((td) => [td.dataset.key, td.textContent]));
  check(rows.every(([tabIndex]) => tabIndex === 0) && bfsRow >= 0, `the runs table's rows are reached with Tab (${rows.length} rows)`);
  check(recorded.length > 0 && !recorded.some(([, v]) => v === "null") && !recorded.some(([k]) => k === "shown" || k === "shading" || k === "expanded shown"),
    `a recorded BFS run opened with Enter shows only its own counters, no playback count or shading key (${JSON.stringify(recorded)})`);
  // The config edited since (it is no longer the one that ran): two maps share the name.
  fs.writeFileSync(path.join(scratch, "rp/c.toml"), `# edited\n${probeConfig}`);
  await page.reload();
  await page.waitForSelector('#results-select option[value="check-tmp/rp/res"]', { state: "attached" });
  const ambiguous = await openRun();
  check(ambiguous.map === null && ambiguous.results === 0 && ambiguous.status.includes("check-tmp/rp/aa/arena.map, check-tmp/rp/arena.map") && ambiguous.status.includes("which one the runs used is unknown"),
    `an ambiguous map is said, and the run not drawn (${JSON.stringify(ambiguous)})`);
  check(errors.length === 0, `no page errors ${errors.join("; ")}`);

  // ---- a 700-pixel window: the canvas fits it; a weighted map's key has its shading ----
  const narrow = await browser.newPage({ viewport: { width: 700, height: 900 }, deviceScaleFactor: 1 });
  await narrow.goto(base);
  await narrow.waitForSelector('#map-select option[value="maps/movingai/arena.map"]', { state: "attached" });
  await narrow.selectOption("#map-select", "maps/movingai/arena.map");
  await narrow.fill("#weights", "maps/weighted/arena-weights.csv");
  await narrow.click("#load-map");
  await narrow.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.weights);
  const fit = await narrow.evaluate(() => {
    const canvas = document.querySelector("#views canvas").getBoundingClientRect();
    return { right: canvas.right, scroll: document.documentElement.scrollWidth, key: Array.from(document.querySelectorAll(".map-key .swatch")).map((s) => s.dataset.tone) };
  });
  const listed = await narrow.$$eval("#map-select option", (o) => o.map((e) => e.value));
  await narrow.close();
  check(fit.right <= 700 && fit.scroll <= 700, `the canvas fits a 700-pixel window (right edge ${fit.right}, page ${fit.scroll} wide)`);
  check(fit.key.some((t) => t.startsWith("weight 1 to 9")), `a weighted map's key shows its weight shading (${JSON.stringify(fit.key)})`);
  check(!listed.includes("maps/weighted/arena-weights.csv"), `weight files are not listed as maps`);

  // ---- refusals ----
  for (const bad of ["../../etc/passwd", "/etc/passwd", "escape.map", "maps/../../etc/passwd"]) {
    const status = await page.evaluate(async (p) => (await fetch(`/api/map?path=${encodeURIComponent(p)}`)).status, bad);
    check(status === 403 || status === 404, `GET /api/map?path=${bad}: ${status}`);
  }
  // A request declaring a 100 MB body: the server answers after the head, so the client
  // sends the head and the first MiB and reads the answer (a server reading the body
  // first would wait for the rest, and the check would time out).
  const bodyStatus = await new Promise((resolve) => {
    const url = new URL(base);
    const socket = net.connect(Number(url.port), url.hostname);
    let answer = "";
    const status = () => {
      const m = answer.match(/^HTTP\/1\.1 (\d+)/);
      return m ? Number(m[1]) : null;
    };
    const finish = (result) => {
      clearTimeout(timer);
      socket.destroy();
      resolve(result);
    };
    const timer = setTimeout(() => finish("no answer within 30 s"), 30000);
    socket.on("data", (data) => {
      answer += data.toString("latin1");
      if (status() !== null) finish(status());
    });
    socket.on("error", (e) => finish(status() ?? `error: ${e.message}`));
    socket.write(`POST /api/plan HTTP/1.1\r\nHost: ${url.host}\r\nContent-Type: application/json\r\nContent-Length: ${100 * 1024 * 1024}\r\n\r\n`);
    socket.write(Buffer.alloc(1 << 20, 32));
  });
  check(bodyStatus === 413, `a request declaring a 100 MB body: ${bodyStatus}`);

  // ---- den520d: A* scenario queries planned and drawn, timed in the page ----
  await page.selectOption("#map-select", "maps/movingai/den520d.map");
  await page.click("#load-map");
  await page.waitForFunction(() => window.gridplan.state.map && window.gridplan.state.map.name === "den520d.map");
  const problems = await page.evaluate(() => window.gridplan.state.map.problems);
  // Start and goal markers at least MARKER_RADIUS pixels across on a map drawn at 2 pixels
  // a cell (they were 2 x 2 pixels).
  const markers = await page.evaluate((p) => {
    const { state, START_COLOR, GOAL_COLOR } = window.gridplan;
    document.querySelector("#problem-select").value = "0";
    document.querySelector("#problem-select").dispatchEvent(new Event("change"));
    const canvas = document.querySelector("#views canvas");
    const d = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
    const count = (hex) => {
      const c = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
      let n = 0;
      for (let i = 0; i < d.length; i += 4) if (d[i] === c[0] && d[i + 1] === c[1] && d[i + 2] === c[2]) n++;
      return n;
    };
    return { cell: state.view.cell, start: count(START_COLOR), goal: count(GOAL_COLOR) };
  }, problems[0]);
  check(markers.cell <= 2 && markers.start >= 60 && markers.goal >= 60,
    `den520d's start and goal markers show at ${markers.cell} pixels a cell (${markers.start} and ${markers.goal} pixels of their colours)`);
  const picks = [];
  const n = 25;
  for (let k = 0; k < n; k++) picks.push(Math.floor(((k + 0.5) * problems.length) / n));
  const times = [];
  for (const i of picks) {
    const p = problems[i];
    const t = await page.evaluate(([s, g]) => window.gridplan.timeQuery("astar", s, g), [[p[0], p[1]], [p[2], p[3]]]);
    times.push({ i, ms: t.ms, counters: t.counters });
  }
  const sorted = [...times].sort((a, b) => a.ms - b.ms);
  const median = sorted[Math.floor(sorted.length / 2)];
  const cli = planJson(["maps/movingai/den520d.map", "--planner", "astar", "--problem", String(median.i + 1)]);
  check(JSON.stringify(cli.counters) === JSON.stringify(median.counters), `den520d problem ${median.i + 1}: counters equal plan --json's`);
  console.log(`den520d A*: ${n} scenario queries (every ${Math.round(problems.length / n)}th of ${problems.length}) planned and drawn in the page: median ${median.ms.toFixed(1)} ms (problem ${median.i + 1}, n_expanded ${median.counters.n_expanded}), min ${sorted[0].ms.toFixed(1)} ms, max ${sorted[sorted.length - 1].ms.toFixed(1)} ms`);
  check(median.ms < 200, `the median den520d A* query is planned and drawn within 200 ms (${median.ms.toFixed(1)} ms)`);

  // OPEN's frontier after the playback: the cells drawn in the frontier colour are exactly
  // those plan --trace lists as generated and never expanded.
  const traceDir = fs.mkdtempSync(path.join(process.env.TMPDIR || "/tmp", "gridplan-trace-"));
  const traceFile = path.join(traceDir, "t.trace.json");
  const medianProblem = problems[median.i];
  planJson(["maps/movingai/den520d.map", "--planner", "astar", "--problem", String(median.i + 1), "--trace", traceFile]);
  const traced = JSON.parse(fs.readFileSync(traceFile, "utf8")).events;
  fs.rmSync(traceDir, { recursive: true, force: true });
  const expandedIds = new Set(traced.filter((e) => e.type === "expanding").map((e) => e.id));
  const frontier = new Set(traced.filter((e) => e.type === "generating" && !expandedIds.has(e.id)).map((e) => e.id));
  await page.evaluate(([s, g]) => window.gridplan.timeQuery("astar", s, g), [[medianProblem[0], medianProblem[1]], [medianProblem[2], medianProblem[3]]]);
  const drawn = await page.evaluate(() => {
    const r = window.gridplan.state.results[0];
    const [red, green, blue] = window.gridplan.FRONTIER_COLORS[0];
    const d = r.searchData.data;
    const cells = [];
    for (let i = 0; i < d.length / 4; i++) if (d[4 * i] === red && d[4 * i + 1] === green && d[4 * i + 2] === blue) cells.push(i);
    return cells;
  });
  const same = drawn.length === frontier.size && drawn.every((id) => frontier.has(id));
  check(same && frontier.size > 0, `the frontier drawn is plan --trace's generated and unexpanded cells (${drawn.length} drawn, ${frontier.size} in the trace)`);
} finally {
  await browser.close();
  server.kill();
  fs.rmSync(scratch, { recursive: true, force: true });
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
