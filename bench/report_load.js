// Times how fast a `blockworld report` site's index opens from file:// in headless Chromium
// (the Debian package, driven by playwright-core, started as tests/browser/check_report.js
// starts it). Prints one JSON line: the scenes, the page size, and per run and as the median
// and the slowest of RUNS runs (a fresh profile each, so nothing comes from the browser's
// cache):
//   load_ms    navigation start to the load event (performance timing of the page);
//   dom_ms     navigation start to DOMContentLoaded (the scripts run, the grid drawn);
//   shown_ms   navigation start to the first page of the grid drawn, with every thumbnail
//              inside the window decoded (the page a reader sees);
//   thumbs     the thumbnails of the first page, and those inside the window.
// Exits 2 on bad usage, 1 when the page does not draw its first page within 30 s.
//
//   node bench/report_load.js SITE_DIR [RUNS]
'use strict';

const fs = require('fs');
const os = require('os');
const path = require('path');
const { pathToFileURL } = require('url');

const PLAYWRIGHT = process.env.BLOCKWORLD_PLAYWRIGHT_CORE ||
  path.join(__dirname, '..', 'target', 'playwright', 'node_modules', 'playwright-core');
const CHROMIUM = process.env.BLOCKWORLD_CHROMIUM || '/usr/bin/chromium';
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

// Runs in the page before its scripts: records, against the navigation's time origin, the
// first animation frame at which the grid holds its first page and every thumbnail inside the
// window has decoded.
function watchFirstPage() {
  function check() {
    var grid = document.getElementById('grid');
    var count = document.getElementById('count');
    if (grid && count && count.dataset.shown !== undefined) {
      var size = window.BLOCKWORLD_PAGE_SIZE || 200;
      var want = Math.min(Number(count.dataset.shown), size);
      var imgs = Array.prototype.slice.call(grid.querySelectorAll('img'));
      var inside = imgs.filter(function (i) {
        var r = i.getBoundingClientRect();
        return r.bottom > 0 && r.top < window.innerHeight;
      });
      var decoded = inside.every(function (i) { return i.complete && i.naturalWidth > 0; });
      if (grid.children.length === want && decoded) {
        window.__firstPage = { shown_ms: performance.now(), thumbs: imgs.length, inside: inside.length };
        return;
      }
    }
    requestAnimationFrame(check);
  }
  requestAnimationFrame(check);
}

async function oneRun(chromium, index) {
  const userData = fs.mkdtempSync(path.join(os.tmpdir(), 'blockworld-chromium-'));
  const browser = await chromium.launchPersistentContext(userData, {
    executablePath: CHROMIUM, args: FLAGS, headless: true, viewport: { width: 1280, height: 900 },
  });
  try {
    const page = await browser.newPage();
    await page.addInitScript(watchFirstPage);
    await page.goto(index, { waitUntil: 'load' });
    await page.waitForFunction(() => window.__firstPage, null, { timeout: 30000 });
    return await page.evaluate(() => {
      const nav = performance.getEntriesByType('navigation')[0];
      const first = window.__firstPage;
      return {
        load_ms: Math.round(nav.loadEventEnd),
        dom_ms: Math.round(nav.domContentLoadedEventEnd),
        shown_ms: Math.round(first.shown_ms),
        thumbs: first.thumbs,
        inside: first.inside,
        scenes: (window.BLOCKWORLD_SCENES || []).length,
        page_size: window.BLOCKWORLD_PAGE_SIZE || 200,
      };
    });
  } finally {
    await browser.close();
    fs.rmSync(userData, { recursive: true, force: true });
  }
}

function median(xs) {
  const s = xs.slice().sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

async function main() {
  const [siteArg, runsArg] = process.argv.slice(2);
  const runs = Number(runsArg || 5);
  if (!siteArg || !Number.isInteger(runs) || runs < 1) {
    console.error('usage: report_load.js SITE_DIR [RUNS >= 1, default 5]');
    process.exit(2);
  }
  const index = path.join(path.resolve(siteArg), 'index.html');
  if (!fs.existsSync(index)) {
    console.error(index + ': no such file; build the site with `blockworld report DATASET -o SITE`');
    process.exit(2);
  }
  const { chromium } = require(PLAYWRIGHT);
  const all = [];
  for (let k = 0; k < runs; k++) all.push(await oneRun(chromium, pathToFileURL(index).href));
  const load = all.map((r) => r.load_ms);
  const shown = all.map((r) => r.shown_ms);
  const dom = all.map((r) => r.dom_ms);
  console.log(JSON.stringify({
    site: path.resolve(siteArg),
    scenes: all[0].scenes,
    page_size: all[0].page_size,
    thumbs: all[0].thumbs,
    thumbs_in_window: all[0].inside,
    load_ms: { median: median(load), max: Math.max(...load), runs: load },
    dom_ms: { median: median(dom), max: Math.max(...dom), runs: dom },
    shown_ms: { median: median(shown), max: Math.max(...shown), runs: shown },
  }));
}

main().catch((e) => { console.error('FAIL ' + (e && e.stack || e)); process.exit(1); });
