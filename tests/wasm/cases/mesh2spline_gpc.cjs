// SPDX-License-Identifier: MIT
// mesh2spline on a solid of genus > 0: the bundled torus (genus 1) goes over its GPC domain (one
// cuboid glued to itself), with the CLI's GPC stats, the boundary tagged and coloured by cuboid,
// the cut by scaled Jacobian, the volspline-gpc-spline JSON (the native CLI's within rounding),
// GLB and VTU; splineCut and splineQuality on that JSON; progress and cancellation; {ok:false, message} for bad
// options and JSON.
'use strict';
const { execFileSync } = require('child_process');
const os = require('os');

module.exports = function (vs, { check, sourceDir, fs, path }) {
  const file = path.join(sourceDir, 'samples/meshes/torus.off');
  const torus = new Uint8Array(fs.readFileSync(file));
  const decode = (b) => new TextDecoder().decode(b);
  const text = (s) => new TextEncoder().encode(s);
  const view = { vtu_cells: 4, preview_samples: 5, preview_lines: 3, cut_samples: 9 };

  const stages = [];
  const r = vs.mesh2spline(torus, 'torus.off', view, (stage, fraction) => { stages.push([stage, fraction]); return true; });
  check(r.ok === true && r.domain === 'gpc', `mesh2spline(torus.off) runs over the GPC: ${r.message || r.domain}`);
  if (!r.ok) return;
  const s = r.stats;
  check(s.genus === 1 && s.cuboids === 1 && s.ill_points === 0 && s.t_shapes === 0 && s.interfaces === 1,
        `torus: genus ${s.genus}, ${s.cuboids} cuboid, ${s.ill_points} ill-points, ${s.t_shapes} T-shapes, ${s.interfaces} interface`);
  check(s.rms_rel > 0 && s.rms_rel <= 0.002, `torus rms_rel ${s.rms_rel} ≤ 0.002 (the target)`);
  check(s.hausdorff_rel > 0 && s.hausdorff_rel < 0.02, `torus hausdorff_rel ${s.hausdorff_rel} < 0.02`);
  check(s.semi_standard_max_error <= 1e-12, `torus semi_standard_max_error ${s.semi_standard_max_error} ≤ 1e-12`);
  check(s.min_scaled_jacobian > 0 && s.negative_jacobian_fraction === 0 && s.lattice_negative_fraction === 0,
        `torus: no folds (min scaled Jacobian ${s.min_scaled_jacobian}, lattice ${s.lattice_negative_fraction})`);
  check(s.control_points >= 64 && r.control_points.length === 3 * s.control_points, `torus: ${s.control_points} control points`);
  check(r.control_uvw.length === r.control_points.length && r.control_uvw.every((x) => x >= 0 && x <= 1), 'control_uvw: each anchor in its cuboid, [0, 1]');
  check(s.interface_gap_rel <= 1e-9 && s.continued_interfaces === 1, `the glued face is continued, gap ${s.interface_gap_rel}`);
  check(s.untangle_surface_shift_rel >= 0 && s.untangle_surface_shift_rel < 0.01,
        `the untangling moved the surface by ${s.untangle_surface_shift_rel} of the diagonal, under 1 %`);
  check(s.untangle_path === 'rounds' && s.certificate_passes >= 1 && s.local_certificate_passes <= s.certificate_passes,
        `the torus's certificate rounds alone certify (${s.untangle_path}, ${s.certificate_passes} passes, ${s.local_certificate_passes} local)`);
  check(s.input === 'torus.off' && s.fit === 'grid' && s.times_s.total > 0 && s.times_s.gpc > 0, 'stats: input, fit, times_s');
  const h = s.level_history;
  check(s.knot_refinement === 'hierarchical' && h.length === s.levels + 1 && h[h.length - 1].control_points === s.control_points &&
        Math.abs(h[h.length - 1].rms_rel - s.rms_rel) < 1e-15 && h.every((l) => l.surface_max_rel >= 0),
        `knot_refinement ${s.knot_refinement}, level_history of ${h.length} levels ending at the result`);
  check(stages.length > 2 && stages.every(([st, f]) => typeof st === 'string' && f >= 0 && f <= 1) &&
        stages.some(([st]) => /^fit level/.test(st)) && stages.some(([st]) => /^untangle: certificate round \d+: \d+ cells uncertified$/.test(st)),
        `progress reported (${stages.length} calls, fit levels and certificate rounds included)`);

  // The view: 4 surface faces of 5×5 points (the glued pair is inside), each point's cuboid and colour.
  const b = r.boundary, n = b.positions.length / 3;
  check(n === 4 * 25 && b.uvw.length === 3 * n && b.cuboid instanceof Uint32Array && b.cuboid.length === n && b.colours.length === 3 * n,
        `boundary: 4 faces of 5×5 points with uvw, cuboid and colour (${n} points)`);
  check(b.triangles.length === 4 * 16 * 6 && b.triangles.every((i) => i < n), 'boundary triangles');
  check(b.cuboid.every((c) => c === 0) && b.colours.every((c) => c >= 0.25 && c <= 0.95), 'every point in cuboid 0, colours in [0.25, 0.95]');
  check(r.lines.positions.length === 4 * 2 * 3 * 16 * 6 && r.lines.cuboid.length === 4 * 2 * 3 * 16, 'iso-lines: 4 faces × 2 directions × 3 lines × 16 segments');
  // The boundary lies near the torus of revolution (R 1, r 0.25): within the fit error.
  let worst = 0;
  for (let i = 0; i < b.positions.length; i += 3) {
    const [x, y, z] = [b.positions[i], b.positions[i + 1], b.positions[i + 2]];
    worst = Math.max(worst, Math.abs(Math.hypot(Math.hypot(x, y) - 1, z) - 0.25));
  }
  check(worst < 0.03, `boundary within 0.03 of the torus (worst ${worst.toFixed(4)})`);
  const c = r.cut;
  check(c.axis === 2 && c.position === 0.5 && c.positions.length === 81 * 3 && c.triangles.length === 64 * 6 &&
        c.scaled_jacobian.length === 81 && c.cuboid.length === 81, 'cut: 9×9 points in the one cuboid');
  check(Math.abs(c.min_scaled_jacobian - Math.min(...c.scaled_jacobian)) < 1e-7 && c.scaled_jacobian.every((q) => q >= -1 && q <= 1),
        `cut scaled Jacobian in [−1, 1], min ${c.min_scaled_jacobian}`);

  // Files: the GPC spline JSON (parses, one point per control point), GLB and VTU.
  const json = JSON.parse(decode(r.spline_json));
  check(json.format === 'volspline-gpc-spline' && json.domain.cuboids.length === 1 && json.points.length === s.control_points,
        'spline_json is the volspline-gpc-spline document');
  check(decode(r.glb.slice(0, 4)) === 'glTF', 'glb starts with glTF');
  const vtu = decode(r.vtu);
  check(/<VTKFile/.test(vtu) && /scaled_jacobian/.test(vtu) && /"cuboid"/.test(vtu), 'vtu: sampled hexes with cuboid and scaled_jacobian');

  // splineCut reads the GPC JSON and reproduces the run's cut.
  const again = vs.splineCut(r.spline_json, 2, 0.5, 9);
  check(again.ok && again.positions.every((x, i) => Math.abs(x - c.positions[i]) < 1e-5) && again.cuboid.length === 81,
        'splineCut(gpc json, 2, 0.5, 9) equals the run\'s cut');
  const u0 = vs.splineCut(r.spline_json, 0, 0, 5);
  check(u0.ok && u0.positions.length === 75 && u0.axis === 0, 'splineCut of the gpc json on u = 0');
  const badCut = vs.splineCut(text('{"format": "volspline-gpc-spline", "version": 1}'), 2, 0.5, 9);
  check(badCut.ok === false && /spline JSON/.test(badCut.message), `a broken gpc JSON: ${JSON.stringify(badCut.message)}`);

  // splineQuality on the GPC JSON: the lattice of every cuboid, the boundary's distance to the mesh
  // at the points of the run's boundary preview.
  const q = vs.splineQuality(r.spline_json, torus, 'torus.off', { lattice: 6, bins: 10, preview_samples: 5, preview_lines: 3 });
  check(q.ok && q.samples === 216 * s.cuboids && q.cuboids === s.cuboids && q.counts.reduce((a, x) => a + x, 0) === q.samples,
        `splineQuality(gpc json): ${q.ok ? `${q.samples} lattice points in ${q.cuboids} cuboid(s), binned` : q.message}`);
  check(q.ok && q.min_scaled_jacobian > 0 && q.folded.length === 0 && q.counts.slice(0, 5).every((c) => c === 0),
        `torus lattice: none folded, min scaled Jacobian ${q.min_scaled_jacobian}`);
  check(q.ok && q.boundary_distance_rel.length === n && q.max_distance_rel > 0 && q.max_distance_rel < 0.02,
        `boundary distance per preview point, max ${q.max_distance_rel} (hausdorff_rel ${s.hausdorff_rel})`);

  // The native CLI writes the same spline at level 0: same domain and intervals, points within
  // 1e-4 of the diagonal (the builds round differently; the fits are iterative). Level 0 only:
  // whether a level meets max_rms_rel, or which knots the misfit marks, may differ by rounding.
  const native = process.env.VOLSPLINE_NATIVE || path.join(sourceDir, 'build/release/cli/volspline');
  if (fs.existsSync(native)) {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'volspline-gpc-spline-'));
    try {
      execFileSync(native, ['mesh2spline', file, '-o', path.join(dir, 't.json'), '--max-levels', '0', '--quiet']);
      const a = JSON.parse(fs.readFileSync(path.join(dir, 't.json'), 'utf8'));
      const level0 = vs.mesh2spline(torus, 'torus.off', { ...view, max_levels: 0 }, null);
      const json = JSON.parse(decode(level0.spline_json));
      const same = JSON.stringify(a.intervals) === JSON.stringify(json.intervals) && a.points.length === json.points.length;
      let far = 0;
      if (same) a.points.forEach((p, i) => p.forEach((x, k) => { far = Math.max(far, Math.abs(x - json.points[i][k])); }));
      check(same && far <= 1e-4 * Math.hypot(2.5, 2.5, 0.5), `native and WebAssembly GPC splines agree (intervals, points within ${far.toExponential(1)})`);
    } finally {
      fs.rmSync(dir, { recursive: true, force: true });
    }
  }

  // The volumetric map (most of the GPC's time) reports its phases, so a cancel there is heard.
  const phases = stages.map(([st]) => st);
  check(['surface map', 'grid untangling', 'padding'].every((p) => phases.includes(p)) && stages.every(([, f], i) => i === 0 || f >= stages[i - 1][1]),
        `the volumetric map reports its phases, fractions increasing: ${JSON.stringify([...new Set(phases)])}`);

  // Cancellation through the progress callback, and the module keeps working.
  let calls = 0;
  const cancelled = vs.mesh2spline(torus, 'torus.off', view, () => ++calls < 3);
  check(cancelled.ok === false && cancelled.message === 'cancelled', 'progress returning false cancels the GPC run: ' + cancelled.message);
  let seen = [];
  const inMap = vs.mesh2spline(torus, 'torus.off', view, (stage) => { seen.push(stage); return stage !== 'grid untangling'; });
  check(inMap.ok === false && inMap.message === 'cancelled' && seen[seen.length - 1] === 'grid untangling',
        `a cancel inside the volumetric map stops there: ${inMap.message} after ${JSON.stringify(seen.slice(-2))}`);
  const bad = (options, pattern, what) => {
    let x;
    try { x = vs.mesh2spline(torus, 'torus.off', options, null); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(x && x.ok === false && typeof x.message === 'string' && pattern.test(x.message), `${what}: ${JSON.stringify(x && x.message)}`);
  };
  bad({ fit: 'meshless' }, /meshless/, 'meshless on genus 1');
  bad({ max_levels: -1 }, /max_levels|levels/, 'max_levels -1 on genus 1');
  bad({ max_rms_rel: 0 }, /rms/, 'max_rms_rel 0 on genus 1');
  bad({ gpc_grid_nodes: 10 }, /nodes/, 'gpc_grid_nodes 10');
  bad({ padding: 'no' }, /padding/, 'padding not a boolean');
  bad({ adaptive_knots: true, adaptive_growth: 0.5 }, /adaptive_growth/, 'adaptive_growth 0.5');
  bad({ measure_lattice: 2 }, /measure_lattice/, 'measure_lattice 2');
  bad({ surface_weight: -1 }, /surface_weight/, 'surface_weight -1');
  const adaptive = vs.mesh2spline(torus, 'torus.off', { ...view, outputs: false, adaptive_knots: true, max_surface_error_rel: 0.004, measure_lattice: 8 }, null);
  check(adaptive.ok && adaptive.stats.knot_refinement === 'adaptive' && adaptive.stats.lattice_samples === 512 * adaptive.stats.cuboids,
        `adaptive knots, a surface target and an 8³ measure lattice reach the job (${adaptive.message || adaptive.stats.control_points + ' control points'})`);
  // A torus of 4×3 quads: the construction may fail (its surface maps fold); then the message says
  // so, as the CLI's exit 1, never as an internal error.
  const ring = (nu, nv) => {
    let off = `OFF\n${nu * nv} ${2 * nu * nv} 0\n`;
    for (let i = 0; i < nu; i++)
      for (let j = 0; j < nv; j++) {
        const u = (2 * Math.PI * i) / nu, v = (2 * Math.PI * j) / nv;
        off += `${(1 + 0.3 * Math.cos(v)) * Math.cos(u)} ${(1 + 0.3 * Math.cos(v)) * Math.sin(u)} ${0.3 * Math.sin(v)}\n`;
      }
    const id = (i, j) => (i % nu) * nv + (j % nv);
    for (let i = 0; i < nu; i++)
      for (let j = 0; j < nv; j++) off += `3 ${id(i, j)} ${id(i + 1, j)} ${id(i + 1, j + 1)}\n3 ${id(i, j)} ${id(i + 1, j + 1)} ${id(i, j + 1)}\n`;
    return text(off);
  };
  const coarse = vs.mesh2spline(ring(4, 3), 'ring.off', { outputs: false }, null);
  check(coarse.ok === true || (/^mesh2spline failed: /.test(coarse.message) && /ring\.off|cuboid/.test(coarse.message)),
        `a 4×3 torus: ${coarse.ok ? 'converted' : JSON.stringify(coarse.message)}`);
  const small = vs.mesh2spline(torus, 'torus.off', { ...view, outputs: false, max_levels: 0 }, null);
  check(small.ok && small.stats.levels === 0 && small.spline_json === undefined, `after errors a level-0 run works, no files (${small.message || small.stats.control_points})`);
};
