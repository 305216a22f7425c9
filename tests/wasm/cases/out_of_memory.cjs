// SPDX-License-Identifier: MIT
// Out of memory is an error object, not an abort: a raw uint8 volume of 800³ voxels (512 MB, within
// the readers' 2³¹-voxel plausibility limit) expands to 2 GB of float samples, more than the
// module's 2 GB WebAssembly memory can hold next to the input. The call returns {ok:false} with a
// message about memory, and the same module then runs the next jobs normally.
'use strict';
module.exports = function (vs, { check }) {
  const n = 800;
  let huge = new Uint8Array(n * n * n);  // zero pages: cheap to make
  let r;
  try {
    r = vs.loadVolume(huge, `huge_${n}x${n}x${n}_uint8.raw`, null);
  } catch (e) {
    r = { thrown: String(e) };
  }
  huge = null;
  check(r && r.ok === false && /memory/i.test(r.message || ''), `out of memory gives {ok:false, message about memory}: ${JSON.stringify(r && (r.message || r.thrown))}`);
  check(r && r.ok === false && !/internal error/.test(r.message || ''), 'the out-of-memory message is not an internal error');

  // The module is still usable: a small volume and a small lens after the failure.
  const ramp = new Uint8Array(24).map((_, i) => i);
  const after = vs.loadVolume(ramp, 'ramp_4x3x2_uint8.raw', null);
  check(after.ok === true && after.samples.length === 24 && after.max === 23, 'loadVolume works after the out-of-memory error: ' + after.message);
  const width = 48, height = 40;
  const pixels = new Uint8Array(width * height).map((_, i) => (i * 7) % 251);
  const lens = vs.lens({ width, height, channels: 1, pixels }, ['circle:24,20,8'], { grid: 16, height: 1, render: false }, null);
  check(lens.ok === true && lens.stats.flipped_triangles === 0, 'lens works after the out-of-memory error: ' + lens.message);
};
