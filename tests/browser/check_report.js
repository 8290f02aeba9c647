// Opens a `blockworld report` site from file:// in headless Chromium (the Debian package,
// driven by playwright-core) and checks it as a reader would use it. Prints one JSON line of
// findings on stdout; exits 1 with the failures on stderr when a check fails, 2 on bad usage.
//
//   node tests/browser/check_report.js SITE_DIR [SCREENSHOT_DIR]
//
// Checks: no console errors or failed requests on any page; every link and image of the index
// and of every scene page resolves to a file of the site; the outcome and family filters change
// the visible count; the first page holds one page of sized thumbnails; switching an overlay on
// changes the screenshot's pixels. With SCREENSHOT_DIR, writes report_index.png and
// report_scene.png there.
'use strict';

const fs = require('fs');
const path = require('path');
const { pathToFileURL, fileURLToPath } = require('url');

const PLAYWRIGHT = process.env.BLOCKWORLD_PLAYWRIGHT_CORE ||
  path.join(__dirname, '..', '..', 'target', 'playwright', 'node_modules', 'playwright-core');
const CHROMIUM = process.env.BLOCKWORLD_CHROMIUM || '/usr/bin/chromium';
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

const failures = [];
const fail = (msg) => failures.push(msg);

function watch(page, errors) {
  page.on('console', (m) => { if (m.type() === 'error') errors.push('console: ' + m.text()); });
  page.on('pageerror', (e) => errors.push('page error: ' + e.message));
  page.on('requestfailed', (r) => errors.push('request failed: ' + r.url()));
}

// Every href and src of the page, as absolute URLs, checked to be files of the site.
async function checkLinks(page, site) {
  const urls = await page.evaluate(() => {
    const out = [];
    document.querySelectorAll('a[href]').forEach((a) => out.push(a.href));
    document.querySelectorAll('img[src], script[src]').forEach((e) => out.push(e.src));
    document.querySelectorAll('link[href]').forEach((e) => out.push(e.href));
    return out;
  });
  let checked = 0;
  for (const u of urls) {
    const url = new URL(u);
    if (url.protocol !== 'file:') { fail(page.url() + ': links off the site: ' + u); continue; }
    if (url.hash && url.pathname === new URL(page.url()).pathname) continue;
    const file = fileURLToPath(url.href.split('#')[0]);
    if (!file.startsWith(site)) fail(page.url() + ': links outside the site: ' + u);
    else if (!fs.existsSync(file)) fail(page.url() + ': broken link or image: ' + u);
    checked++;
  }
  const broken = await page.evaluate(() => Array.from(document.images)
    .filter((i) => i.complete && i.naturalWidth === 0 && i.loading !== 'lazy').map((i) => i.src));
  broken.forEach((b) => fail(page.url() + ': image does not decode: ' + b));
  return checked;
}

async function shownCount(page) {
  return Number(await page.getAttribute('#count', 'data-shown'));
}

async function checkFilters(page) {
  const all = await shownCount(page);
  const outcomes = await page.$$eval('#outcome option', (os) => os.map((o) => o.value).filter((v) => v));
  const families = await page.$$eval('#family option', (os) => os.map((o) => o.value).filter((v) => v));
  const counts = {};
  for (const value of outcomes) {
    await page.selectOption('#outcome', value);
    counts[value] = await shownCount(page);
  }
  await page.selectOption('#outcome', '');
  if (families.length > 0) {
    await page.selectOption('#family', families[0]);
    counts['family=' + families[0]] = await shownCount(page);
    await page.selectOption('#family', '');
  }
  if (!Object.values(counts).some((n) => n !== all)) fail('no filter changes the visible count');
  const grid = await page.$$eval('#grid a', (as) => as.length);
  const size = await page.evaluate(() => window.BLOCKWORLD_PAGE_SIZE);
  if (!(size > 0)) fail('scenes.js sets no page size');
  if (grid !== Math.min(all, size)) fail('the grid shows ' + grid + ' of ' + all + ' scenes');
  // Sized before their pictures load, so lazy loading fetches only those near the window.
  const unsized = await page.$$eval('#grid img', (is) =>
    is.filter((i) => !(Number(i.getAttribute('height')) > 0)).length);
  if (unsized) fail(unsized + ' thumbnails have no height before their pictures load');
  return { all, counts };
}

// Screenshot of the first view with the overlays as the page opens, then with `name` on.
async function checkToggle(page, name) {
  const view = await page.$('figure.view .stack');
  const before = await view.screenshot();
  const box = await page.$('input[data-overlay="' + name + '"]');
  if (!box) { fail(page.url() + ': no toggle ' + name); return 0; }
  await box.setChecked(!(await box.isChecked()));
  const after = await view.screenshot();
  await box.setChecked(!(await box.isChecked()));
  let differ = 0;
  const n = Math.min(before.length, after.length);
  for (let i = 0; i < n; i++) if (before[i] !== after[i]) differ++;
  differ += Math.abs(before.length - after.length);
  if (differ === 0) fail(page.url() + ': toggling ' + name + ' leaves the view unchanged');
  return differ;
}

// The docs' scene picture: the first declined scene (else the first), its answer and the
// vertices' codes over the views.
async function sceneShot(page, scenes, shotDir) {
  await page.goto(pathToFileURL(path.join(path.resolve(process.argv[2]), 'index.html')).href);
  const declined = await page.$$eval('#grid a.o-declined', (as) => as.map((a) => a.href));
  await page.goto(declined[0] || scenes[0], { waitUntil: 'load' });
  const codes = await page.$('input[data-overlay="codes"]');
  if (codes) await codes.setChecked(true);
  await page.screenshot({ path: path.join(shotDir, 'report_scene.png'), fullPage: false });
}

async function main() {
  const [siteArg, shotDir] = process.argv.slice(2);
  if (!siteArg) { console.error('usage: check_report.js SITE_DIR [SCREENSHOT_DIR]'); process.exit(2); }
  const site = path.resolve(siteArg);
  const { chromium } = require(PLAYWRIGHT);
  const userData = fs.mkdtempSync(path.join(require('os').tmpdir(), 'blockworld-chromium-'));
  // A fresh profile (--user-data-dir) each run: playwright takes it as launchPersistentContext's
  // first argument and refuses it among the flags.
  const browser = await chromium.launchPersistentContext(userData, {
    executablePath: CHROMIUM, args: FLAGS, headless: true, viewport: { width: 1280, height: 900 },
  });
  const errors = [];
  const found = { pages: 0, links: 0 };
  try {
    const page = await browser.newPage();
    watch(page, errors);
    const t0 = Date.now();
    await page.goto(pathToFileURL(path.join(site, 'index.html')).href, { waitUntil: 'load' });
    found.index_load_ms = Date.now() - t0;
    found.links += await checkLinks(page, site);
    found.filters = await checkFilters(page);
    if (shotDir) await page.screenshot({ path: path.join(shotDir, 'report_index.png'), fullPage: false });
    const scenes = await page.$$eval('#grid a', (as) => as.map((a) => a.href));
    found.toggles = {};
    for (const [k, href] of scenes.entries()) {
      await page.goto(href, { waitUntil: 'load' });
      found.pages++;
      found.links += await checkLinks(page, site);
      if (k === 0) {
        for (const name of ['truth', 'codes', 'ids', 'depth', 'answer', 'vision']) {
          if (await page.$('input[data-overlay="' + name + '"]')) found.toggles[name] = await checkToggle(page, name);
        }
      }
    }
    if (shotDir) await sceneShot(page, scenes, shotDir);
  } finally {
    await browser.close();
    fs.rmSync(userData, { recursive: true, force: true });
  }
  errors.forEach(fail);
  console.log(JSON.stringify(found));
  if (failures.length) { failures.forEach((f) => console.error('FAIL ' + f)); process.exit(1); }
}

main().catch((e) => { console.error('FAIL ' + (e && e.stack || e)); process.exit(1); });
