// SPDX-License-Identifier: MIT
// loadVolume(bytes, name, layout): raw volumes with dims from the name or from a layout object,
// NRRD with attached data (raw, gzip), VTK-written legacy VTK, MetaImage, VTI and NIfTI files with
// their origin and direction; {ok:false, message} naming the file for bad input.
'use strict';
module.exports = function (vs, { check, dataDir, sourceDir, fs, path }) {
  const text = (s) => new TextEncoder().encode(s);
  // 4×3×2 uint8 ramp: sample (x, y, z) = x + 4y + 12z.
  const ramp = new Uint8Array(24).map((_, i) => i);
  const fromName = vs.loadVolume(ramp, 'ramp_4x3x2_uint8.raw', null);
  check(fromName.ok === true, 'raw with dims in the name: ' + fromName.message);
  if (fromName.ok) {
    check(fromName.nx === 4 && fromName.ny === 3 && fromName.nz === 2 && fromName.type === 'uint8', 'dims 4×3×2 uint8');
    check(fromName.samples instanceof Float32Array && fromName.samples.length === 24 && fromName.samples[13] === 13, 'samples x fastest');
    check(fromName.min === 0 && fromName.max === 23 && fromName.spacing.join() === '1,1,1', 'min, max, spacing');
  }
  const u16 = new Uint8Array(new Uint16Array([1, 2, 3, 65535, 5, 6]).buffer);
  const withLayout = vs.loadVolume(u16, 'upload.raw', { dims: [3, 2, 1], type: 'uint16' });
  check(withLayout.ok && withLayout.nx === 3 && withLayout.max === 65535 && withLayout.type === 'uint16', 'raw with a layout object (uint16)');

  const header = 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 3 2\nspacings: 1 2 3\nencoding: raw\n\n';
  const nrrd = new Uint8Array([...text(header), ...ramp]);
  const n = vs.loadVolume(nrrd, 'ramp.nrrd', null);
  check(n.ok && n.nx === 4 && n.nz === 2 && n.samples[23] === 23 && n.spacing.join() === '1,2,3', 'NRRD with attached data: ' + n.message);

  // gzip NRRD in the browser build (stb's inflate, checksum checked), made with node's zlib.
  const gz = require('zlib').gzipSync(Buffer.from(ramp));
  const gzNrrd = vs.loadVolume(new Uint8Array([...text(header.replace('encoding: raw', 'encoding: gzip')), ...gz]), 'ramp.nrrd', null);
  check(gzNrrd.ok && gzNrrd.samples[23] === 23, 'gzip NRRD: ' + gzNrrd.message);
  const badGz = Buffer.from(gz); badGz[badGz.length - 6] ^= 0xff;  // corrupt the CRC32
  const corrupt = vs.loadVolume(new Uint8Array([...text(header.replace('encoding: raw', 'encoding: gzip')), ...badGz]), 'bad.nrrd', null);
  check(!corrupt.ok && /bad\.nrrd.*(corrupt|checksum)/.test(corrupt.message), 'corrupt gzip NRRD: ' + JSON.stringify(corrupt.message));

  // Files written by VTK 9.1 (tests/data/volumes): samples 0..59, origin (10, -20, 30).
  const volumes = path.join(sourceDir || '', 'tests/data/volumes');
  if (sourceDir && fs.existsSync(volumes)) {
    for (const [file, dir] of [['u8_bin.vtk', [1, 0, 0, 0, 1, 0, 0, 0, 1]], ['u8_ascii.vtk', [1, 0, 0, 0, 1, 0, 0, 0, 1]],
                               ['u8.mha', [1, 0, 0, 0, 1, 0, 0, 0, 1]], ['d_binary_z.vti', [-1, 0, 0, 0, -1, 0, 0, 0, 1]],
                               ['d_appended_b64.vti', [-1, 0, 0, 0, -1, 0, 0, 0, 1]], ['n.nii.gz', [1, 0, 0, 0, 1, 0, 0, 0, 1]]]) {
      const v = vs.loadVolume(new Uint8Array(fs.readFileSync(path.join(volumes, file))), file, null);
      const samplesOk = v.ok && v.samples.length === 60 && v.samples.every((x, i) => x === i);
      check(samplesOk && v.origin.join() === '10,-20,30' && v.direction.join() === dir.join() && v.spacing.join() === '0.5,0.25,2',
            `VTK-written ${file}: ${v.ok ? `origin ${v.origin}, direction ${v.direction}` : v.message}`);
    }
  }

  const bucky = path.join(dataDir || '', 'volumes/bucky_32x32x32_uint8.raw');
  if (dataDir && fs.existsSync(bucky)) {
    const b = vs.loadVolume(new Uint8Array(fs.readFileSync(bucky)), 'bucky_32x32x32_uint8.raw', null);
    check(b.ok && b.nx === 32 && b.samples.length === 32768 && b.max > b.min, 'bucky 32³ from the shared data');
  }

  const bad = (args, pattern, what) => {
    let x;
    try { x = vs.loadVolume(...args); } catch (e) { check(false, what + ': threw ' + e); return; }
    check(x && x.ok === false && pattern.test(x.message), `${what}: ${JSON.stringify(x && x.message)}`);
  };
  bad([ramp, 'nodims.raw', null], /nodims\.raw.*dims/, 'raw without dims');
  bad([ramp, 'short_4x3x3_uint8.raw', null], /short_4x3x3_uint8\.raw/, 'raw with too few bytes');
  bad([ramp, 'x.raw', { dims: [4, 3] }], /dims/, 'layout with 2 dims');
  bad([ramp, 'x.raw', { dims: [4, 3, 2], type: 'int12' }], /int12/, 'unknown sample type');
  bad([text('NRRD0004\ntype: uint8\ndimension: 2\nsizes: 4 3\nencoding: raw\n\n'), 'flat.nrrd', null], /flat\.nrrd/, 'NRRD of dimension 2');
  bad([text('garbage'), 'junk.nrrd', null], /junk\.nrrd/, 'not an NRRD');
  bad([ramp, 'volume.xyz', null], /volume\.xyz/, 'unknown extension');
  check(vs.loadVolume(ramp, 'ramp_4x3x2_uint8.raw', null).ok, 'loadVolume still works after errors');
};
