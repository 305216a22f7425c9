// SPDX-License-Identifier: MIT
// WASM/native time ratio of the lens job. Runs the protocol of tests/bench/bench_lens.cpp on the
// node build (camera.png 512×512, circle:256,200,70, magnification 2, grids 100 and 200: calibrate
// h0 once, then the median of 5 fixed-height runs, and the median of 5 calibrated runs), and, given
// the native bench_lens binary, runs it too and prints both with the ratios as JSON.
// usage: node --no-experimental-fetch tests/wasm/bench_lens_wasm.cjs NODE_BUILD.cjs SHARED_DATA [BENCH_LENS]
'use strict';
const fs = require('fs');
const path = require('path');
const { execFileSync } = require('child_process');
const [modulePath, dataDir, nativeBench] = process.argv.slice(2);
if (!modulePath || !dataDir) {
  console.error('usage: node --no-experimental-fetch tests/wasm/bench_lens_wasm.cjs NODE_BUILD.cjs SHARED_DATA [BENCH_LENS]');
  process.exit(2);
}
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];

require(path.resolve(modulePath))().then((vs) => {
  const decoded = vs.decodeImage(new Uint8Array(fs.readFileSync(path.join(dataDir, 'images/camera.png'))), 'camera.png');
  if (!decoded.ok) throw new Error(decoded.message);
  const image = decoded.image;
  const rois = ['circle:256,200,70'];
  const out = { image: 'camera.png 512x512, circle:256,200,70, magnification 2', wasm: {} };
  for (const grid of [100, 200]) {
    const calibrated = vs.lens(image, rois, { grid }, null);
    if (!calibrated.ok) throw new Error(calibrated.message);
    const options = { grid, height: calibrated.stats.height };
    const total = [], wall = [], cpu = [], noRender = [], withCalibration = [];
    for (let run = 0; run < 5; run++) {
      const t0 = performance.now();
      const c0 = process.cpuUsage();
      const r = vs.lens(image, rois, options, null);
      const c1 = process.cpuUsage(c0);
      wall.push(performance.now() - t0);
      // Process CPU time of the call (user + system): robust when the machine is shared.
      cpu.push((c1.user + c1.system) / 1000);
      total.push(r.stats.ms_total);
      noRender.push(r.stats.ms_total - r.stats.ms_render);
      withCalibration.push(vs.lens(image, rois, { grid }, null).stats.ms_total);
    }
    out.wasm['grid_' + grid] = {
      ms_total_median: median(total), cpu_ms_total_median: median(cpu), ms_without_render_median: median(noRender),
      ms_wall_median: median(wall), ms_total_with_calibration_median: median(withCalibration),
      vertices: calibrated.stats.vertices, magnification_center: calibrated.stats.magnification_center,
    };
  }
  if (nativeBench) {
    const native = JSON.parse(execFileSync(nativeBench, { encoding: 'utf8', maxBuffer: 1 << 24 }));
    out.native = {};
    out.ratio_wasm_over_native = {};
    for (const grid of [100, 200]) {
      const n = native['grid_' + grid], w = out.wasm['grid_' + grid];
      out.native['grid_' + grid] = { ms_total_median: n.ms_total_median, cpu_ms_total_median: n.cpu_ms_total_median, ms_without_render_median: n.ms_without_render_median,
                                     ms_total_with_calibration_median: n.ms_total_with_calibration_median };
      out.ratio_wasm_over_native['grid_' + grid] = {
        fixed_height: w.ms_total_median / n.ms_total_median,
        fixed_height_cpu: w.cpu_ms_total_median / n.cpu_ms_total_median,
        without_render: w.ms_without_render_median / n.ms_without_render_median,
        with_calibration: w.ms_total_with_calibration_median / n.ms_total_with_calibration_median,
      };
    }
  }
  console.log(JSON.stringify(out, null, 2));
}).catch((e) => { console.error('bench failed: ' + e.message); process.exit(1); });
