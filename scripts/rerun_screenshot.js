// Screenshots Rerun's web viewer showing a recording (docs/rerun.md "Viewer screenshot"): the
// viewer of the rerun-sdk wheel (`rerun --serve-web FILE.rrd`) must already serve it at URL;
// this opens the page in headless Chromium (the Debian package, driven by playwright-core,
// WebGL on the SwiftShader software rasterizer), waits until the viewer has drawn, and writes
// the PNG. Exits 1 when the browser or the page fails, 2 on bad usage.
//
//   node scripts/rerun_screenshot.js URL OUT.png [WAIT_S]
'use strict';

const path = require('path');

const PLAYWRIGHT = process.env.BLOCKWORLD_PLAYWRIGHT_CORE ||
  path.join(__dirname, '..', 'target', 'playwright', 'node_modules', 'playwright-core');
const CHROMIUM = process.env.BLOCKWORLD_CHROMIUM || '/usr/bin/chromium';
const FLAGS = ['--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist', '--disable-background-networking', '--no-first-run'];

async function main() {
  const [url, out, wait] = process.argv.slice(2);
  if (!url || !out) {
    console.error('usage: node scripts/rerun_screenshot.js URL OUT.png [WAIT_S]');
    process.exit(2);
  }
  const { chromium } = require(PLAYWRIGHT);
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: FLAGS });
  try {
    const page = await browser.newPage({ viewport: { width: 1400, height: 860 } });
    await page.goto(url);
    await page.waitForTimeout(1000 * Number(wait || 30));
    const title = await page.title();
    await page.screenshot({ path: out });
    console.log(JSON.stringify({ url, out, title }));
  } finally {
    await browser.close();
  }
}

main().catch((e) => {
  console.error(String(e));
  process.exit(1);
});
