// SPDX-License-Identifier: MIT
// Shared start of the page benchmarks (measure_lens_fps.cjs, measure_mesh_fps.cjs): serves
// siteDir on a free 127.0.0.1 port, starts Debian's Chromium headless on SwiftShader, opens the
// page at #tab and waits for the core. Returns {browser, page, close()}.
'use strict';
const { chromium } = require('playwright-core');
const { serve } = require('../../web/serve.cjs');

async function openBenchPage(siteDir, { tab, chromiumPath = '/usr/bin/chromium', viewport = { width: 1400, height: 900 } }) {
  let server;
  const port = await new Promise((resolve) => { server = serve(siteDir, 0, resolve); });
  const browser = await chromium.launch({
    executablePath: chromiumPath, headless: true,
    args: ['--no-sandbox', '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--no-first-run', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = await browser.newPage({ viewport });
  await page.goto(`http://127.0.0.1:${port}/#${tab}`);
  await page.waitForFunction(() => /^core /.test(document.getElementById('core-version').textContent), null, { timeout: 30000 });
  return { browser, page, close: async () => { await browser.close(); server.close(); } };
}

module.exports = { openBenchPage };
