// SPDX-License-Identifier: MIT
// gpc(bytes, name, options, progress): the GPC domain of the shared torus (genus 1: one tube
// closed on itself, 1 cuboid, no ill-points) and of the bundled sphere (genus 0: 1 cuboid), view
// arrays of consistent sizes, DOMAIN.json and the segmented GLB as bytes (the same DOMAIN.json as
// the native CLI's within rounding), progress and cancellation, and {ok:false, message} for bad
// meshes and options (never an exception).
'use strict';
const { execFileSync } = require('child_process');
const os = require('os');

module.exports = function (vs, { check, dataDir, sourceDir, fs, path }) {
  const decode = (b) => new TextDecoder().decode(b);
  const text = (s) => new TextEncoder().encode(s);
  const torusFile = path.join(dataDir, 'meshes/torus.off');
  const torus = new Uint8Array(fs.readFileSync(torusFile));

  const stages = [];
  const r = vs.gpc(torus, 'torus.off', {}, (stage, fraction) => { stages.push([stage, fraction]); return true; });
  check(r.ok === true, 'gpc(torus.off) ok: ' + r.message);
  if (r.ok) {
    const s = r.stats;
    check(s.genus === 1 && s.cuboids === 1 && s.ill_points === 0, `torus: genus ${s.genus}, cuboids ${s.cuboids}, ill_points ${s.ill_points}`);
    check(s.tubes === 1 && s.t_shapes === 0 && s.caps === 0 && s.interfaces === 1, `torus: ${s.tubes} tube, ${s.t_shapes} T-shapes, ${s.caps} caps, ${s.interfaces} interface`);
    check(s.flipped_triangles === 0 && s.grid_inverted_hexes === 0 && s.grid_min_scaled_jacobian > 0,
          `torus: flipped_triangles ${s.flipped_triangles}, grid_inverted_hexes ${s.grid_inverted_hexes}, grid_min_scaled_jacobian ${s.grid_min_scaled_jacobian}`);
    check(s.cut_disc_intersections === 0 && s.cut_discs_outside === 0, 'torus: the cut disc is a meridian');
    check(s.input === 'torus.off' && s.times_s.total > 0 && s.times_s.volumetric_map >= 0, 'stats: input and times_s');
    check(stages.length > 0 && stages.every(([st, f]) => typeof st === 'string' && f >= 0 && f <= 1), `progress reported (${stages.length} calls)`);

    const nf = r.surface.face_cuboid.length;
    check(r.surface.positions instanceof Float32Array && r.surface.colours instanceof Float32Array && r.surface.face_cuboid instanceof Uint32Array,
          'surface arrays are typed');
    check(nf > 100 && r.surface.positions.length === 9 * nf && r.surface.colours.length === 9 * nf, `surface: 3 points per triangle (${nf} triangles)`);
    check(r.surface.face_cuboid.every((c) => c < s.cuboids), 'face_cuboid names a cuboid');
    check(r.surface.colours.every((c) => c >= 0.25 && c <= 0.95), 'colours in [0.25, 0.95]');
    check(r.poly_edges instanceof Float32Array && r.poly_edges.length > 0 && r.poly_edges.length % 6 === 0, 'poly_edges: segments of 2 points');
    check(r.corners instanceof Float32Array && r.corners.length === 24 * s.cuboids, '8 corners per cuboid');
    const inBox = (p) => { for (let i = 0; i < p.length; i++) if (p[i] < r.bbox_min[i % 3] - 1e-6 || p[i] > r.bbox_max[i % 3] + 1e-6) return false; return true; };
    check(inBox(r.surface.positions) && inBox(r.poly_edges) && inBox(r.corners), 'every view point lies in bbox_min..bbox_max');
    // The refined surface keeps every input vertex and adds points on input edges: same box.
    const info = vs.meshInfo(torus, 'torus.off');
    const d = [0, 1, 2].map((k) => Math.max(Math.abs(r.bbox_min[k] - info.bbox_min[k]), Math.abs(r.bbox_max[k] - info.bbox_max[k])));
    check(info.ok && Math.max(...d) < 1e-6, `the view's bounding box is the input's (within ${Math.max(...d).toExponential(1)})`);

    const domain = JSON.parse(decode(r.domain_json));
    check(domain.format === 'volspline-gpc' && domain.genus === 1 && domain.cuboids.length === 1 && domain.ill_points.length === 0,
          'domain_json is the volspline-gpc document of 1 cuboid');
    check(decode(r.glb.slice(0, 4)) === 'glTF' && new DataView(r.glb.buffer, r.glb.byteOffset).getUint32(8, true) === r.glb.length,
          `glb is a GLB of its own length (${r.glb.length} bytes)`);

    // The native CLI writes the same domain: same structure, numbers within rounding (the two
    // builds round differently, the grid solve is iterative).
    const native = process.env.VOLSPLINE_NATIVE || path.join(sourceDir, 'build/release/cli/volspline');
    if (fs.existsSync(native)) {
      const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'volspline-gpc-'));
      execFileSync(native, ['gpc', torusFile, '-o', path.join(dir, 'd.json'), '--quiet']);
      const a = JSON.parse(fs.readFileSync(path.join(dir, 'd.json'), 'utf8'));
      let worst = 0, sameShape = true;
      const walk = (x, y) => {
        if (typeof x === 'number' && typeof y === 'number') worst = Math.max(worst, Math.abs(x - y));
        else if (x && y && typeof x === 'object' && typeof y === 'object' && Object.keys(x).length === Object.keys(y).length) for (const k of Object.keys(x)) walk(x[k], y[k]);
        else if (x !== y) sameShape = false;
      };
      walk(a, domain);
      check(sameShape && worst < 1e-6, `native and WebAssembly DOMAIN.json agree (largest difference ${worst.toExponential(2)})`);
      fs.rmSync(dir, { recursive: true, force: true });
    }
  }

  // Genus 0: one cuboid; without outputs no files.
  const sphere = vs.gpc(new Uint8Array(fs.readFileSync(path.join(sourceDir, 'samples/meshes/sphere.off'))), 'sphere.off', { outputs: false, grid_nodes: 2000 }, null);
  check(sphere.ok && sphere.stats.genus === 0 && sphere.stats.cuboids === 1 && sphere.stats.ill_points === 0, `sphere: genus 0, 1 cuboid (${sphere.message || ''})`);
  check(sphere.ok && sphere.domain_json === undefined && sphere.glb === undefined, 'outputs: false omits the files');
  check(sphere.ok && sphere.stats.grid_nodes <= 4000, `grid_nodes reaches the job (${sphere.ok && sphere.stats.grid_nodes} nodes)`);

  // Cancellation through the progress callback.
  let calls = 0;
  const cancelled = vs.gpc(torus, 'torus.off', {}, () => ++calls < 2);
  check(cancelled.ok === false && cancelled.message === 'cancelled', 'progress returning false cancels: ' + cancelled.message);

  // Errors: {ok:false, message} naming the problem; the module keeps working.
  const bad = (args, pattern, what) => {
    let x;
    try { x = vs.gpc(...args); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(x && x.ok === false && typeof x.message === 'string' && pattern.test(x.message), `${what}: ${JSON.stringify(x && x.message)}`);
  };
  bad([text('OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n'), 'open.off', {}, null], /open\.off/, 'open mesh');
  bad([text('OFF\n4 2 0\n0 0 0\n1 0 0\n'), 'broken.off', {}, null], /broken\.off/, 'truncated OFF');
  bad([torus, 'torus.off', { corners: [1, 2, 3, 4, 5, 6, 7, 8] }, null], /genus-0/, 'corners on a genus-1 solid');
  bad([torus, 'torus.off', { grid_nodes: 10 }, null], /target_nodes/, 'grid_nodes 10');
  bad([torus, 'torus.off', { untangle: 'yes' }, null], /untangle/, 'untangle not a boolean');
  bad([torus, 'torus.off', { snap: 0.5 }, null], /snap/, 'snap 0.5');
  bad([torus, 'torus.off', { merge_cuboids: 1 }, null], /merge_cuboids/, 'merge_cuboids not a boolean');
  bad([torus, 'torus.off', { limb_persistence: 1 }, null], /limb_persistence/, 'limb_persistence 1');
  bad([torus, 'torus.off', { threads: 0 }, null], /threads/, 'threads 0');
  bad([torus, 'torus.off', {}, 42], /progress/, 'progress not a function');
  bad(['nope', 'torus.off', {}, null], /Uint8Array/, 'bytes not an array');
  const again = vs.gpc(torus, 'torus.off', { outputs: false }, null);
  check(again.ok && again.stats.cuboids === 1, 'gpc still works after errors');
};
