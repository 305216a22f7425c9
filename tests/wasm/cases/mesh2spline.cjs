// SPDX-License-Identifier: MIT
// mesh2spline(bytes, name, options, progress) and splineCut(json, axis, position, samples): a
// small sphere fit with sane measures and view arrays of consistent sizes, the CLI's output
// formats as bytes, progress and cancellation through the callback, and {ok:false, message} for
// bad meshes and options (never an exception).
'use strict';
module.exports = function (vs, { check, sourceDir, fs, path }) {
  const sample = (name) => new Uint8Array(fs.readFileSync(path.join(sourceDir, 'samples/meshes', name)));
  const text = (s) => new TextEncoder().encode(s);
  const decode = (b) => new TextDecoder().decode(b);
  const small = { max_levels: 1, measure_samples: 16, vtu_cells: 4, preview_samples: 5, preview_lines: 3, cut_samples: 9 };

  const stages = [];
  const r = vs.mesh2spline(sample('sphere.off'), 'sphere.off', small, (stage, fraction) => { stages.push([stage, fraction]); return true; });
  check(r.ok === true, 'mesh2spline(sphere.off) ok: ' + r.message);
  if (r.ok) {
    const s = r.stats;
    check(s.rms_rel > 0 && s.rms_rel < 0.01, `sphere rms_rel ${s.rms_rel} in (0, 0.01)`);
    check(s.hausdorff_rel >= 0 && s.hausdorff_rel < 0.05, `sphere hausdorff_rel ${s.hausdorff_rel} < 0.05`);
    check(s.control_points >= 64 && s.levels <= 1 && s.cuboids === 1, `sphere control_points ${s.control_points}, levels ${s.levels}`);
    check(s.min_scaled_jacobian > 0 && s.negative_jacobian_fraction === 0, `sphere min_scaled_jacobian ${s.min_scaled_jacobian} > 0`);
    check(s.semi_standard_max_error < 1e-9, `sphere semi_standard_max_error ${s.semi_standard_max_error}`);
    check(s.flipped_triangles === 0 && s.corners.length === 8 && s.input === 'sphere.off' && s.fit === 'grid', 'sphere facts');
    check(s.times_s && s.times_s.total > 0, 'stats.times_s.total > 0');
    check(stages.length > 0 && stages.every(([st, f]) => typeof st === 'string' && f >= 0 && f <= 1), `progress reported (${stages.length} calls)`);

    const nv = r.input.positions.length / 3;
    check(r.input.positions instanceof Float32Array && r.input.triangles instanceof Uint32Array && nv > 100, 'input arrays');
    check(Array.from(r.input.triangles).every((i) => i < nv), 'input triangle ids in range');
    check(r.boundary.positions.length === 6 * 25 * 3 && r.boundary.uvw.length === r.boundary.positions.length, 'boundary: 6 faces of 5×5 points with uvw');
    check(r.boundary.triangles.length === 6 * 16 * 2 * 3 && Array.from(r.boundary.triangles).every((i) => i < 150), 'boundary triangles');
    check(r.lines.positions.length === 6 * 2 * 3 * 16 * 6 && r.lines.uvw.length === r.lines.positions.length, 'iso-lines: 6 faces × 2 directions × 3 lines × 16 segments');
    check(Array.from(r.boundary.uvw).every((x) => x >= 0 && x <= 1), 'boundary uvw in [0, 1]');
    check(r.control_points.length === 3 * s.control_points, 'one control point per function');
    // The boundary lies near the unit sphere (the sample's radius); allow the fit error.
    let worst = 0;
    for (let i = 0; i < r.boundary.positions.length; i += 3) {
      const p = r.boundary.positions;
      worst = Math.max(worst, Math.abs(Math.hypot(p[i], p[i + 1], p[i + 2]) - 1));
    }
    const radius = Math.max(...Array.from(r.input.positions).map(Math.abs));
    check(Math.abs(radius - 1) > 0.05 || worst < 0.05, `boundary within 0.05 of the unit sphere (worst ${worst.toFixed(4)})`);
    check(r.cut.axis === 2 && r.cut.position === 0.5 && r.cut.positions.length === 81 * 3 && r.cut.triangles.length === 64 * 6, 'cut of 9×9 points at w = 0.5');
    check(r.cut.scaled_jacobian.length === 81 && Array.from(r.cut.scaled_jacobian).every((q) => q > 0 && q <= 1), 'cut scaled Jacobian in (0, 1]');
    check(Math.abs(r.cut.min_scaled_jacobian - Math.min(...r.cut.scaled_jacobian)) < 1e-7, 'cut min_scaled_jacobian');

    // Outputs: the same formats the CLI writes.
    check(/"volspline-tspline"/.test(decode(r.spline_json)), 'spline_json is a volspline-tspline document');
    check(decode(r.glb.slice(0, 4)) === 'glTF', 'glb starts with glTF');
    const vtu = decode(r.vtu);
    check(/<VTKFile/.test(vtu) && /scaled_jacobian/.test(vtu) && /NumberOfCells="64"/.test(vtu), 'vtu: 4×4×4 hexes with scaled_jacobian');

    // splineCut from the JSON reproduces the run's cut, and takes other axes.
    const c = vs.splineCut(r.spline_json, 2, 0.5, 9);
    check(c.ok && c.positions.length === r.cut.positions.length && c.positions.every((x, i) => Math.abs(x - r.cut.positions[i]) < 1e-6),
          'splineCut(json, 2, 0.5, 9) equals the run\'s cut');
    const cu = vs.splineCut(r.spline_json, 0, 0, 5);
    check(cu.ok && cu.positions.length === 75 && cu.axis === 0, 'splineCut on the u = 0 face');
    const badCut = (args, pattern, what) => {
      let x;
      try { x = vs.splineCut(...args); } catch (e) { check(false, what + ': threw ' + e); return; }
      check(x.ok === false && pattern.test(x.message), `${what}: ${JSON.stringify(x.message)}`);
    };
    badCut([r.spline_json, 3, 0.5, 9], /axis/, 'cut axis 3');
    badCut([r.spline_json, 0, 1.5, 9], /position/, 'cut position 1.5');
    badCut([text('{"format": "nope"}'), 0, 0.5, 9], /spline JSON/, 'cut of a bad JSON');
  }

  // No outputs when not asked; fewer levels give fewer control points (level 0 only).
  const r0 = vs.mesh2spline(sample('sphere.off'), 'sphere.off', { ...small, max_levels: 0, outputs: false }, null);
  check(r0.ok && r0.spline_json === undefined && r0.glb === undefined && r0.vtu === undefined, 'outputs: false omits the files');
  check(r0.ok && r.ok && r0.stats.levels === 0 && r0.stats.control_points <= r.stats.control_points, 'max_levels 0 gives level 0 only');

  // Cancellation through the progress callback.
  let calls = 0;
  const cancelled = vs.mesh2spline(sample('sphere.off'), 'sphere.off', small, () => ++calls < 3);
  check(cancelled.ok === false && cancelled.message === 'cancelled', 'progress returning false cancels: ' + cancelled.message);

  // Errors: {ok:false, message} naming the problem; the module keeps working.
  const bad = (args, pattern, what) => {
    let x;
    try { x = vs.mesh2spline(...args); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(x && x.ok === false && typeof x.message === 'string' && pattern.test(x.message), `${what}: ${JSON.stringify(x && x.message)}`);
  };
  // A solid of genus > 0 runs over its GPC domain: mesh2spline_gpc.cjs.
  bad([text('OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n'), 'open.off', small, null], /open\.off/, 'open mesh');
  bad([text('OFF\n4 2 0\n0 0 0\n1 0 0\n'), 'broken.off', small, null], /broken\.off/, 'truncated OFF');
  bad([sample('sphere.off'), 'sphere.off', { fit: 'magic' }, null], /fit/, 'unknown fit');
  bad([sample('sphere.off'), 'sphere.off', { max_levels: 'two' }, null], /max_levels/, 'max_levels not a number');
  bad([sample('sphere.off'), 'sphere.off', { max_levels: 99 }, null], /max_levels|levels/, 'max_levels out of range');
  bad([sample('sphere.off'), 'sphere.off', { corners: [1, 2, 3] }, null], /corner/, '3 corners');
  bad([sample('sphere.off'), 'sphere.off', { cut_axis: 5 }, null], /cut_axis/, 'cut_axis 5');
  bad([sample('sphere.off'), 'sphere.off', small, 42], /progress/, 'progress not a function');
  bad(['nope', 'sphere.off', small, null], /Uint8Array/, 'bytes not an array');
  // Every job option of Mesh2SplineOptions is a key: out-of-range values name the key.
  bad([sample('sphere.off'), 'sphere.off', { max_surface_error_rel: 0 }, null], /max_surface_error_rel/, 'max_surface_error_rel 0');
  bad([sample('sphere.off'), 'sphere.off', { max_surface_error_rel: 'tiny' }, null], /max_surface_error_rel/, 'max_surface_error_rel not a number');
  bad([sample('sphere.off'), 'sphere.off', { area_balance_iterations: 21 }, null], /area_balance_iterations/, 'area_balance_iterations 21');
  bad([sample('sphere.off'), 'sphere.off', { area_balance_iterations: 1.5 }, null], /area_balance_iterations/, 'area_balance_iterations not an integer');
  bad([sample('sphere.off'), 'sphere.off', { min_scaled_jacobian: 0.6 }, null], /min_scaled_jacobian/, 'min_scaled_jacobian 0.6');
  bad([sample('sphere.off'), 'sphere.off', { min_scaled_jacobian: -0.1 }, null], /min_scaled_jacobian/, 'min_scaled_jacobian -0.1');
  bad([sample('sphere.off'), 'sphere.off', { threads: 0 }, null], /threads/, 'threads 0');
  bad([sample('sphere.off'), 'sphere.off', { compare_uniform: 'yes' }, null], /compare_uniform/, 'compare_uniform not a boolean');
  bad([sample('sphere.off'), 'sphere.off', { max_control_points: 10 }, null], /max_control_points|max-control-points|control points/, 'max_control_points 10');
  bad([sample('sphere.off'), 'sphere.off', { max_rms_rel: -1 }, null], /max-rms|rms/, 'max_rms_rel -1');
  check(r.ok && r.stats.uniform_control_points === null && r.stats.repaired_control_points === 0 &&
        r.stats.negative_jacobian_fraction_fit === r.stats.negative_jacobian_fraction,
        'without compare_uniform or repair: uniform_control_points null, nothing repaired');
  // Loose targets stop at level 0; the keys reach the job (a stricter surface error would refine).
  const loose = { ...small, max_levels: 2, outputs: false, max_rms_rel: 1, max_surface_error_rel: 1, area_balance_iterations: 0,
                  threads: 2, min_scaled_jacobian: 0.05, compare_uniform: true };
  const rl = vs.mesh2spline(sample('sphere.off'), 'sphere.off', loose, null);
  check(rl.ok && rl.stats.levels === 0, `loose max_rms_rel and max_surface_error_rel stop at level 0: ${rl.message || rl.stats.levels}`);
  check(rl.ok && (rl.stats.uniform_control_points === null || rl.stats.uniform_control_points >= 64) && rl.stats.uniform_rms_rel >= 0,
        `compare_uniform reports the uniform fit (${rl.ok && rl.stats.uniform_control_points}, ${rl.ok && rl.stats.uniform_rms_rel})`);
  check(rl.ok && rl.stats.repaired_control_points >= 0 && rl.stats.min_scaled_jacobian > 0, `Jacobian repair target accepted (repaired ${rl.ok && rl.stats.repaired_control_points})`);
  const strict = vs.mesh2spline(sample('sphere.off'), 'sphere.off', { ...loose, compare_uniform: false, min_scaled_jacobian: 0, max_surface_error_rel: 1e-4 }, null);
  check(strict.ok && strict.stats.levels >= 1, `a strict max_surface_error_rel refines past level 0 (levels ${strict.ok && strict.stats.levels})`);
  const again = vs.mesh2spline(sample('sphere.off'), 'sphere.off', { ...small, max_levels: 0, outputs: false }, null);
  check(again.ok, 'mesh2spline still works after errors');
};
