// SPDX-License-Identifier: MIT
// lens(image, rois, options, progress), decodeImage and encodePng on small synthetic images:
// typed arrays out, stats with sane values, progress and cancellation, errors as {ok:false, message}.
'use strict';
module.exports = function (vs, { check }) {
  // 64×48 RGB checkerboard of 8-pixel squares with a colour ramp, deterministic.
  const width = 64, height = 48;
  const pixels = new Uint8Array(width * height * 3);
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      const i = 3 * (y * width + x), on = ((x >> 3) + (y >> 3)) & 1;
      pixels[i] = on ? 230 : 20; pixels[i + 1] = (4 * x) & 255; pixels[i + 2] = (5 * y) & 255;
    }
  }
  const image = { width, height, channels: 3, pixels, name: 'checker' };

  const png = vs.encodePng(image);
  check(png.ok && png.bytes instanceof Uint8Array && png.bytes[1] === 0x50, 'encodePng gives PNG bytes');
  const decoded = png.ok ? vs.decodeImage(png.bytes, 'checker.png') : { ok: false };
  check(decoded.ok && decoded.image.width === width && decoded.image.height === height && decoded.image.channels === 3,
        'decodeImage(encodePng(image)) keeps the size');
  check(decoded.ok && decoded.image.pixels.every((v, i) => v === pixels[i]), 'PNG round trip is lossless');

  const stages = [];
  const progress = (stage, fraction) => { stages.push([stage, fraction]); return true; };
  const roi = { shape: 'circle', values: [32, 24, 10] };
  const metric = vs.lens(image, [roi], { magnification: 2, grid: 24 }, progress);
  check(metric.ok === true, 'metric lens ok: ' + metric.message);
  if (metric.ok) {
    const s = metric.stats;
    check(s.flipped_triangles === 0, 'metric lens: no flipped triangles');
    // The job calibrates h0 on a coarse grid to reach the wanted magnification; 25 % is what a
    // 24-vertex grid resolves at a 10-pixel ROI.
    check(Math.abs(s.magnification_center - 2) < 0.5, 'metric lens magnification near 2: ' + s.magnification_center);
    check(s.iterations > 0 && s.height > 0 && s.distortion_sum >= 0 && s.distortion_max >= 0, 'metric lens stats sane');
    check(metric.positions instanceof Float32Array && metric.positions.length === 2 * s.vertices, 'positions Float32Array 2 per vertex');
    check(metric.texture instanceof Float32Array && metric.texture.length === 2 * s.vertices, 'texture Float32Array 2 per vertex');
    check(metric.triangles instanceof Uint32Array && metric.triangles.length === 3 * s.triangles, 'triangles Uint32Array 3 per triangle');
    check(metric.image && metric.image.width === width && metric.image.pixels.length === pixels.length, 'rendered image has the input size');
    check(stages.length > 0 && stages.every(([st, f]) => typeof st === 'string' && f >= 0 && f <= 1), 'progress stages with fractions in [0,1]');
    // Reusing the calibrated height skips calibration and gives the same deformation.
    const again = vs.lens(image, [roi], { magnification: 2, grid: 24, height: s.height, render: false }, undefined);
    check(again.ok && again.image === null && again.stats.ms_calibration === 0, 'explicit height: no calibration, no image');
    check(again.ok && Math.abs(again.stats.magnification_center - s.magnification_center) < 1e-9, 'explicit height reproduces the magnification');
  }

  // LensSession: the same results as lens(), with the mesh and factorization reused across α.
  {
    const session = new vs.LensSession();
    const same = (a, b) => a.ok && b.ok && a.positions.length === b.positions.length &&
      a.positions.every((v, i) => v === b.positions[i]) && a.texture.every((v, i) => v === b.texture[i]) &&
      a.triangles.every((v, i) => v === b.triangles[i]) && a.stats.distortion_sum === b.stats.distortion_sum &&
      a.stats.iterations === b.stats.iterations && a.stats.height === b.stats.height;
    const calibrated = session.run(image, [roi], { magnification: 2, grid: 24, render: false }, undefined);
    check(same(calibrated, vs.lens(image, [roi], { magnification: 2, grid: 24, render: false }, undefined)),
          'LensSession.run equals lens() for a calibrated request');
    check(calibrated.ok && calibrated.session.calibrations === 1 && calibrated.session.mesh_builds >= 2, 'LensSession counts its calibration');
    const h = calibrated.ok ? calibrated.stats.height : 1;
    const first = session.run(image, [roi], { magnification: 2, grid: 24, height: h, alpha: 0, render: false }, null);
    const builds = first.ok ? first.session.mesh_builds : -1;
    for (const alpha of [0.5, 1]) {
      const live = session.run(image, [roi], { magnification: 2, grid: 24, height: h, alpha, render: false }, null);
      check(same(live, vs.lens(image, [roi], { magnification: 2, grid: 24, height: h, alpha, render: false }, null)),
            `LensSession α = ${alpha} equals lens()`);
      check(live.ok && live.session.mesh_builds === builds && live.stats.ms_factorize === 0, `LensSession α = ${alpha} reuses the factorization`);
    }
    const moved = session.run(image, [{ shape: 'circle', values: [30, 24, 10] }], { grid: 24, height: h, render: true }, null);
    check(moved.ok && moved.session.mesh_builds === builds + 1 && moved.image && moved.image.width === width, 'LensSession rebuilds for a moved ROI and renders');
    const wrong = session.run(image, [roi], { alpha: 3 }, null);
    check(wrong.ok === false && /alpha/.test(wrong.message), 'LensSession bad option: ' + JSON.stringify(wrong.message));
    const stopped = session.run(image, [roi], { grid: 24 }, () => false);
    check(stopped.ok === false && stopped.message === 'cancelled', 'LensSession run can be cancelled');
    const c = session.counters();
    check(c.runs === 5 && c.mesh_reuses >= 2, 'LensSession counters(): ' + JSON.stringify(c));
    session.clear();
    const cleared = session.run(image, [roi], { grid: 24, height: h, render: false }, null);
    check(cleared.ok && cleared.session.mesh_builds === c.mesh_builds + 1, 'LensSession.clear() drops the caches');
    session.delete();
  }

  // Live mode (dragging): a moved ROI is answered by translating the last solved lens; the full
  // request at the same place is then exactly lens() again.
  {
    const session = new vs.LensSession();
    const opts = { magnification: 2, grid: 24, height: 1.0, render: false };
    const base = session.run(image, ['circle:30,24,8'], { ...opts, mode: 'live' }, null);
    check(base.ok && base.stats.translated === false, 'live: the first request is solved in full: ' + base.message);
    const moved = session.run(image, ['circle:33,22,8'], { ...opts, mode: 'live' }, null);
    check(moved.ok && moved.stats.translated === true && moved.session.translation_reuses === 1 && moved.session.mesh_builds === base.session.mesh_builds,
          'live: a moved ROI is translated, nothing rebuilt');
    let offset = moved.ok && base.ok && moved.positions.length === base.positions.length;
    for (let i = 0; offset && i < base.positions.length; i += 2)
      offset = Math.abs(moved.positions[i] - base.positions[i] - 3) < 1e-4 && Math.abs(moved.positions[i + 1] - base.positions[i + 1] + 2) < 1e-4 &&
               Math.abs(moved.texture[i] - base.texture[i] - 3) < 1e-4 && Math.abs(moved.texture[i + 1] - base.texture[i + 1] + 2) < 1e-4;
    check(offset, 'live: positions and texture moved by the ROI offset (3, -2)');
    const full = session.run(image, ['circle:33,22,8'], opts, null);
    const fresh = vs.lens(image, ['circle:33,22,8'], opts, null);
    check(full.ok && fresh.ok && full.stats.translated === false && full.positions.length === fresh.positions.length &&
          full.positions.every((x, i) => x === fresh.positions[i]) && full.stats.distortion_sum === fresh.stats.distortion_sum,
          'live: the full request after the drag equals a fresh lens()');
    const resized = session.run(image, ['circle:33,22,9'], { ...opts, mode: 'live' }, null);
    check(resized.ok && resized.stats.translated === false, 'live: a resized ROI is solved in full');
    const badMode = session.run(image, ['circle:33,22,9'], { ...opts, mode: 'fast' }, null);
    check(badMode.ok === false && /mode/.test(badMode.message), 'unknown mode: ' + JSON.stringify(badMode.message));
    session.delete();
  }

  for (const method of ['fisheye', 'bifocal', 'zoom']) {
    const r = vs.lens(image, ['circle:32,24,10'], { method, magnification: 2, grid: 24, render: false }, null);
    check(r.ok && r.stats.iterations === 0 && r.stats.baseline_parameter > 1, method + ' baseline ok');
  }

  const cancelled = vs.lens(image, [roi], { grid: 24 }, () => false);
  check(cancelled.ok === false && cancelled.message === 'cancelled', 'progress returning false cancels');

  const bad = (args, pattern, what) => {
    let r;
    try { r = vs.lens(...[...args, undefined, undefined, undefined, undefined].slice(0, 4)); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(r && r.ok === false && pattern.test(r.message), what + ': message ' + JSON.stringify(r && r.message));
  };
  bad([image, [roi], { magnification: 0.5 }], /magnification/, 'magnification below 1');
  bad([image, [roi], { method: 'swirl' }], /method/, 'unknown method');
  bad([image, [roi], { grid: 'big' }], /grid/, 'grid not a number');
  bad([image, [roi], { grid: 2.5 }], /grid/, 'grid not an integer');
  bad([image, [], {}], /ROI/, 'no ROI');
  bad([image, [{ shape: 'circle', values: [32, 24] }], {}], /roi 0/, 'circle with two values');
  bad([image, [{ shape: 'circle', values: [500, 500, 10] }], {}], /roi 0/, 'circle outside the image');
  bad([image, ['ellipse:1,2,3'], {}], /ellipse/, 'unknown ROI text');
  bad([{ width, height, channels: 3, pixels: new Uint8Array(10) }, [roi], {}], /pixels/, 'pixels of the wrong size');
  bad([null, [roi], {}], /image/, 'no image');
  bad([image, [roi], {}, 42], /progress/, 'progress not a function');
  const notImage = vs.decodeImage(new TextEncoder().encode('not a png'), 'broken.png');
  check(notImage.ok === false && /broken\.png/.test(notImage.message), 'decodeImage of junk names the file');
  const after = vs.lens(image, ['circle:20,20,8'], { method: 'fisheye', grid: 16, render: false }, undefined);
  check(after.ok, 'lens still works after errors');
};
