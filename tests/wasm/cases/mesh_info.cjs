// SPDX-License-Identifier: MIT
// meshInfo(bytes, name): counts, genus, bbox and flat typed arrays of the bundled sample meshes;
// every bad input comes back as {ok:false, message} naming the problem (never an exception).
'use strict';
module.exports = function (vs, { check, sourceDir, fs, path }) {
  const sample = (name) => new Uint8Array(fs.readFileSync(path.join(sourceDir, 'samples/meshes', name)));
  const text = (s) => new TextEncoder().encode(s);

  // cube.off: 8 vertices, 12 triangles, genus 0, unit-ish box.
  const cube = vs.meshInfo(sample('cube.off'), 'cube.off');
  check(cube.ok === true, 'meshInfo(cube.off) ok: ' + cube.message);
  if (cube.ok) {
    check(cube.vertices === 8 && cube.faces === 12 && cube.edges === 18, 'cube counts V=8 F=12 E=18');
    check(cube.closed && cube.manifold && cube.components === 1, 'cube closed, manifold, one component');
    check(cube.genus === 0 && cube.euler_characteristic === 2, 'cube genus 0, chi 2');
    check(cube.positions instanceof Float32Array && cube.positions.length === 24, 'cube positions Float32Array(24)');
    check(cube.triangles instanceof Uint32Array && cube.triangles.length === 36, 'cube triangles Uint32Array(36)');
    check(Array.from(cube.triangles).every((i) => i < 8), 'cube triangle ids < 8');
    check(Array.isArray(cube.bbox_min) && cube.bbox_min.length === 3, 'cube bbox_min is [x,y,z]');
    // The bbox must contain every position exactly (float32 rounding of the same doubles).
    let inside = true;
    for (let i = 0; i < cube.positions.length; i++) {
      const k = i % 3;
      if (cube.positions[i] < Math.fround(cube.bbox_min[k]) || cube.positions[i] > Math.fround(cube.bbox_max[k])) inside = false;
    }
    check(inside, 'cube positions lie inside the bbox');
  }

  // torus.off: genus 1; the same bytes as an ArrayBuffer are accepted too.
  const torusBytes = sample('torus.off');
  const torus = vs.meshInfo(torusBytes.buffer.slice(torusBytes.byteOffset, torusBytes.byteOffset + torusBytes.length), 'torus.off');
  check(torus.ok === true && torus.genus === 1 && torus.closed, 'torus.off genus 1 from an ArrayBuffer');
  check(torus.ok && torus.vertices - torus.edges + torus.faces === 0, 'torus V - E + F = 0');

  // A tetrahedron as OBJ text, extension upper case.
  const tet = vs.meshInfo(text('v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n'), 'tet.OBJ');
  check(tet.ok && tet.vertices === 4 && tet.faces === 4 && tet.genus === 0, 'tetrahedron OBJ: V4 F4 genus 0');
  check(tet.ok && tet.signed_volume > 0 && Math.abs(tet.signed_volume - 1 / 6) < 1e-12, 'tetrahedron volume 1/6');

  // Errors: a message, not an exception; the module keeps working afterwards.
  const bad = (bytes, name, pattern, what) => {
    let r;
    try { r = vs.meshInfo(bytes, name); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(r && r.ok === false && typeof r.message === 'string', what + ': {ok:false, message}');
    check(r && pattern.test(r.message), what + ': message ' + JSON.stringify(r && r.message) + ' matches ' + pattern);
  };
  bad(text('OFF\n4 4 0\n0 0 0\n1 0 0\n'), 'trunc.off', /trunc\.off/, 'truncated OFF');
  bad(text('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n'), 'range.obj', /range\.obj/, 'OBJ index out of range');
  bad(text('hello'), 'notes.txt', /notes\.txt/, 'unknown extension');
  bad('not bytes', 'x.off', /Uint8Array/, 'a string instead of bytes');
  bad(undefined, 'x.off', /Uint8Array/, 'undefined bytes');
  bad(new Uint8Array(0), 'empty.stl', /empty\.stl/, 'empty STL');
  bad(new Uint8Array([1, 2, 3, 4, 5]), 'junk.glb', /junk\.glb/, 'junk GLB');
  // Three triangles on one edge: not manifold.
  bad(text('v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n'), 'fin.obj', /fin\.obj/, 'non-manifold edge');
  const again = vs.meshInfo(sample('cube.off'), 'cube.off');
  check(again.ok && again.vertices === 8, 'meshInfo still works after errors');

  // glTF as real tools write it (#24 item 3): a non-indexed primitive (each triangle its own three
  // vertices) is welded into one closed solid; Draco and meshopt files are refused naming the
  // extension, as the native reader does.
  const testMesh = (name) => new Uint8Array(fs.readFileSync(path.join(sourceDir, 'tests/data/meshes', name)));
  const welded = vs.meshInfo(testMesh('tetra_unindexed.gltf'), 'tetra_unindexed.gltf');
  check(welded.ok && welded.vertices === 4 && welded.closed && welded.components === 1 && welded.genus === 0,
        `non-indexed glTF welds to a closed tetrahedron (${welded.vertices} vertices, closed ${welded.closed}) ${welded.message || ''}`);
  const draco = vs.meshInfo(testMesh('draco_flagged.gltf'), 'draco_flagged.gltf');
  check(!draco.ok && /draco_flagged\.gltf: meshes compressed with KHR_draco_mesh_compression are not supported/.test(draco.message),
        'a Draco glTF is refused naming the extension: ' + JSON.stringify(draco.message));
  const meshopt = text('{"extensionsUsed":["EXT_meshopt_compression"],' + new TextDecoder().decode(testMesh('tetra_unindexed.gltf')).trim().slice(1));
  const refused = vs.meshInfo(meshopt, 'm.gltf');
  check(!refused.ok && /m\.gltf: meshes compressed with EXT_meshopt_compression are not supported/.test(refused.message),
        'a meshopt glTF is refused naming the extension: ' + JSON.stringify(refused.message));
};
