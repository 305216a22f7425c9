// SPDX-License-Identifier: MIT
// vol2spline(volume, name, options, progress): a smooth ball fitted to a small density error, the
// reconstruction on the voxel grid, cancellation, and {ok:false, message} for bad input.
'use strict';
module.exports = function (vs, { check }) {
  if (typeof vs.vol2spline !== 'function') { check(false, 'vol2spline is bound'); return; }
  const [nx, ny, nz] = [12, 10, 8];
  const samples = new Float32Array(nx * ny * nz);
  for (let z = 0; z < nz; z++) for (let y = 0; y < ny; y++) for (let x = 0; x < nx; x++) {
    const r2 = ((x - nx / 2) / (nx / 2)) ** 2 + ((y - ny / 2) / (ny / 2)) ** 2 + ((z - nz / 2) / (nz / 2)) ** 2;
    samples[x + nx * (y + ny * z)] = Math.max(0, 1 - r2);
  }
  const volume = { nx, ny, nz, spacing: [1, 1, 1], samples };
  let calls = 0;
  const r = vs.vol2spline(volume, 'ball', { max_levels: 2, max_rms_rel: 0.02, max_control_points: 2000 }, () => { calls++; return true; });
  check(r.ok === true, 'vol2spline(ball) ok: ' + r.message);
  if (r.ok) {
    const s = r.stats;
    check(s.density_rms_rel >= 0 && s.density_rms_rel < 0.05, `ball density_rms_rel ${s.density_rms_rel} < 0.05`);
    check(s.control_points > 0 && s.voxels === nx * ny * nz && s.levels <= 2, `ball control_points ${s.control_points}, voxels ${s.voxels}`);
    check(['target', 'budget', 'diminishing', 'max_levels', 'no_cells'].includes(s.stop_reason) && s.max_control_points === 2000,
          `ball stop_reason ${s.stop_reason}, max_control_points ${s.max_control_points}`);
    check(Array.isArray(s.curve) && s.curve.length >= 1 && s.times_s.total > 0, 'curve and times_s');
    check(r.reconstruction instanceof Float32Array && r.reconstruction.length === nx * ny * nz, 'reconstruction on the voxel grid');
    let se = 0;
    for (let i = 0; i < samples.length; i++) se += (r.reconstruction[i] - samples[i]) ** 2;
    check(Math.abs(Math.sqrt(se / samples.length) - s.density_rms_rel) < 1e-4, 'reconstruction agrees with density_rms_rel (range 1)');
    check(/"volspline-tspline"/.test(new TextDecoder().decode(r.spline_json.slice(0, 200))), 'spline_json');
    check(calls > 0, 'progress reported');
  }
  const cancelled = vs.vol2spline(volume, 'ball', {}, () => false);
  check(cancelled.ok === false && cancelled.message === 'cancelled', 'progress false cancels: ' + cancelled.message);
  const bad = (args, pattern, what) => {
    let x;
    try { x = vs.vol2spline(...args); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(x && x.ok === false && pattern.test(x.message), `${what}: ${JSON.stringify(x && x.message)}`);
  };
  bad([{ nx, ny, nz, samples: new Float32Array(5) }, 'short', {}, null], /short.*samples/, 'too few samples');
  bad([{ nx, ny, samples }, 'nodims', {}, null], /nodims.*nz/, 'missing nz');
  bad([volume, 'ball', { param: 'magic' }, null], /param/, 'unknown param');
  bad([volume, 'ball', { max_rms_rel: -1 }, null], /./, 'negative max_rms_rel');
  bad([{ nx: 1, ny: 1, nz: 1, samples: new Float32Array(1) }, 'dot', {}, null], /dot/, 'a 1×1×1 volume');
};
