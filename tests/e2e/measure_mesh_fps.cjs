// SPDX-License-Identifier: MIT
// Mesh view frame rate while orbiting, and the time to switch back to the Mesh tab, reproducibly:
// serves SITE_DIR on a free 127.0.0.1 port, opens MESH (default the shared armadillo, 36k
// vertices) in headless Chromium (SwiftShader), then, ROUNDS times, drags the view with pointer
// events the page dispatches every 8 ms (faster than a frame) for SECONDS and counts the animation
// frames that drew (fps = drawn frames / s; a frame that blocks the main thread delays the next
// one, so this is the rate a user sees), and switches Lens → Mesh, timing the click to the end of
// the second animation frame after it (the frame that shows the mesh). With --spline it first
// runs mesh2spline (--levels, default 2) and orbits the spline. Prints JSON with the medians.
// usage: node tests/e2e/measure_mesh_fps.cjs SITE_DIR [--mesh PATH] [--spline] [--levels 2]
//        [--seconds 3] [--rounds 5] [--chromium /usr/bin/chromium]
'use strict';
const fs = require('fs');
const path = require('path');
const { openBenchPage } = require('./bench_page.cjs');

const args = process.argv.slice(2);
const option = (name, fallback) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : fallback; };
const siteDir = args[0];
const mesh = path.resolve(option('--mesh', path.resolve(__dirname, '../../../shared/data/meshes/armadillo.off')));
const seconds = Number(option('--seconds', '3'));
const rounds = Number(option('--rounds', '5'));
const median = (a) => { const b = a.filter((x) => Number.isFinite(x)).sort((x, y) => x - y); return b.length ? b[b.length >> 1] : NaN; };

async function main() {
  const { page, close } = await openBenchPage(siteDir, { tab: 'mesh', chromiumPath: option('--chromium', '/usr/bin/chromium') });
  await page.setInputFiles('#mesh-file', mesh);
  await page.waitForFunction(() => window.volspline.meshTab.info && !window.volspline.jobs.busy, null, { timeout: 120000 });
  const what = { mesh: path.basename(mesh), vertices: await page.evaluate(() => window.volspline.meshTab.info.vertices) };
  if (args.includes('--spline')) {
    await page.selectOption('#mesh-levels', option('--levels', '2'));
    await page.click('#mesh-run');
    await page.waitForFunction(() => window.volspline.meshTab.result || !document.getElementById('error').hidden, null, { timeout: 600000 });
    what.spline = await page.evaluate(() => (window.volspline.meshTab.result ? window.volspline.meshTab.result.stats.control_points : document.getElementById('error-text').textContent));
  }
  await page.waitForTimeout(500);
  // Count draws the same way in every version of the page (older views have no counter).
  await page.evaluate(() => {
    const view = window.volspline.meshTab.view;
    if (view.draws !== undefined) return;
    const draw = view.draw.bind(view);
    view.draws = 0;
    view.draw = () => { view.draws++; draw(); };
  });
  const out = { ...what, seconds, load_before: fs.readFileSync('/proc/loadavg', 'utf8').trim(), orbit_fps: [], tab_switch_ms: [] };
  for (let k = 0; k < rounds; k++) {
    const fps = await page.evaluate(async (s) => {
      const view = window.volspline.meshTab.view;
      const c = view.canvas;
      const r = c.getBoundingClientRect();
      const opts = (x, y) => ({ clientX: r.left + x, clientY: r.top + y, pointerId: 1, bubbles: true, button: 0 });
      c.dispatchEvent(new PointerEvent('pointerdown', opts(r.width / 2, r.height / 2)));
      const draws0 = view.draws;
      const t0 = performance.now();
      let t = 0;
      const timer = setInterval(() => {
        t += 8;
        c.dispatchEvent(new PointerEvent('pointermove', opts(r.width / 2 + 100 * Math.sin(t / 300), r.height / 2 + 30 * Math.cos(t / 500))));
      }, 8);
      await new Promise((resolve) => setTimeout(resolve, 1000 * s));
      clearInterval(timer);
      const drawn = view.draws - draws0, elapsed = performance.now() - t0;
      c.dispatchEvent(new PointerEvent('pointerup', opts(r.width / 2, r.height / 2)));
      return 1000 * drawn / elapsed;
    }, seconds);
    out.orbit_fps.push(fps);
    await page.click('#tab-lens');
    await page.waitForTimeout(300);
    const ms = await page.evaluate(async () => {
      const t0 = performance.now();
      document.getElementById('tab-mesh').click();
      await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
      return performance.now() - t0;
    });
    out.tab_switch_ms.push(ms);
    await page.waitForTimeout(300);
  }
  out.median_orbit_fps = median(out.orbit_fps);
  out.median_tab_switch_ms = median(out.tab_switch_ms);
  out.load_after = fs.readFileSync('/proc/loadavg', 'utf8').trim();
  console.log(JSON.stringify(out, null, 2));
  await close();
}

main().catch((e) => { console.error(e); process.exit(1); });
