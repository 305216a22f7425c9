// SPDX-License-Identifier: MIT
// WASM/native time ratio of the gpc job with default options. For each mesh, RUNS times and
// alternating (so both sides see the same machine load): the native CLI (`volspline gpc MESH -o …
// --glb … --stats-json … --quiet`, wall and user+sys CPU of the process from /usr/bin/time) and
// the node build in this process (gpc with default options, so DOMAIN.json, the segmented GLB and
// the view arrays are made as the CLI makes its files: wall and process CPU of the call). Also
// compares the core's own times_s.total (the job without reading, writing or serializing). One
// untimed node run per mesh first: the engine compiles the hot wasm functions optimized on first
// use, which on a small mesh (torus.off) takes several times the job itself.
// Prints medians, the ratios and the stats keys whose values differ between the two as JSON.
// usage: node --no-experimental-fetch tests/wasm/bench_gpc_wasm.cjs NODE_BUILD.cjs VOLSPLINE_CLI MESH... [--runs 3]
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');
const { execFileSync } = require('child_process');

const args = process.argv.slice(2);
const runsAt = args.indexOf('--runs');
const runs = runsAt >= 0 ? Number(args.splice(runsAt, 2)[1]) : 3;
const [modulePath, cli, ...meshes] = args;
if (!modulePath || !cli || !meshes.length) {
  console.error('usage: node --no-experimental-fetch tests/wasm/bench_gpc_wasm.cjs NODE_BUILD.cjs VOLSPLINE_CLI MESH... [--runs 3]');
  process.exit(2);
}
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'bench-gpc-'));

function native(mesh) {
  const out = path.join(tmp, 'domain.json'), glb = path.join(tmp, 'seg.glb'), stats = path.join(tmp, 'stats.json'), time = path.join(tmp, 'time.txt');
  execFileSync('/usr/bin/time', ['-o', time, '-f', '%e %U %S', cli, 'gpc', mesh, '-o', out, '--glb', glb, '--stats-json', stats, '--quiet']);
  const [wall, user, sys] = fs.readFileSync(time, 'utf8').trim().split(/\s+/).map(Number);
  return { wall_s: wall, cpu_s: user + sys, stats: JSON.parse(fs.readFileSync(stats, 'utf8')) };
}

require(path.resolve(modulePath))().then((vs) => {
  const out = { load_before: fs.readFileSync('/proc/loadavg', 'utf8').trim(), runs, meshes: {} };
  for (const mesh of meshes) {
    const bytes = new Uint8Array(fs.readFileSync(mesh));
    const n = [], w = [];
    vs.gpc(bytes, path.basename(mesh), { outputs: false }, null);
    for (let k = 0; k < runs; k++) {
      n.push(native(mesh));
      const t0 = performance.now(), c0 = process.cpuUsage();
      const r = vs.gpc(bytes, path.basename(mesh), {}, null);
      const c = process.cpuUsage(c0);
      if (!r.ok) throw new Error(`${mesh}: ${r.message}`);
      w.push({ wall_s: (performance.now() - t0) / 1000, cpu_s: (c.user + c.system) / 1e6, stats: r.stats });
    }
    const m = (side, f) => median(side.map(f));
    const side = (s) => ({ wall_s: m(s, (x) => x.wall_s), cpu_s: m(s, (x) => x.cpu_s), core_total_s: m(s, (x) => x.stats.times_s.total) });
    const nat = side(n), wasm = side(w);
    const differ = [];
    for (const [key, value] of Object.entries(n[0].stats)) {
      if (key === 'times_s' || key === 'input') continue;
      if (JSON.stringify(value) !== JSON.stringify(w[0].stats[key])) differ.push({ key, native: value, wasm: w[0].stats[key] });
    }
    const s = n[0].stats;
    out.meshes[path.basename(mesh)] = {
      native: nat, wasm,
      ratio_wasm_over_native: { wall: wasm.wall_s / nat.wall_s, cpu: wasm.cpu_s / nat.cpu_s, core_total: wasm.core_total_s / nat.core_total_s },
      genus: s.genus, cuboids: s.cuboids, grid_nodes: s.grid_nodes, stats_differ: differ,
    };
  }
  out.load_after = fs.readFileSync('/proc/loadavg', 'utf8').trim();
  fs.rmSync(tmp, { recursive: true, force: true });
  console.log(JSON.stringify(out, null, 2));
}).catch((e) => { console.error('bench failed: ' + e.message); process.exit(1); });
