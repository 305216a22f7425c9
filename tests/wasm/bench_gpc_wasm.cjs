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
const path = require('path');
const { benchAgainstNative } = require('./bench_against_native.cjs');

benchAgainstNative({
  script: 'bench_gpc_wasm.cjs',
  tmpPrefix: 'bench-gpc-',
  cliArgs: (mesh, stats, tmp) =>
    ['gpc', mesh, '-o', path.join(tmp, 'domain.json'), '--glb', path.join(tmp, 'seg.glb'), '--stats-json', stats, '--quiet'],
  warmup: (vs, bytes, name) => vs.gpc(bytes, name, { outputs: false }, null),
  run: (vs, bytes, name) => vs.gpc(bytes, name, {}, null),
  summary: (s) => ({ genus: s.genus, cuboids: s.cuboids, grid_nodes: s.grid_nodes }),
});
