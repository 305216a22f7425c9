// SPDX-License-Identifier: MIT
// Lens frame time while dragging, reproducibly: serves SITE_DIR on a free 127.0.0.1 port, opens
// camera.png in headless Chromium (SwiftShader), calibrates the metric lens on a grid, then moves
// the lens with pointer events dispatched by the page every 8 ms (faster than the lens can follow)
// for SECONDS, ROUNDS times.
// What counts is what reaches the screen. Each round is traced (Chrome tracing through playwright,
// two cheap categories): the display compositor's Display::FrameDisplayed events (a frame put on
// screen) and a performance mark after each animation frame that drew a new live lens. A displayed
// frame counts as a lens frame if a new lens was drawn since the previous displayed frame (two draws
// between two displays count once: one of them was never seen). Per round and overall it reports
// the median interval between such presented lens frames (presented_frame_ms, the headline) and
// their mean rate over the round, beside the page's own interval between lens draws (frame_ms), the
// core's ms_total and the worker round trip.
// usage: node tests/e2e/measure_lens_fps.cjs SITE_DIR [--grid 100] [--seconds 3] [--rounds 5]
//        [--image PATH] [--chromium /usr/bin/chromium]
'use strict';
const fs = require('fs');
const path = require('path');
const { openBenchPage } = require('./bench_page.cjs');

const args = process.argv.slice(2);
const option = (name, fallback) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : fallback; };
const siteDir = args[0];
const grid = option('--grid', '100');
const seconds = Number(option('--seconds', '3'));
const rounds = Number(option('--rounds', '5'));
const image = option('--image', path.resolve(__dirname, '../../samples/images/camera.png'));
// Rounds without frames (NaN) are left out rather than sorted as zeros.
const median = (a) => { const b = a.filter((x) => Number.isFinite(x)).sort((x, y) => x - y); return b.length ? b[b.length >> 1] : NaN; };

async function main() {
  const { browser, page, close } = await openBenchPage(siteDir, { tab: 'lens', chromiumPath: option('--chromium', '/usr/bin/chromium') });
  await page.selectOption('#lens-grid', grid);
  await page.setInputFiles('#lens-file', image);
  await page.waitForFunction(() => window.volspline.lensTab.result && !window.volspline.lensTab.running && !window.volspline.jobs.busy, null, { timeout: 60000 });
  const box = await page.locator('#lens-overlay').boundingBox();
  // A mark after every drawn live lens frame, in the trace's clock.
  await page.evaluate(() => {
    const { lensTab } = window.volspline;
    const shown = lensTab.onFrame.bind(lensTab);
    lensTab.onFrame = () => { const live = !!lensTab.shownLive; shown(); if (live) performance.mark('lens-frame'); };
  });
  const out = { grid: Number(grid), seconds, load_before: fs.readFileSync('/proc/loadavg', 'utf8').trim(), rounds: [] };
  for (let k = 0; k < rounds; k++) {
    // Each round presses at the lens's current centre: a round ends where its wobble left the lens,
    // so a fixed press point drifts out of the lens after a few rounds (no drag, no frames).
    const roi = await page.evaluate(() => ({ ...window.volspline.lensTab.roi, ...window.volspline.lensTab.view.image }));
    const [px, py] = [box.x + roi.cx / roi.width * box.width, box.y + roi.cy / roi.height * box.height];
    await page.mouse.move(px, py);
    await page.mouse.down();
    await browser.startTracing(page, { categories: ['disabled-by-default-display.framedisplayed', 'blink.user_timing'] });
    const r = await page.evaluate(async ([x0, y0, ms]) => {
      const { lensTab } = window.volspline;
      lensTab.frameMs = [];
      lensTab.frameLog = [];
      const overlay = document.getElementById('lens-overlay');
      performance.clearMarks();
      const t0 = performance.now();
      performance.mark('drag-start');
      let moves = 0;
      await new Promise((resolve) => {
        const timer = setInterval(() => {
          const t = performance.now() - t0;
          if (t > ms) { clearInterval(timer); resolve(); return; }
          overlay.dispatchEvent(new PointerEvent('pointermove', { clientX: x0 + 60 * Math.sin(t / 500), clientY: y0 + 30 * Math.sin(t / 350), pointerId: 1, pointerType: 'mouse', buttons: 1, bubbles: true }));
          moves++;
        }, 8);
      });
      performance.mark('drag-end');
      return { moves, log: lensTab.frameLog.map((f) => ({ ...f })) };
    }, [px, py, 1000 * seconds]);
    const trace = JSON.parse((await browser.stopTracing()).toString('utf8'));
    await page.mouse.up();
    await page.waitForFunction(() => !window.volspline.lensTab.running && !window.volspline.jobs.busy, null, { timeout: 60000 });
    const events = trace.traceEvents || trace;
    const at = (name) => events.filter((e) => e.name === name && e.ph !== 'e').map((e) => e.ts / 1000).sort((a, b) => a - b);
    const [start] = at('drag-start'), [end] = at('drag-end');
    const displayed = at('Display::FrameDisplayed').filter((t) => t > start && t <= end);
    const drawn = at('lens-frame').filter((t) => t > start && t <= end);
    const presented = [];
    let d = 0;
    for (let i = 0; i < displayed.length; i++) {
      let any = false;
      while (d < drawn.length && drawn[d] <= displayed[i]) { any = true; d++; }
      if (any) presented.push(displayed[i]);
    }
    const gaps = presented.slice(2).map((t, i) => t - presented[i + 1]);  // the first frames include the press
    const intervals = r.log.slice(2).map((f) => f.ms).filter((x) => x > 0);
    out.rounds.push({ frames: r.log.length, moves: r.moves, translated: r.log.filter((f) => f.translated).length,
                      displayed: displayed.length, presented: presented.length,
                      presented_frame_ms: median(gaps), presented_fps: presented.length / ((end - start) / 1000), frame_ms: median(intervals),
                      core_ms_total: median(r.log.map((f) => f.ms_total)), worker_ms: median(r.log.map((f) => f.ms_worker)) });
  }
  out.load_after = fs.readFileSync('/proc/loadavg', 'utf8').trim();
  out.median_presented_frame_ms = median(out.rounds.map((x) => x.presented_frame_ms));
  out.fps = 1000 / out.median_presented_frame_ms;
  out.median_presented_fps = median(out.rounds.map((x) => x.presented_fps));
  out.median_frame_ms = median(out.rounds.map((x) => x.frame_ms));
  out.median_core_ms_total = median(out.rounds.map((x) => x.core_ms_total));
  out.median_worker_ms = median(out.rounds.map((x) => x.worker_ms));
  console.log(JSON.stringify(out, null, 2));
  await close();
}
main().catch((e) => { console.error('measure failed: ' + (e.stack || e)); process.exit(1); });
