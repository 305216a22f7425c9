// SPDX-License-Identifier: MIT
// WASM/native time ratio of mesh2spline with default options, one thread. For each mesh, RUNS
// times and alternating (so both sides see the same machine load): the native CLI
// (`volspline mesh2spline MESH -o … --stats-json … --quiet --threads 1`, wall and user+sys CPU of
// the process from /usr/bin/time) and the node build in this process (mesh2spline with
// {threads: 1, outputs: false}: wall and process CPU of the call). Also compares the core's own
// times_s.total, which excludes reading the file and, in the browser build, the preview geometry.
// Prints medians, the ratios and the stats keys whose values differ between the two as JSON.
// usage: node --no-experimental-fetch tests/wasm/bench_mesh2spline_wasm.cjs NODE_BUILD.cjs VOLSPLINE_CLI MESH... [--runs 3]
'use strict';
const path = require('path');
const { benchAgainstNative } = require('./bench_against_native.cjs');

benchAgainstNative({
  script: 'bench_mesh2spline_wasm.cjs',
  tmpPrefix: 'bench-m2s-',
  cliArgs: (mesh, stats, tmp) =>
    ['mesh2spline', mesh, '-o', path.join(tmp, 'out.json'), '--stats-json', stats, '--quiet', '--threads', '1'],
  run: (vs, bytes, name) => vs.mesh2spline(bytes, name, { threads: 1, outputs: false }, null),
  summary: (s) => ({ control_points: s.control_points, rms_rel: s.rms_rel }),
});
