// SPDX-License-Identifier: MIT
// Loads the CommonJS WebAssembly build under node and calls into the core.
// usage: node --no-experimental-fetch node_smoke_test.cjs BUILD_DIR/wasm/volspline_node.cjs SOURCE_DIR SHARED_DATA
'use strict';
const path = require('path');
const fs = require('fs');
const [modulePath, sourceArg, dataDir] = process.argv.slice(2);
const sourceDir = path.resolve(sourceArg);
const createVolspline = require(path.resolve(modulePath));

let passed = 0;
let failed = 0;
function check(condition, what) {
  if (condition) passed++;
  else { failed++; console.log('FAIL: ' + what); }
}

createVolspline().then((vs) => {
  check(/^\d+\.\d+\.\d+$/.test(vs.version()), 'version() is MAJOR.MINOR.PATCH');
  const cases = fs.existsSync(path.join(sourceDir, 'tests/wasm/cases'))
    ? fs.readdirSync(path.join(sourceDir, 'tests/wasm/cases')).filter((f) => f.endsWith('.cjs')).sort()
    : [];
  for (const c of cases) require(path.join(sourceDir, 'tests/wasm/cases', c))(vs, { check, dataDir, sourceDir, fs, path });
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed === 0 ? 0 : 1);
}).catch((e) => {
  console.log('FAIL: module did not load: ' + e);
  console.log(`${passed} passed, ${failed + 1} failed`);
  process.exit(1);
});
