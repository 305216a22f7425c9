// SPDX-License-Identifier: MIT
// The GLBs volspline writes, checked by the Khronos glTF validator (npm gltf-validator): the
// mesh2spline preview (normals, one scene) and the lens mesh (y up, UVs, the image embedded as
// its texture) must have 0 issues of any severity, and carry the attributes they promise.
// usage: node tests/e2e/validate_glb.cjs build/release/cli/volspline [SHARED_DATA_DIR]
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');
const { execFileSync } = require('child_process');
const validator = require('gltf-validator');

const cli = path.resolve(process.argv[2] || 'build/release/cli/volspline');
const root = path.resolve(__dirname, '../..');
const dataDir = path.resolve(process.argv[3] || path.join(root, '../shared/data'));
const out = fs.mkdtempSync(path.join(os.tmpdir(), 'volspline-glb-'));
let passed = 0;
let failed = 0;
const check = (ok, what) => {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
};

function gltfJson(bytes) {
  const length = bytes.readUInt32LE(12);
  return JSON.parse(bytes.subarray(20, 20 + length).toString('utf8'));
}

async function validate(file, what, expect) {
  const bytes = fs.readFileSync(file);
  const report = await validator.validateBytes(new Uint8Array(bytes));
  const i = report.issues;
  const total = i.numErrors + i.numWarnings + i.numInfos + i.numHints;
  check(total === 0, `${what}: validator issues ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints` +
        (total ? ' ' + JSON.stringify(i.messages.slice(0, 3)) : ''));
  expect(gltfJson(bytes));
}

(async () => {
  const glb = path.join(out, 'sphere.glb');
  execFileSync(cli, ['mesh2spline', path.join(root, 'samples/meshes/sphere.off'), '-o', path.join(out, 'sphere.json'), '--glb', glb,
                     '--max-levels', '1', '--quiet'], { stdio: 'inherit' });
  await validate(glb, 'mesh2spline GLB', (j) => {
    check(j.scene === 0 && j.scenes.length === 1, 'mesh2spline GLB has a default scene');
    check(j.meshes[0].primitives[0].attributes.NORMAL !== undefined, 'mesh2spline GLB surface has NORMAL');
  });
  const image = fs.existsSync(path.join(root, 'samples/images/camera.png')) ? path.join(root, 'samples/images/camera.png')
    : path.join(dataDir, 'images/camera.png');
  const lensGlb = path.join(out, 'lens.glb');
  execFileSync(cli, ['lens', image, '-o', path.join(out, 'lens.png'), '--mesh-out', lensGlb, '--roi', 'circle:256,256,60', '--grid', '40', '--quiet'],
               { stdio: 'inherit' });
  await validate(lensGlb, 'lens GLB', (j) => {
    const p = j.meshes[0].primitives[0];
    check(p.attributes.TEXCOORD_0 !== undefined && p.attributes.NORMAL !== undefined, 'lens GLB has UVs and normals');
    check(j.images.length === 1 && j.images[0].mimeType === 'image/png' && j.materials[0].pbrMetallicRoughness.baseColorTexture.index === 0,
          'lens GLB embeds the image as its base colour texture');
    const pos = j.accessors[p.attributes.POSITION];
    check(pos.min[1] >= -1e-3 && pos.max[1] > 0, 'lens GLB positions are y up (y from 0 to the height)');
  });
  fs.rmSync(out, { recursive: true, force: true });
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
})().catch((e) => { console.error(e); process.exit(1); });
