// SPDX-License-Identifier: MIT
// The protocol the per-job WASM/native benchmarks share: parse `NODE_BUILD.cjs VOLSPLINE_CLI
// MESH... [--runs N]`, then for each mesh RUNS times and alternating (so both sides see the same
// machine load) the native CLI (wall and user+sys CPU of the process from /usr/bin/time, its
// --stats-json) and the node build in this process (wall and process CPU of the call, its stats),
// and print as JSON the medians, the ratios, the core's own times_s.total on both sides and the
// stats keys whose values differ (all but times_s and input must agree).
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');
const { execFileSync } = require('child_process');

const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];

// spec: script (file name for the usage line), tmpPrefix, cliArgs(mesh, stats, tmp) (the CLI's
// words after the binary, writing its stats to `stats` and other outputs into `tmp`), run(vs, bytes, name) (the node call; returns {ok, stats}),
// warmup(vs, bytes, name) (optional untimed call first), summary(stats) (extra fields per mesh,
// from the native stats).
function benchAgainstNative(spec) {
  const args = process.argv.slice(2);
  const runsAt = args.indexOf('--runs');
  const runs = runsAt >= 0 ? Number(args.splice(runsAt, 2)[1]) : 3;
  const [modulePath, cli, ...meshes] = args;
  if (!modulePath || !cli || !meshes.length) {
    console.error(`usage: node --no-experimental-fetch tests/wasm/${spec.script} NODE_BUILD.cjs VOLSPLINE_CLI MESH... [--runs 3]`);
    process.exit(2);
  }
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), spec.tmpPrefix));

  function native(mesh) {
    const stats = path.join(tmp, 'stats.json'), time = path.join(tmp, 'time.txt');
    execFileSync('/usr/bin/time', ['-o', time, '-f', '%e %U %S', cli, ...spec.cliArgs(mesh, stats, tmp)]);
    const [wall, user, sys] = fs.readFileSync(time, 'utf8').trim().split(/\s+/).map(Number);
    return { wall_s: wall, cpu_s: user + sys, stats: JSON.parse(fs.readFileSync(stats, 'utf8')) };
  }

  require(path.resolve(modulePath))().then((vs) => {
    const out = { load_before: fs.readFileSync('/proc/loadavg', 'utf8').trim(), runs, meshes: {} };
    for (const mesh of meshes) {
      const bytes = new Uint8Array(fs.readFileSync(mesh));
      const n = [], w = [];
      if (spec.warmup) spec.warmup(vs, bytes, path.basename(mesh));
      for (let k = 0; k < runs; k++) {
        n.push(native(mesh));
        const t0 = performance.now(), c0 = process.cpuUsage();
        const r = spec.run(vs, bytes, path.basename(mesh));
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
      out.meshes[path.basename(mesh)] = {
        native: nat, wasm,
        ratio_wasm_over_native: { wall: wasm.wall_s / nat.wall_s, cpu: wasm.cpu_s / nat.cpu_s, core_total: wasm.core_total_s / nat.core_total_s },
        ...spec.summary(n[0].stats), stats_differ: differ,
      };
    }
    out.load_after = fs.readFileSync('/proc/loadavg', 'utf8').trim();
    fs.rmSync(tmp, { recursive: true, force: true });
    console.log(JSON.stringify(out, null, 2));
  }).catch((e) => { console.error('bench failed: ' + e.message); process.exit(1); });
}

module.exports = { benchAgainstNative, median };
