// SPDX-License-Identifier: MIT
// Browser end-to-end tests: serves a built site on a free 127.0.0.1 port and drives Debian's
// Chromium headless with playwright-core. Builds nothing itself.
// usage: node tests/e2e/run_e2e.cjs SITE_DIR [--shared-data DIR] [--artifacts DIR] [--chromium PATH]
//   SITE_DIR     the assembled site (build/wasm/site)
//   --shared-data  folder with images/ used when the site bundles no sample image (default ../shared/data)
//   --artifacts  where screenshots go (default tests/artifacts)
// Ends with "N passed, M failed"; exit status 1 if anything failed.
'use strict';
const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');
const { serve } = require('../../web/serve.cjs');

const args = process.argv.slice(2);
const option = (name, fallback) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : fallback; };
const repo = path.resolve(__dirname, '../..');
const siteDir = args.find((a, i) => !a.startsWith('--') && (i === 0 || !args[i - 1].startsWith('--')));
const sharedData = path.resolve(option('--shared-data', path.join(repo, '../shared/data')));
const artifacts = path.resolve(option('--artifacts', path.join(repo, 'tests/artifacts')));
const chromiumPath = option('--chromium', '/usr/bin/chromium');
if (!siteDir || !fs.existsSync(path.join(siteDir, 'index.html'))) {
  console.error('usage: node tests/e2e/run_e2e.cjs SITE_DIR [--shared-data DIR] [--artifacts DIR]');
  console.log('0 passed, 1 failed');
  process.exit(2);
}
fs.mkdirSync(artifacts, { recursive: true });

let passed = 0, failed = 0;
const check = (ok, what) => {
  if (ok) { passed++; console.log('ok   ' + what); } else { failed++; console.log('FAIL ' + what); }
};
const notes = [];

// Fraction of canvas pixels that differ from its corner pixel, and the number of distinct colours
// (quantised): a blank or single-colour canvas gives ~0 and 1.
async function canvasContent(page, selector) {
  return page.evaluate((sel) => {
    const c = document.querySelector(sel);
    const tmp = document.createElement('canvas');
    tmp.width = c.width; tmp.height = c.height;
    const ctx = tmp.getContext('2d');
    ctx.drawImage(c, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    const colours = new Set();
    let differ = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (d[i] !== d[0] || d[i + 1] !== d[1] || d[i + 2] !== d[2]) differ++;
      colours.add((d[i] >> 4) << 8 | (d[i + 1] >> 4) << 4 | d[i + 2] >> 4);
    }
    return { differ: differ / (d.length / 4), colours: colours.size, width: c.width, height: c.height };
  }, selector);
}

const stat = (page, table, key) => page.evaluate(([t, k]) => {
  const td = document.querySelector(`#${t} td[data-key="${k}"]`);
  return td ? td.textContent : null;
}, [table, key]);

async function waitStat(page, table, key, predicate = () => true, timeout = 60000) {
  const t0 = Date.now();
  for (;;) {
    const v = await stat(page, table, key);
    if (v !== null && predicate(v)) return v;
    if (Date.now() - t0 > timeout) return v;
    await page.waitForTimeout(50);
  }
}
const errorText = (page) => page.evaluate(() => (document.getElementById('error').hidden ? '' : document.getElementById('error-text').textContent));
const idle = (page, timeout = 60000) => page.waitForFunction(() => !window.volspline.jobs.busy && !window.volspline.lensTab.running, null, { timeout });

async function main() {
  let server;
  const port = await new Promise((resolve) => { server = serve(siteDir, 0, resolve); });
  const origin = `http://127.0.0.1:${port}`;
  const browser = await chromium.launch({
    executablePath: chromiumPath, headless: true,
    args: ['--no-sandbox', '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--no-first-run', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  const pageErrors = [], foreign = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push('console: ' + m.text()); });
  page.on('request', (r) => { const u = r.url(); if (!u.startsWith(origin) && !u.startsWith('data:') && !u.startsWith('blob:')) foreign.push(u); });

  try {
    // --- page and core
    await page.goto(origin + '/');
    await page.waitForFunction(() => /^core \d+\.\d+\.\d+$/.test(document.getElementById('core-version').textContent), null, { timeout: 30000 })
      .then(() => check(true, 'the page loads and the WebAssembly core reports its version'),
            () => check(false, 'the page loads and the WebAssembly core reports its version'));
    check(await page.evaluate(() => self.crossOriginIsolated), 'the page is cross-origin isolated (cancel through a shared flag)');
    const available = await page.evaluate(() => window.volspline.jobs.ready().then((r) => r.jobs));

    // --- mesh tab: a sample from the menu
    const meshSamples = await page.$$eval('#mesh-samples option', (os) => os.map((o) => o.value).filter(Boolean));
    check(meshSamples.some((v) => v.endsWith('torus.off')), 'the samples menu lists the bundled meshes');
    await page.selectOption('#mesh-samples', meshSamples.find((v) => v.endsWith('torus.off')));
    const genus = await waitStat(page, 'mesh-stats', 'genus');
    const vertices = Number(await stat(page, 'mesh-stats', 'vertices'));
    check(genus === '1' && vertices > 100, `torus.off stats: genus ${genus}, ${vertices} vertices`);
    check((await stat(page, 'mesh-stats', 'closed')) === 'yes', 'torus.off is closed');
    await page.waitForTimeout(200);
    const meshPixels = await canvasContent(page, '#mesh-canvas');
    check(meshPixels.differ > 0.05 && meshPixels.colours > 10, `mesh canvas is not blank (${(100 * meshPixels.differ).toFixed(1)} % drawn, ${meshPixels.colours} colours)`);
    // Orbit: a drag changes the picture.
    const box = await page.locator('#mesh-canvas').boundingBox();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.down();
    await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 40, { steps: 8 });
    await page.mouse.up();
    await page.waitForTimeout(200);
    const rotated = await canvasContent(page, '#mesh-canvas');
    check(Math.abs(rotated.differ - meshPixels.differ) > 1e-4 || rotated.colours !== meshPixels.colours, 'dragging orbits the view');
    await page.screenshot({ path: path.join(artifacts, 'mesh-torus.png') });

    // --- mesh tab: malformed upload shows the core's message; the page keeps working
    await page.setInputFiles('#mesh-file', { name: 'broken.off', mimeType: 'application/octet-stream', buffer: Buffer.from('OFF\n4 2 0\n0 0 0\n1 0 0\n') });
    await page.waitForFunction(() => !document.getElementById('error').hidden, null, { timeout: 20000 }).catch(() => {});
    const meshError = await errorText(page);
    check(/broken\.off/.test(meshError), `a malformed mesh shows an error naming the file: "${meshError}"`);
    await page.screenshot({ path: path.join(artifacts, 'mesh-error.png') });
    await page.selectOption('#mesh-samples', meshSamples.find((v) => v.endsWith('cube.off')));
    const cubeVertices = await waitStat(page, 'mesh-stats', 'vertices', (v) => v === '8');
    check(cubeVertices === '8' && (await errorText(page)) === '', 'after the error a sample still loads (cube: 8 vertices) and the error is cleared');

    if (available.includes('mesh2spline')) {
      notes.push('mesh2spline is in the build but its page test is not written yet');
    } else {
      console.log('skip mesh2spline: not in this build');
    }

    // --- lens tab
    await page.click('#tab-lens');
    const imageSamples = await page.$$eval('#lens-samples option', (os) => os.map((o) => o.value).filter(Boolean));
    if (imageSamples.length) {
      await page.selectOption('#lens-samples', imageSamples[0]);
    } else {
      const fallback = path.join(sharedData, 'images/camera.png');
      console.log('note: the site bundles no sample image; uploading ' + fallback);
      await page.setInputFiles('#lens-file', fallback);
    }
    const magnification = Number(await waitStat(page, 'lens-stats', 'magnification_center'));
    await idle(page);
    const lensStats = async () => page.evaluate(() => ({ ...window.volspline.lensTab.result.stats }));
    let s = await lensStats();
    check(Math.abs(magnification - 2) < 0.5, `metric lens magnification near the wanted 2: ${magnification}`);
    check(s.flipped_triangles === 0 && s.iterations > 0 && Number.isFinite(s.distortion_sum) && s.distortion_sum > 0,
          `metric lens stats sane (flipped ${s.flipped_triangles}, iterations ${s.iterations}, distortion_sum ${s.distortion_sum})`);
    const lensPixels = await canvasContent(page, '#lens-canvas');
    check(lensPixels.differ > 0.05 && lensPixels.colours > 4, `lens canvas is not blank (${(100 * lensPixels.differ).toFixed(1)} % differ, ${lensPixels.colours} colours)`);
    await page.screenshot({ path: path.join(artifacts, 'lens-metric.png') });

    // Drag the lens: live re-runs with the calibrated height; measure the update rate.
    const overlay = await page.locator('#lens-overlay').boundingBox();
    const roi0 = await page.evaluate(() => ({ ...window.volspline.lensTab.roi }));
    const img = await page.evaluate(() => ({ ...window.volspline.lensTab.view.image }));
    const toPage = (x, y) => [overlay.x + x / img.width * overlay.width, overlay.y + y / img.height * overlay.height];
    await page.evaluate(() => { window.volspline.lensTab.frameMs = []; });
    let [px, py] = toPage(roi0.cx, roi0.cy);
    await page.mouse.move(px, py);
    await page.mouse.down();
    const t0 = Date.now();
    for (let k = 1; k <= 60; k++) {
      await page.mouse.move(px + k * 2, py + k);
      await page.waitForTimeout(16);
    }
    await page.mouse.up();
    const dragMs = Date.now() - t0;
    await idle(page);
    const roi1 = await page.evaluate(() => ({ ...window.volspline.lensTab.roi }));
    const frames = await page.evaluate(() => [...window.volspline.lensTab.frameMs]);
    s = await lensStats();
    check(roi1.cx > roi0.cx + 20 && roi1.cy > roi0.cy + 10, `dragging moves the lens (${roi0.cx.toFixed(0)},${roi0.cy.toFixed(0)} -> ${roi1.cx.toFixed(0)},${roi1.cy.toFixed(0)})`);
    check(frames.length >= 3, `the lens re-ran live while dragging (${frames.length} frames in ${dragMs} ms)`);
    check(s.flipped_triangles === 0 && s.ms_calibration === 0, 'live runs reuse the calibrated height and fold nothing');
    const sorted = [...frames].sort((a, b) => a - b);
    const medianMs = sorted.length ? sorted[sorted.length >> 1] : NaN;
    notes.push(`lens drag (grid ${await page.inputValue('#lens-grid')}): median frame ${medianMs.toFixed(1)} ms = ${(1000 / medianMs).toFixed(1)} fps over ${frames.length} frames; per run ms_total ${s.ms_total.toFixed(1)}`);

    // Resize by dragging the rim.
    [px, py] = toPage(roi1.cx + roi1.r, roi1.cy);
    await page.mouse.move(px, py);
    await page.mouse.down();
    await page.mouse.move(px + 30, py, { steps: 5 });
    await page.mouse.up();
    await idle(page);
    const roi2 = await page.evaluate(() => ({ ...window.volspline.lensTab.roi }));
    check(roi2.r > roi1.r + 5, `dragging the rim resizes the lens (r ${roi1.r.toFixed(1)} -> ${roi2.r.toFixed(1)})`);

    // Frame time while dragging, measured with the input faster than the lens can follow: the mouse
    // button is pressed through Playwright, then the page itself moves the pointer every 8 ms
    // for 3 s (Playwright's own moves are paced by its round trips, ~100 ms each). The frame
    // time is the median interval between displayed live results. Printed, never asserted.
    const roiD = await page.evaluate(() => ({ ...window.volspline.lensTab.roi }));
    [px, py] = toPage(roiD.cx, roiD.cy);
    await page.mouse.move(px, py);
    await page.mouse.down();
    const live = await page.evaluate(async ([x0, y0]) => {
      const { lensTab } = window.volspline;
      lensTab.frameMs = [];
      const overlayEl = document.getElementById('lens-overlay');
      const first = lensTab.result;
      const seen = [];
      const t0 = performance.now();
      let moves = 0;
      await new Promise((resolve) => {
        // A timer, not requestAnimationFrame: under the software renderer the page's animation
        // frames slow down with the drawing itself, which would pace the input, not the lens.
        const timer = setInterval(() => {
          const t = performance.now() - t0;
          if (lensTab.result !== seen[seen.length - 1]?.result && lensTab.result !== first)
            seen.push({ result: lensTab.result, at: performance.now() });
          if (t > 3000) { clearInterval(timer); resolve(); return; }
          const dx = 60 * Math.sin(t / 500), dy = 30 * Math.sin(t / 350);  // a wobble around the start
          overlayEl.dispatchEvent(new PointerEvent('pointermove', { clientX: x0 + dx, clientY: y0 + dy, pointerId: 1, pointerType: 'mouse', buttons: 1, bubbles: true }));
          moves++;
        }, 8);
      });
      const totals = seen.map((f) => f.result.stats.ms_total);
      return { moves, frames: [...lensTab.frameMs], totals };
    }, [px, py]);
    await page.mouse.up();
    await idle(page);
    const med = (a) => { const b = [...a].sort((x, y) => x - y); return b.length ? b[b.length >> 1] : NaN; };
    const frameMedian = med(live.frames.slice(1));  // the first interval includes the press
    check(live.frames.length >= 3, `saturated drag re-ran live (${live.frames.length} frames for ${live.moves} pointer moves in 3 s)`);
    notes.push(`lens drag saturated (grid ${await page.inputValue('#lens-grid')}): median frame ${frameMedian.toFixed(1)} ms = ${(1000 / frameMedian).toFixed(1)} fps over ${live.frames.length} frames (${live.moves} pointer moves); median core ms_total ${med(live.totals).toFixed(1)} ms`);
    const timing = await page.evaluate(() => document.getElementById('lens-timing')?.textContent ?? null);
    if (timing !== null) check(/last run [\d.]+ ms/.test(timing) && /frame [\d.]+ ms/.test(timing), `the page shows the run and frame times: "${timing}"`);
    await page.screenshot({ path: path.join(artifacts, 'lens-drag.png') });

    // α re-run time at the calibrated height (the slider's 'change' event, one run each).
    const alphaRuns = await page.evaluate(async () => {
      const { lensTab, jobs } = window.volspline;
      const slider = document.getElementById('lens-alpha');
      const out = [];
      for (const a of ['0.25', '0.5', '0.75', '0.1', '0.6', '0']) {
        const before = lensTab.result;
        const t = performance.now();
        slider.value = a;
        slider.dispatchEvent(new Event('change'));
        while (lensTab.result === before || lensTab.running || jobs.busy) await new Promise((r) => setTimeout(r, 2));
        out.push({ wall: performance.now() - t, total: lensTab.result.stats.ms_total, factorize: lensTab.result.stats.ms_factorize });
      }
      return out;
    });
    check(alphaRuns.length === 6, 'the α slider re-runs the flattening');
    notes.push(`α re-run (grid 100, calibrated height): median core ms_total ${med(alphaRuns.map((r) => r.total)).toFixed(1)} ms, ms_factorize ${med(alphaRuns.map((r) => r.factorize)).toFixed(2)} ms, slider-to-result ${med(alphaRuns.map((r) => r.wall)).toFixed(1)} ms`);

    // α slider re-runs the flattening.
    await page.locator('#lens-alpha').fill('1');
    await page.waitForFunction(() => window.volspline.lensTab.result?.options.alpha === 1, null, { timeout: 30000 }).catch(() => {});
    await idle(page);
    s = await lensStats();
    check((await page.evaluate(() => window.volspline.lensTab.result.options.alpha)) === 1 && s.flipped_triangles === 0,
          `α = 1 (conformal) re-runs: distortion_sum ${s.distortion_sum.toFixed(3)}, magnification ${s.magnification_center.toFixed(3)}, flipped ${s.flipped_triangles}`);
    await page.screenshot({ path: path.join(artifacts, 'lens-alpha1.png') });
    await page.locator('#lens-alpha').fill('0');
    await page.waitForFunction(() => window.volspline.lensTab.result?.options.alpha === 0, null, { timeout: 30000 }).catch(() => {});
    await idle(page);

    // Baselines one click away.
    for (const method of ['fisheye', 'bifocal', 'zoom']) {
      await page.check(`input[name="lens-method"][value="${method}"]`);
      await page.waitForFunction((m) => window.volspline.lensTab.result?.options.method === m, method, { timeout: 30000 }).catch(() => {});
      await idle(page);
      s = await lensStats();
      const m = Number(await stat(page, 'lens-stats', 'magnification_center'));
      check((await stat(page, 'lens-stats', 'method')) === method && s.iterations === 0 && m > 1.2,
            `${method} baseline shown (magnification_center ${m.toFixed(3)})`);
      await page.screenshot({ path: path.join(artifacts, `lens-${method}.png`) });
    }
    await page.check('input[name="lens-method"][value="metric"]');
    await idle(page);

    // Download PNG: the core renders, the browser saves a real PNG.
    const [downloadEvent] = await Promise.all([page.waitForEvent('download', { timeout: 60000 }), page.click('#lens-download-png')]);
    const pngPath = path.join(artifacts, 'lens-download.png');
    await downloadEvent.saveAs(pngPath);
    const png = fs.readFileSync(pngPath);
    check(png.length > 1000 && png.slice(1, 4).toString() === 'PNG', `Download PNG gives a PNG (${png.length} bytes)`);

    // Cancel: a slow job (grid 400, recalibration) is stopped and the worker keeps working.
    const cancelled = await page.evaluate(async () => {
      const { jobs, lensTab } = window.volspline;
      const { cx, cy, r } = lensTab.roi;
      const p = jobs.run('lens', { key: lensTab.key, rois: [{ shape: 'circle', values: [cx, cy, r] }], options: { grid: 400, magnification: 3.3 } });
      setTimeout(() => jobs.cancel(), 100);
      const t = performance.now();
      const r1 = await p;
      return { message: r1.message, ok: r1.ok, ms: performance.now() - t };
    });
    check(cancelled.ok === false && cancelled.message === 'cancelled', `Cancel stops a running job (${cancelled.message} after ${cancelled.ms.toFixed(0)} ms)`);

    // Malformed image: the core's message, then the page still works.
    await page.setInputFiles('#lens-file', { name: 'broken.png', mimeType: 'image/png', buffer: Buffer.from('\x89PNG\r\n\x1a\nnot really') });
    await page.waitForFunction(() => !document.getElementById('error').hidden, null, { timeout: 20000 }).catch(() => {});
    const lensError = await errorText(page);
    check(/broken\.png/.test(lensError), `a malformed image shows an error naming the file: "${lensError}"`);
    await page.screenshot({ path: path.join(artifacts, 'lens-error.png') });
    await page.locator('#lens-magnification').fill('2.5');
    await page.waitForFunction(() => window.volspline.lensTab.result?.options.magnification === 2.5, null, { timeout: 60000 }).catch(() => {});
    await idle(page);
    s = await lensStats();
    check(Math.abs(s.magnification_center - 2.5) < 0.6 && s.flipped_triangles === 0,
          `after the error the lens still runs (magnification 2.5 -> measured ${s.magnification_center.toFixed(3)})`);
    await page.screenshot({ path: path.join(artifacts, 'lens-after-error.png') });

    check(foreign.length === 0, 'no request leaves 127.0.0.1' + (foreign.length ? ': ' + foreign.join(' ') : ''));
    check(pageErrors.length === 0, 'no uncaught page errors' + (pageErrors.length ? ': ' + pageErrors.join(' | ') : ''));
  } catch (e) {
    check(false, 'test run aborted: ' + (e.stack || e));
    await page.screenshot({ path: path.join(artifacts, 'aborted.png') }).catch(() => {});
  } finally {
    await browser.close();
    server.close();
  }
  for (const n of notes) console.log('note: ' + n);
  console.log(`screenshots in ${artifacts}`);
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed === 0 ? 0 : 1);
}

main().catch((e) => { console.log('FAIL ' + e); console.log(`${passed} passed, ${failed + 1} failed`); process.exit(1); });
