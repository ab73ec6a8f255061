#!/usr/bin/env node
// The real-browser check of an rsts dashboard (scripts/check_dashboard.sh): opens pages of the
// static site from the file system (file:// URLs, as a user double-clicking index.html does) in
// headless Chromium, and fails when a page throws, logs a console error, asks for anything that
// is not a local file (the site must work offline: no CDN, no server), or lacks an element it
// must show. Takes a full-page screenshot of each page.
//
//   node check_dashboard.cjs --out DIR [--chromium /usr/bin/chromium] [--first-screen]
//        --page NAME FILE.html [--expect CSS-SELECTOR]... ...
//
// --first-screen: screenshots of the first 1400×1000 of each page instead of the whole page.
//
// Prints one JSON document (per page: ok, problems, screenshot, counts of each expected selector)
// and exits 0 when every page is fine, 1 otherwise, 2 on bad usage or when the browser cannot run.
"use strict";
const fs = require("fs");
const path = require("path");
const { pathToFileURL } = require("url");
const { chromium } = require("playwright-core");

const CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run"];
const VIEWPORT = { width: 1400, height: 1000 };
const WAIT = 60000;

function usage(msg) {
  console.error(`check_dashboard: ${msg}\nusage: node check_dashboard.cjs --out DIR [--chromium PATH] [--first-screen] --page NAME FILE [--expect SELECTOR]... ...`);
  process.exit(2);
}

function parseArgs(argv) {
  const opts = { chromium: "/usr/bin/chromium", pages: [], fullPage: true };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === "--out" || a === "--chromium") {
      if (i + 1 >= argv.length) usage(`${a} wants a value`);
      opts[a.slice(2)] = argv[++i];
    } else if (a === "--first-screen") {
      opts.fullPage = false;
    } else if (a === "--page") {
      if (i + 2 >= argv.length) usage("--page wants NAME FILE");
      const [name, file] = argv.slice(i + 1, i + 3);
      i += 2;
      if (!fs.existsSync(file)) usage(`no such file: ${file}`);
      opts.pages.push({ name, file: path.resolve(file), expect: [] });
    } else if (a === "--expect") {
      if (!opts.pages.length || i + 1 >= argv.length) usage("--expect SELECTOR follows a --page");
      opts.pages[opts.pages.length - 1].expect.push(argv[++i]);
    } else {
      usage(`unknown argument ${a}`);
    }
  }
  if (!opts.out || !opts.pages.length) usage("--out and at least one --page are needed");
  return opts;
}

async function check(browser, p, outDir, fullPage) {
  const problems = [];
  const console_ = [];
  const context = await browser.newContext({ viewport: VIEWPORT });
  const page = await context.newPage();
  page.on("pageerror", (e) => problems.push(`page error: ${String(e).split("\n")[0]}`));
  page.on("console", (m) => {
    console_.push(`[${m.type()}] ${m.text()}`);
    if (m.type() === "error") problems.push(`console error: ${m.text().slice(0, 300)}`);
  });
  page.on("requestfailed", (r) => problems.push(`request failed: ${r.url()} (${r.failure()?.errorText})`));
  // Offline: anything but a local file is refused and counted.
  await context.route("**/*", (route) => {
    const url = route.request().url();
    if (url.startsWith("file://") || url.startsWith("data:")) return route.continue();
    problems.push(`asked for ${url} (the site must work offline)`);
    return route.abort();
  });
  const result = { name: p.name, file: p.file };
  try {
    await page.goto(pathToFileURL(p.file).href, { waitUntil: "load", timeout: WAIT });
    await page.waitForTimeout(300);
    result.title = await page.title();
    result.counts = {};
    for (const sel of p.expect) {
      const n = await page.locator(sel).count();
      result.counts[sel] = n;
      if (n === 0) problems.push(`nothing matches ${sel}`);
    }
    // Every inline SVG plot drew something (a polyline or a marker).
    result.plots = await page.locator("figure.plot svg").count();
    result.empty_plots = await page.locator("figure.plot").evaluateAll((figs) => figs.filter((f) => !f.querySelector("polyline, circle")).length);
    if (result.empty_plots > 0) problems.push(`${result.empty_plots} plot(s) without a line or marker`);
    result.screenshot = path.join(outDir, `${p.name}.png`);
    await page.screenshot({ path: result.screenshot, fullPage, timeout: WAIT });
  } catch (e) {
    problems.push(`could not open the page: ${String(e.message || e).split("\n")[0]}`);
  }
  fs.writeFileSync(path.join(outDir, `${p.name}_console.txt`), console_.join("\n") + "\n");
  await context.close();
  result.problems = problems;
  result.ok = problems.length === 0;
  return result;
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  fs.mkdirSync(opts.out, { recursive: true });
  let browser;
  try {
    browser = await chromium.launch({ executablePath: opts.chromium, headless: true, args: CHROMIUM_ARGS });
  } catch (e) {
    console.error(`check_dashboard: cannot start ${opts.chromium}: ${String(e.message || e).split("\n")[0]}`);
    return 2;
  }
  const results = [];
  try {
    for (const p of opts.pages) {
      const r = await check(browser, p, path.resolve(opts.out), opts.fullPage);
      console.error(`check_dashboard: ${p.name}: ${r.ok ? "ok" : r.problems.length + " problem(s)"}`);
      for (const x of r.problems) console.error(`    ${x}`);
      results.push(r);
    }
  } finally {
    await browser.close();
  }
  process.stdout.write(JSON.stringify({ browser: "chromium (headless)", results }, null, 2) + "\n");
  return results.every((r) => r.ok) ? 0 : 1;
}

main().then((code) => process.exit(code), (e) => { console.error(`check_dashboard: ${e.stack || e}`); process.exit(2); });
