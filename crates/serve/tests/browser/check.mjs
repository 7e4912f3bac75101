// The browser test of `gridplan serve` (run by .ci/run): Debian's Chromium driven by
// Playwright (playwright-core, never downloading a browser).
//
//   node check.mjs GRIDPLAN_BINARY SERVED_DIR
//
// SERVED_DIR holds a copy of the repository's maps/ as maps/ and a link `escape.map` to
// /etc/passwd. The test starts `gridplan serve SERVED_DIR --port 0`, then: loads
// maps/paper/map10.map, clicks start and goal, runs A* and BFS, checks that the counters
// shown equal `gridplan plan --json`'s, that both animations reach the goal, and that a
// screenshot's path-coloured pixels lie on the path's cells; checks the path-traversal and
// body-size refusals; and measures in the page the den520d A* scenario queries planned
// and drawn (performance.now()), printing the median.
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
  check(errors.length === 0, `no page errors ${errors.join("; ")}`);

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
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
