#!/usr/bin/env node
// The real-viewer check of scripts/check_viewer.sh: opens MCAP files in Foxglove Studio's web
// build (served from --www on 127.0.0.1) in headless Chromium, as a user does — "Open local
// file" after Layouts > "Import layout" of a shipped layout — plays them to the end, and
// fails when the viewer reports a problem or a panel shows no data. Writes a screenshot per case.
//
//   node check_viewer.cjs --www DIR --out DIR [--chromium /usr/bin/chromium]
//        --case NAME FILE.mcap LAYOUT.json COLOURS [--expect-failure REGEX] ...
//
// COLOURS: comma-separated colours of scene entities that each 3-D panel of the layout must
// show, "-" for none: #rrggbb (a line colour: at least MIN_PIXELS pixels within an L1 distance
// of COLOUR_DISTANCE) or #rrggbb/DISTANCE/PIXELS (e.g. a lit, translucent surface). With
// --expect-failure REGEX after a case, that case must fail with a problem matching REGEX (the
// check's self-test: it shows that the check catches what it is meant to).
//
// A case fails when: the page throws; the console reports an error; the player reports a
// problem (the data source's Problems list, "Player problem" in the console); an error toast
// shows; a 3-D panel logs a topic, frame or transform error after playback started; a 3-D
// panel lacks one of COLOURS; a Plot panel's data ("Download plot data as CSV") has no finite
// value for one of its series.
// Prints one JSON document (per case: ok, problems, screenshot, series counts) and exits 0
// when every case behaved as expected, 1 otherwise, 2 on bad usage.
"use strict";
const fs = require("fs");
const http = require("http");
const path = require("path");
const { chromium } = require("playwright-core");

const MIN_PIXELS = 150;
const COLOUR_DISTANCE = 40;
const VIEWPORT = { width: 1600, height: 1000 };
// Software WebGL on a loaded 2-core machine can take a while to deliver a frame.
const SCREENSHOT_TIMEOUT = 120000;
// Waits for the viewer's UI (the machines that run this are often loaded).
const WAIT = 120000;
// Quiet console time (ms) that counts as settled.
const QUIET = 4000;
// Longest playback (the files the check writes last 20 s of motion at most, played at 1x).
const PLAY_LIMIT = 300000;
// Chromium as root in a container: no sandbox; no background traffic (the network is closed);
// WebGL through SwiftShader (no GPU).
const CHROMIUM_ARGS = [
  "--no-sandbox",
  "--disable-gpu-sandbox",
  "--use-angle=swiftshader",
  "--enable-unsafe-swiftshader",
  "--ignore-gpu-blocklist",
  "--disable-background-networking",
  "--disable-component-update",
  "--disable-sync",
  "--disable-quic",
  "--no-first-run",
];

function usage(msg) {
  console.error(`check_viewer: ${msg}\nusage: node check_viewer.cjs --www DIR --out DIR [--chromium PATH] --case NAME FILE LAYOUT COLOURS [--expect-failure REGEX] ...`);
  process.exit(2);
}

function parseColour(spec) {
  const m = /^#([0-9a-fA-F]{6})(?:\/(\d+)\/(\d+))?$/.exec(spec);
  if (!m) usage(`bad colour ${spec} (want #rrggbb or #rrggbb/DISTANCE/PIXELS)`);
  return { spec, rgb: [0, 2, 4].map((i) => parseInt(m[1].slice(i, i + 2), 16)), distance: m[2] ? Number(m[2]) : COLOUR_DISTANCE, min: m[3] ? Number(m[3]) : MIN_PIXELS };
}

function parseArgs(argv) {
  const opts = { chromium: "/usr/bin/chromium", cases: [] };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === "--www" || a === "--out" || a === "--chromium") {
      if (i + 1 >= argv.length) usage(`${a} wants a value`);
      opts[a.slice(2)] = argv[++i];
    } else if (a === "--case") {
      if (i + 4 >= argv.length) usage("--case wants NAME FILE LAYOUT COLOURS");
      const [name, file, layout, colours] = argv.slice(i + 1, i + 5);
      i += 4;
      for (const f of [file, layout]) if (!fs.existsSync(f)) usage(`no such file: ${f}`);
      opts.cases.push({ name, file: path.resolve(file), layout: path.resolve(layout), colours: colours === "-" ? [] : colours.split(",").map(parseColour), expectFailure: false });
    } else if (a === "--expect-failure") {
      if (!opts.cases.length || i + 1 >= argv.length) usage("--expect-failure REGEX follows a --case");
      opts.cases[opts.cases.length - 1].expectFailure = new RegExp(argv[++i]);
    } else {
      usage(`unknown argument ${a}`);
    }
  }
  if (!opts.www || !opts.out || !opts.cases.length) usage("--www, --out and at least one --case are needed");
  return opts;
}

// A static server on 127.0.0.1 (ephemeral port): the Studio build under /, the case files
// under /files/N/NAME. Honours Range requests (the remote-file data source uses them).
function serve(www, files) {
  const types = { ".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm", ".json": "application/json", ".css": "text/css", ".png": "image/png", ".svg": "image/svg+xml", ".woff2": "font/woff2" };
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, "http://x").pathname);
    if (url === "/favicon.ico") {
      res.writeHead(204).end();
      return;
    }
    let file;
    const m = url.match(/^\/files\/(\d+)\/[^/]+$/);
    if (m) file = files[Number(m[1])];
    else {
      file = path.join(www, path.normalize(url).replace(/^(\.\.[/\\])+/, ""));
      if (url.endsWith("/")) file = path.join(file, "index.html");
    }
    let stat;
    try {
      stat = fs.statSync(file);
    } catch {
      res.writeHead(404).end("not found");
      return;
    }
    const headers = { "Content-Type": types[path.extname(file)] || "application/octet-stream", "Accept-Ranges": "bytes" };
    const range = /^bytes=(\d*)-(\d*)$/.exec(req.headers.range || "");
    if (range) {
      let start = range[1] ? Number(range[1]) : stat.size - Number(range[2]);
      let end = range[1] && range[2] ? Number(range[2]) : stat.size - 1;
      end = Math.min(end, stat.size - 1);
      start = Math.max(0, start);
      res.writeHead(206, { ...headers, "Content-Range": `bytes ${start}-${end}/${stat.size}`, "Content-Length": end - start + 1 });
      fs.createReadStream(file, { start, end }).pipe(res);
    } else {
      res.writeHead(200, { ...headers, "Content-Length": stat.size });
      fs.createReadStream(file).pipe(res);
    }
  });
  return new Promise((resolve) => server.listen(0, "127.0.0.1", () => resolve(server)));
}

// In the page: the browser's file picker, answered with the next queued file. The file is put
// into the origin-private file system so Studio gets a real FileSystemFileHandle (it checks its
// permission and keeps it in its list of recent files), as from a user's pick.
function installFilePicker() {
  window.__rstsPicks = [];
  window.showOpenFilePicker = async () => {
    const url = window.__rstsPicks.shift();
    if (!url) throw new DOMException("no file queued", "AbortError");
    const name = decodeURIComponent(url.split("/").pop());
    const root = await navigator.storage.getDirectory();
    const handle = await root.getFileHandle(name, { create: true });
    const writable = await handle.createWritable();
    await writable.write(await (await fetch(url)).blob());
    await writable.close();
    return [handle];
  };
}

// Closes the first-use hints ("Open settings to configure topics and layers.") that cover panels.
async function closeHints(page) {
  await page.evaluate(() => {
    for (const el of document.querySelectorAll("body *")) {
      if (el.childElementCount === 0 && /^Open settings to configure/.test(el.textContent || "")) {
        let box = el;
        for (let up = 0; up < 4 && box && !box.querySelector("button"); up++) box = box.parentElement;
        box?.querySelector("button")?.click();
      }
    }
  });
  await page.waitForTimeout(300);
}

// Pixels of `png` near each colour of `colours` (parsed by parseColour).
function countColours(page, png, colours) {
  return page.evaluate(
    async ({ b64, colours }) => {
      const img = new Image();
      img.src = `data:image/png;base64,${b64}`;
      await img.decode();
      const canvas = document.createElement("canvas");
      canvas.width = img.width;
      canvas.height = img.height;
      const ctx = canvas.getContext("2d");
      ctx.drawImage(img, 0, 0);
      const data = ctx.getImageData(0, 0, img.width, img.height).data;
      const counts = colours.map(() => 0);
      for (let p = 0; p < data.length; p += 4) {
        for (let k = 0; k < colours.length; k++) {
          const [r, g, b] = colours[k].rgb;
          if (Math.abs(data[p] - r) + Math.abs(data[p + 1] - g) + Math.abs(data[p + 2] - b) <= colours[k].distance) counts[k]++;
        }
      }
      return counts;
    },
    { b64: png.toString("base64"), colours },
  );
}

// Parses Studio's plot CSV (columns: x, receive time, header.stamp, topic, value): finite values per series.
function seriesCounts(csv) {
  const counts = {};
  for (const line of csv.split("\n").slice(1)) {
    if (!line) continue;
    const cells = line.split(",");
    const value = Number(cells[cells.length - 1]);
    const label = cells.slice(3, cells.length - 1).join(",");
    counts[label] = (counts[label] || 0) + (Number.isFinite(value) ? 1 : 0);
  }
  return counts;
}

async function runCase(browser, base, index, c, outDir) {
  const problems = [];
  const log = [];
  const context = await browser.newContext({ viewport: VIEWPORT, acceptDownloads: true });
  await context.addInitScript(installFilePicker);
  const page = await context.newPage();
  let playing = false;
  const firstLine = (t) => String(t).split("\n")[0].slice(0, 300);
  page.on("pageerror", (e) => problems.push(`page error: ${firstLine(e)}`));
  const t0 = Date.now();
  const stamp = () => `${((Date.now() - t0) / 1000).toFixed(1).padStart(6)} s`;
  const step = (what) => log.push(`${stamp()} [check] ${what}`);
  // The viewer remounts its panels after a layout import and after a file opens; a 3-D panel
  // still re-creating its renderer when playback starts may show none of the scene (seen once on a
  // loaded machine: a check file played with an empty 3-D panel, fine when rerun). So each step
  // waits until the console has been quiet for QUIET ms, as a person would before going on.
  let lastConsole = Date.now();
  const settle = async () => {
    const limit = Date.now() + WAIT;
    while (Date.now() < limit && Date.now() - lastConsole < QUIET) await page.waitForTimeout(250);
  };
  page.on("console", (m) => {
    lastConsole = Date.now();
    const text = m.text();
    log.push(`${stamp()} [${m.type()}] ${text}`);
    if (m.type() === "error") problems.push(`console error: ${firstLine(text)}`);
    // The 3-D panel logs its settings-tree errors as "[topics > /x] ...", "[transforms > ...]".
    else if (playing && m.type() === "warning" && /^\[(topics|transforms|general|layers) >/.test(text)) {
      problems.push(`3-D panel: ${firstLine(text)}`);
    }
  });
  const result = { name: c.name, file: c.file, layout: c.layout, expect_failure: c.expectFailure ? String(c.expectFailure) : null };
  try {
    await page.goto(`${base}/index.html`, { waitUntil: "domcontentloaded", timeout: WAIT });
    await page.getByText("Open local file", { exact: true }).waitFor({ timeout: WAIT });
    step("page loaded");
    // 1. Layouts > Import layout (a user imports it once; it stays for every file opened later).
    await page.getByRole("button", { name: "Dismiss" }).click().catch(() => {});
    await page.keyboard.press("Escape");
    await page.locator('button[title="Layouts"]').click();
    await page.evaluate((u) => window.__rstsPicks.push(u), `${base}/files/${index + 1}/${encodeURIComponent(path.basename(c.layout))}`);
    await page.locator('button[title="Import layout"]').click();
    const layoutName = path.basename(c.layout, ".json");
    await page.getByText(layoutName, { exact: true }).first().waitFor({ timeout: WAIT });
    await settle();
    step("layout imported");
    // 2. Data source > Open local file.
    await page.locator('button[title="Data source"]').click();
    await page.locator('button[title="New connection"]').click().catch(() => {});
    const open = page.getByText("Open local file", { exact: true });
    await open.waitFor({ timeout: WAIT });
    await page.evaluate((u) => window.__rstsPicks.push(u), `${base}/files/${index}/${encodeURIComponent(path.basename(c.file))}`);
    await open.click();
    await page.getByText(path.basename(c.file)).first().waitFor({ timeout: WAIT });
    step("file opened");
    await page.locator('button[title="Data source"]').click(); // close the sidebar
    await page.waitForTimeout(3000);
    await settle();
    await closeHints(page);
    // 3. Play to the end.
    // (Unless the viewer already reported a problem and will not play.)
    const play = page.locator('button[title^="Play"]').first();
    const ready = Date.now() + WAIT;
    while (Date.now() < ready && problems.length === 0 && !(await play.isEnabled().catch(() => false))) {
      await page.waitForTimeout(500);
    }
    if (await play.isEnabled().catch(() => false)) {
      playing = true;
      step("play");
      await play.click({ timeout: WAIT });
      const end = Date.now() + PLAY_LIMIT;
      while (Date.now() < end) {
        await page.waitForTimeout(1000);
        if ((await page.locator('button[title^="Pause"]').count()) === 0) break;
      }
      if (Date.now() >= end) problems.push(`playback did not reach the end within ${PLAY_LIMIT / 1000} s`);
    } else if (problems.length === 0) {
      problems.push("the Play button never became enabled (no data loaded?)");
    }
    await page.waitForTimeout(1500);
    await closeHints(page);
    step("end of playback; screenshot");
    result.screenshot = path.join(outDir, `${c.name}.png`);
    await page.screenshot({ path: result.screenshot, timeout: SCREENSHOT_TIMEOUT });
    // 4. Problems the viewer shows.
    for (const t of await page.locator(".notistack-MuiContent-error, .SnackbarItem-variantError, [class*='variantError']").allInnerTexts()) {
      problems.push(`error toast: ${t.trim().slice(0, 300)}`);
    }
    const badge = await page.locator('button[title="Data source"] .MuiBadge-badge').allInnerTexts();
    if (badge.some((t) => t.trim() !== "" && t.trim() !== "0")) {
      await page.locator('button[title="Data source"]').click();
      await page.getByText("Problems").first().click().catch(() => {});
      await page.waitForTimeout(500);
      await page.screenshot({ path: path.join(outDir, `${c.name}_problems.png`), timeout: SCREENSHOT_TIMEOUT });
      problems.push(`the data source reports ${badge.join(" ")} problem(s); see ${c.name}_problems.png`);
    }
    // 5. Every panel shows data.
    result.panels = [];
    const panels = page.locator('[data-testid^="panel-mouseenter-container"]');
    const n = await panels.count();
    for (let i = 0; i < n; i++) {
      const panel = panels.nth(i);
      const id = ((await panel.getAttribute("data-testid")) || "").replace("panel-mouseenter-container", "").trim();
      const title = (await panel.locator(".MuiTypography-body2").first().innerText().catch(() => "")).trim() || id || `panel ${i}`;
      const download = panel.locator('button[title="Download plot data as CSV"]');
      const canvas = panel.locator("canvas").first();
      if ((await download.count()) > 0) {
        const wait = page.waitForEvent("download", { timeout: WAIT });
        await download.click();
        const file = path.join(outDir, `${c.name}_plot${i}.csv`);
        await (await wait).saveAs(file);
        const counts = seriesCounts(fs.readFileSync(file, "utf8"));
        const legend = (await panel.locator('[class*="legend"], [class*="Legend"]').first().innerText().catch(() => "")).split("\n").map((s) => s.trim()).filter(Boolean);
        result.panels.push({ kind: "plot", title, series: counts });
        const empty = Object.entries(counts).filter(([, k]) => k === 0).map(([l]) => l);
        if (Object.keys(counts).length === 0) problems.push(`plot "${title}" shows no data at all (legend: ${legend.join(" | ")})`);
        if (empty.length) problems.push(`plot "${title}": no data for ${empty.join(", ")}`);
      } else if ((await canvas.count()) > 0 && c.colours.length > 0) {
        const box = await canvas.boundingBox();
        const png = await page.screenshot({ clip: box, timeout: SCREENSHOT_TIMEOUT });
        const counts = await countColours(page, png, c.colours);
        result.panels.push({ kind: "3d", title, colour_pixels: Object.fromEntries(c.colours.map((col, k) => [col.spec, counts[k]])) });
        c.colours.forEach((col, k) => {
          if (counts[k] < col.min) problems.push(`3-D panel "${title}": ${counts[k]} pixels of ${col.spec} (scene data not shown; at least ${col.min} expected)`);
        });
      }
    }
    if (!result.panels.some((p) => p.kind === "3d") && c.colours.length > 0) problems.push("no 3-D panel found");
  } catch (e) {
    problems.push(`the check could not drive the viewer: ${String(e.message || e).split("\n")[0]}`);
    await page.screenshot({ path: path.join(outDir, `${c.name}_failed.png`), timeout: SCREENSHOT_TIMEOUT }).catch(() => {});
  }
  fs.writeFileSync(path.join(outDir, `${c.name}_console.txt`), log.join("\n") + "\n");
  await context.close();
  result.problems = [...new Set(problems)];
  result.ok = result.problems.length === 0;
  result.as_expected = c.expectFailure ? result.problems.some((p) => c.expectFailure.test(p)) : result.ok;
  return result;
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  fs.mkdirSync(opts.out, { recursive: true });
  const files = opts.cases.flatMap((c) => [c.file, c.layout]);
  const server = await serve(path.resolve(opts.www), files);
  const base = `http://127.0.0.1:${server.address().port}`;
  const browser = await chromium.launch({ executablePath: opts.chromium, headless: true, args: CHROMIUM_ARGS });
  const results = [];
  try {
    for (let k = 0; k < opts.cases.length; k++) {
      const c = opts.cases[k];
      console.error(`check_viewer: ${c.name}: ${path.basename(c.file)} with ${path.basename(c.layout)}${c.expectFailure ? ` (self-test: must fail with ${c.expectFailure})` : ""} ...`);
      const started = Date.now();
      const r = await runCase(browser, base, 2 * k, c, opts.out);
      r.seconds = Math.round((Date.now() - started) / 1000);
      console.error(`check_viewer: ${c.name}: ${r.ok ? "no problem" : r.problems.length + " problem(s)"} (${r.seconds} s)${r.as_expected ? "" : "  <-- NOT AS EXPECTED"}`);
      for (const p of r.problems) console.error(`    ${p}`);
      results.push(r);
    }
  } finally {
    await browser.close();
    server.close();
  }
  process.stdout.write(JSON.stringify({ viewer: "Foxglove Studio 1.48.0 (web build)", results }, null, 2) + "\n");
  return results.every((r) => r.as_expected) ? 0 : 1;
}

main().then(
  (code) => process.exit(code),
  (e) => {
    console.error(`check_viewer: ${e.stack || e}`);
    process.exit(2);
  },
);
