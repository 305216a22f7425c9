#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Hostile-input campaign: generates malformed, oversized and tricky inputs for every reader and
command of the volspline CLI, runs each in an empty working folder and reports crashes (signal
or sanitizer report), hangs (timeout), peak memory above 2 GB for an input under 2 MB, and files
written anywhere but the named outputs.

usage: campaign.py VOLSPLINE_BIN SOURCE_DIR SHARED_DATA_DIR [--timeout S] [--keep DIR]
Prints one line per failure and a summary; exits 1 on any failure."""
import gzip, os, random, shutil, struct, subprocess, sys, tempfile, zlib

BIN, SRC, DATA = (os.path.abspath(a) for a in sys.argv[1:4])
TIMEOUT = 120
if '--timeout' in sys.argv: TIMEOUT = int(sys.argv[sys.argv.index('--timeout') + 1])
rng = random.Random(23)
cases = []  # (name, file name, bytes or None, argv template)


def add(name, filename, data, *commands):
    for argv in commands: cases.append((name, filename, data, argv))


def read(path):
    with open(path, 'rb') as f: return f.read()


def mutate(data, count):
    out = []
    for _ in range(count):
        b = bytearray(data)
        kind = rng.randrange(5)
        if kind == 0 and len(b) > 1: b = b[:rng.randrange(1, len(b))]                     # truncate
        elif kind == 1:
            for _ in range(rng.randrange(1, 8)): b[rng.randrange(len(b))] = rng.randrange(256)  # flip bytes
        elif kind == 2:
            i = rng.randrange(len(b)); b[i:i] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 64)))
        elif kind == 3:
            i = rng.randrange(len(b)); j = min(len(b), i + rng.randrange(1, 200)); b[i:j] = b''
        else:
            i = rng.randrange(len(b)); b[i:i] = rng.choice([b'\x1b[31m', b'999999999999', b'-1', b'nan', b'1e400', b'\0'])
        out.append(bytes(b))
    return out


INFO = ['info', '{in}']
M2S = ['mesh2spline', '{in}', '-o', 'out/m.json', '--vtk', 'out/m.vtu', '--glb', 'out/m.glb', '--stats-json',
       'out/m_stats.json', '--max-levels', '0', '--quiet']
LENS = ['lens', '{in}', '-o', 'out/l.png', '--grid', '16', '--stats-json', 'out/l.json', '--quiet']
V2S = ['vol2spline', '{in}', '-o', 'out/v.json', '--vtk', 'out/v.vtu', '--max-levels', '1', '--quiet']
EVAL = ['eval', '{in}', '--uvw', '0.5,0.5,0.5', '--jacobian']
GPC = ['gpc', '{in}', '-o', 'out/g.json', '--glb', 'out/g.glb', '--vtk', 'out/g.vtu', '--stats-json', 'out/g_stats.json',
       '--grid-nodes', '2000', '--quiet']

# Meshes: every format, mutated, with lying counts and extreme coordinates.
tetra_off = b'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n'
cube_off = read(os.path.join(DATA, 'meshes', 'cube.off'))
sphere_off = read(os.path.join(DATA, 'meshes', 'sphere.off'))
for i, d in enumerate(mutate(cube_off, 30)): add('off-mut', 'm%d.off' % i, d, INFO, M2S)
for i, scale in enumerate(['1e150', '1e300', '1e-300', '1e308']):
    lines = sphere_off.decode().split('\n')
    nv = int(lines[1].split()[0])
    scaled = lines[:2] + [' '.join('%s' % (float(x) * float(scale)) for x in l.split()) for l in lines[2:2 + nv]] + lines[2 + nv:]
    add('off-scale', 's%d.off' % i, '\n'.join(scaled).encode(), INFO, M2S)
for i, shift in enumerate([1e5, 1e9, 1e15]):
    lines = sphere_off.decode().split('\n'); nv = int(lines[1].split()[0])
    moved = lines[:2] + [' '.join('%r' % (float(x) + shift) for x in l.split()) for l in lines[2:2 + nv]] + lines[2 + nv:]
    add('off-shift', 't%d.off' % i, '\n'.join(moved).encode(), M2S)
for i, head in enumerate([b'OFF\n2000000000 2000000000 0\n', b'OFF\n-5 3 0\n', b'OFF\n4 99999999 0\n0 0 0\n',
                          b'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n', b'OFF\n', b'', b'\x1b]0;pwned\x07OFF\n']):
    add('off-head', 'h%d.off' % i, head, INFO, M2S)
tetra_obj = b'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n'
for i, d in enumerate(mutate(tetra_obj, 20) + [b'v 1e400 0 0\n' + tetra_obj, b'f -9 -9 -9\n', b'v nan nan nan\nf 1 1 1\n']):
    add('obj', 'o%d.obj' % i, d, INFO, M2S)
ply = (b'ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n'
       b'element face 4\nproperty list uchar int vertex_indices\nend_header\n' +
       struct.pack('<12f', 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1) +
       b''.join(struct.pack('<B3i', 3, *f) for f in [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]))
for i, d in enumerate(mutate(ply, 25) + [ply.replace(b'vertex 4', b'vertex 4000000000'),
                                         ply.replace(b'uchar int', b'uint int')]):
    add('ply', 'p%d.ply' % i, d, INFO, M2S)
stl = b'\0' * 80 + struct.pack('<I', 4) + b''.join(
    struct.pack('<12fH', 0, 0, 0, *a, *b, *c, 0) for a, b, c in [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (0, 0, 1)),
                                                               ((0, 0, 0), (0, 0, 1), (0, 1, 0)), ((1, 0, 0), (0, 1, 0), (0, 0, 1))])
for i, d in enumerate(mutate(stl, 20) + [stl[:80] + struct.pack('<I', 0xFFFFFFFF) + stl[84:]]):
    add('stl', 'st%d.stl' % i, d, INFO, M2S)
gltf_corpus = os.path.join(SRC, 'tests', 'fuzz', 'corpus', 'gltf')
for fname in sorted(os.listdir(gltf_corpus)):
    d = read(os.path.join(gltf_corpus, fname))
    ext = os.path.splitext(fname)[1]
    add('gltf', 'g_' + fname, d, INFO)
    for i, m in enumerate(mutate(d, 6)): add('gltf-mut', 'g%d_%s' % (i, fname), m, INFO, M2S)
for depth in (600, 5000, 20000, 100000):
    add('gltf-deep', 'deep%d.gltf' % depth, b'{"asset":{"version":"2.0"},"extras":' + b'[' * depth + b']' * depth + b'}', INFO, M2S)
add('gltf-uri', 'uri.gltf', b'{"asset":{"version":"2.0"},"buffers":[{"uri":"/dev/zero","byteLength":100}]}', INFO)
add('gltf-uri', 'uri2.gltf', b'{"asset":{"version":"2.0"},"buffers":[{"uri":"../../../../etc/passwd","byteLength":100}]}', INFO)

# Genus 1 (mesh2spline's multi-cuboid route), mutated; every mesh case above also through gpc.
torus_off = read(os.path.join(DATA, 'meshes', 'torus.off'))
for i, d in enumerate([torus_off] + mutate(torus_off, 12)): add('torus', 'tor%d.off' % i, d, M2S)
cases += [(name, filename, data, GPC) for name, filename, data, argv in list(cases) if argv is M2S]

# Images: PNG and JPEG headers, truncations, DHT overflow, size claims; lens on each.
png = read(os.path.join(SRC, 'tests', 'fuzz', 'corpus', 'image', 'rgba.png'))
jpg = read(os.path.join(SRC, 'tests', 'fuzz', 'corpus', 'image', 'rgb.jpg'))
for i, d in enumerate(mutate(png, 20)): add('png', 'i%d.png' % i, d, LENS)
for i, d in enumerate(mutate(jpg, 30)): add('jpg', 'j%d.jpg' % i, d, LENS)
def png_of(w, h, body=b'\0' * 100):
    chunk = lambda t, d: struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    return b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 6, 0, 0, 0)) + chunk(b'IDAT', zlib.compress(body)) + chunk(b'IEND', b'')
for i, (w, h) in enumerate([(20000, 20000), (1 << 24, 1), (1, 1 << 24), (0, 5), (65535, 65535), (8000, 8000), (3, 3)]):
    add('png-size', 'ps%d.png' % i, png_of(w, h), LENS)
add('png-bomb', 'bomb.png', png_of(8000, 8000, b'\0' * (8000 * 4 + 1) * 8000), LENS)
bad_dht = bytearray(jpg); k = bad_dht.find(b'\xff\xc4')
for j in range(16): bad_dht[k + 5 + j] = 0xFF
add('jpg-dht', 'dht.jpg', bytes(bad_dht), LENS)
add('jpg-trunc', 'tr.jpg', jpg[:len(jpg) // 3], LENS)
add('img-empty', 'e.png', b'', LENS)

# Volumes: raw names, NRRD/VTK/MetaImage/VTI/NIfTI headers with lies and bombs.
bucky = read(os.path.join(SRC, 'samples', 'volumes', 'bucky_32x32x32_uint8.raw'))
for name in ['v_32x32x32_uint7.raw', 'v_0x32x32_uint8.raw', 'v_32x32_uint8.raw', 'v_99999999999x1x1_uint8.raw',
             'v_32x32x32_float64.raw', 'v_16x16x16_uint8.raw', 'plain.raw', 'v_32x32x32_UINT8.raw']:
    add('raw', name, bucky, V2S)
nrrd = b'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n\n' + bytes(range(256)) * 2
for i, d in enumerate(mutate(nrrd, 25)): add('nrrd', 'n%d.nrrd' % i, d, V2S)
for i, sizes in enumerate([b'1024 1024 1024', b'4096 4096 4096', b'2000000000 1 1', b'0 1 1', b'-3 4 4']):
    add('nrrd-bomb', 'nb%d.nrrd' % i, b'NRRD0004\ntype: uint8\ndimension: 3\nsizes: ' + sizes + b'\nencoding: gzip\n\n' +
        gzip.compress(b'\0' * 1000000), V2S)
add('nhdr-dev', 'z.nhdr', b'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: /dev/zero\n\n', V2S)
add('nhdr-self', 'self.nhdr', b'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: self.nhdr\n\n', V2S)
vtk = (b'# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 8 8 8\nSPACING 1 1 1\nORIGIN 0 0 0\n'
       b'POINT_DATA 512\nSCALARS d unsigned_char 1\nLOOKUP_TABLE default\n' + bytes(range(256)) * 2)
for i, d in enumerate(mutate(vtk, 20)): add('vtk', 'k%d.vtk' % i, d, V2S)
mha = b'ObjectType = Image\nNDims = 3\nDimSize = 8 8 8\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' + bytes(range(256)) * 2
for i, d in enumerate(mutate(mha, 15)): add('mha', 'a%d.mha' % i, d, V2S)
add('mha-bomb', 'ab.mha', b'ObjectType = Image\nNDims = 3\nDimSize = 2048 2048 2048\nElementType = MET_UCHAR\nCompressedData = True\n'
    b'ElementDataFile = LOCAL\n' + zlib.compress(b'\0' * 1000000), V2S)
vti = (b'<?xml version="1.0"?><VTKFile type="ImageData" version="1.0" byte_order="LittleEndian"><ImageData WholeExtent="0 7 0 7 0 7" '
       b'Origin="0 0 0" Spacing="1 1 1"><Piece Extent="0 7 0 7 0 7"><PointData Scalars="d"><DataArray type="UInt8" Name="d" '
       b'format="ascii">' + b' '.join(b'%d' % (i % 256) for i in range(512)) + b'</DataArray></PointData></Piece></ImageData></VTKFile>')
for i, d in enumerate(mutate(vti, 15) + [vti.replace(b'0 7 0 7 0 7', b'0 4095 0 4095 0 4095')]): add('vti', 'x%d.vti' % i, d, V2S)
nii = bytearray(352 + 512)
struct.pack_into('<i', nii, 0, 348); struct.pack_into('<8h', nii, 40, 3, 8, 8, 8, 1, 1, 1, 1)
struct.pack_into('<hh', nii, 70, 2, 8); struct.pack_into('<f', nii, 108, 352.0); nii[344:348] = b'n+1\0'
struct.pack_into('<4f', nii, 76, 1, 1, 1, 1)
for i, d in enumerate(mutate(bytes(nii), 15)): add('nii', 'y%d.nii' % i, d, V2S)
big = bytearray(nii); struct.pack_into('<8h', big, 40, 3, 32767, 32767, 32767, 1, 1, 1, 1)
add('nii-bomb', 'yb.nii.gz', gzip.compress(bytes(big) + b'\0' * 1000000), V2S)
gz = bytearray(gzip.compress(bytes(nii))); gz[-4:] = struct.pack('<I', 0xFFFFFFF0)
add('nii-isize', 'yi.nii.gz', bytes(gz), V2S)

# Spline JSON: number overflow, tiny spans, bad weights, nesting, big arrays.
one = b'{"format":"volspline-tspline","version":1,"dimension":3,"functions":[{"knots":[[0,1,2,3,4],[0,1,2,3,4],[0,1,2,3,4]],"weight":1,"point":[1,2,3]}]}'
for i, d in enumerate(mutate(one, 30)): add('json', 'sp%d.json' % i, d, EVAL)
for i, (old, new) in enumerate([(b'[0,1,2,3,4]', b'[0,0,0,0,1e-320]'), (b'"weight":1', b'"weight":1e400'),
                                (b'"weight":1', b'"weight":1e308'), (b'[1,2,3]', b'[1e308,1e308,1e308]'),
                                (b'"weight":1', b'"weight":-1'), (b'[0,1,2,3,4]', b'[4,3,2,1,0]'),
                                (b'[0,1,2,3,4]', b'[-1e308,0,0,0,1e308]'), (b'"dimension":3', b'"dimension":2147483648')]):
    add('json-val', 'sv%d.json' % i, one.replace(old, new, 1), EVAL)
add('json-deep', 'sd.json', b'[' * 100000 + b']' * 100000, EVAL)
add('json-many', 'sm.json', one[:-2] + b',' + b','.join([b'{"knots":[[0,1,2,3,4],[0,1,2,3,4],[0,1,2,3,4]],"weight":1,"point":[1,2,3]}'] * 20000) + b']}', EVAL)

# Special files and output hazards.
special = [('dev-zero', ['info', '/dev/zero']), ('dev-zero-img', ['lens', '/dev/zero', '-o', 'out/z.png', '--quiet']),
           ('dir-in', ['info', '.']), ('fifo', ['info', 'fifo.off']), ('fifo-vol', ['vol2spline', 'f_4x4x4_uint8.raw', '-o', 'out/f.json']),
           ('out-is-in', ['mesh2spline', 'in.off', '-o', 'in.off', '--quiet']),
           ('out-dir', ['mesh2spline', 'in.off', '-o', 'out', '--quiet']),
           ('out-full', ['mesh2spline', 'in.off', '-o', 'out/a.json', '--stats-json', 'full', '--quiet']),
           ('out-null', ['mesh2spline', 'in.off', '-o', 'null', '--quiet']),
           ('out-same', ['mesh2spline', 'in.off', '-o', 'out/a.json', '--vtk', 'out/./a.json', '--quiet']),
           ('out-missing-dir', ['mesh2spline', 'in.off', '-o', 'out/a.json', '--glb', 'nope/x.glb', '--quiet']),
           ('out-symlink-tmp', ['mesh2spline', 'in.off', '-o', 'out/b.json', '--max-levels', '0', '--quiet']),
           ('roi-huge', ['lens', 'in.png', '-o', 'out/r.png', '--roi', 'circle:4,4,1e9', '--quiet']),
           ('roi-outside', ['lens', 'in.png', '-o', 'out/r.png', '--roi', 'circle:-100,4,3', '--quiet']),
           ('cells', ['mesh2spline', 'in.off', '-o', 'out/c.json', '--initial-cells', '64', '--quiet']),
           ('esc-arg', ['mesh2spline', '\x1b[2Jin.off', '-o', 'out/c.json', '--quiet'])]
for name, argv in special: add(name, None, None, argv)

work = tempfile.mkdtemp(prefix='hostile-')
failures, counts, peak_max = [], {'runs': 0, 'exit0': 0, 'exit1': 0, 'exit2': 0}, (0, '')
for n, (name, filename, data, template) in enumerate(cases):
    run = os.path.join(work, 'run%d' % n)
    os.makedirs(os.path.join(run, 'out'))
    size = 0
    if filename:
        with open(os.path.join(run, filename), 'wb') as f: f.write(data)
        size = len(data)
    open(os.path.join(run, 'in.off'), 'wb').write(cube_off)
    open(os.path.join(run, 'in.png'), 'wb').write(png)
    os.mkfifo(os.path.join(run, 'fifo.off')); os.mkfifo(os.path.join(run, 'f_4x4x4_uint8.raw'))
    # Private device nodes for the device-output cases (never the system's /dev/null, /dev/full).
    if os.geteuid() == 0:
        os.mknod(os.path.join(run, 'null'), 0o666 | 0o020000, os.makedev(1, 3))
        os.mknod(os.path.join(run, 'full'), 0o666 | 0o020000, os.makedev(1, 7))
    os.symlink(os.path.join(run, 'in.off'), os.path.join(run, 'out', 'b.json.tmp-volspline'))
    before = set()
    for root, dirs, files in os.walk(run):
        for x in files + dirs: before.add(os.path.relpath(os.path.join(root, x), run))
    argv = [a.replace('{in}', filename or '') for a in template]
    outputs = {argv[i + 1] for i, a in enumerate(argv[:-1]) if a in ('-o', '--vtk', '--glb', '--stats-json', '--frames-vtk', '--mesh-out')}
    try:
        p = subprocess.run(['/usr/bin/time', '-f', '%M', BIN] + argv, cwd=run, capture_output=True, timeout=TIMEOUT,
                           env=dict(os.environ, ASAN_OPTIONS='detect_leaks=1:abort_on_error=1',
                                    UBSAN_OPTIONS='print_stacktrace=1:halt_on_error=1'))
        code, err = p.returncode, p.stderr.decode('utf-8', 'replace')
    except subprocess.TimeoutExpired:
        failures.append('HANG %s %s' % (name, ' '.join(argv))); continue
    counts['runs'] += 1
    lines = err.strip().split('\n')
    peak_kb = int(lines[-1]) if lines and lines[-1].isdigit() else 0
    if peak_kb > peak_max[0]: peak_max = (peak_kb, name + ' ' + ' '.join(argv))
    if 'terminated by signal' in err or code >= 128 or 'Sanitizer' in err or 'runtime error' in err:
        failures.append('CRASH %s exit %d %s :: %s' % (name, code, ' '.join(argv), err[-400:]))
    elif code in (0, 1, 2): counts['exit%d' % code] += 1
    else: failures.append('EXIT %d %s %s' % (code, name, ' '.join(argv)))
    if peak_kb > 2 * 1024 * 1024 and size < 2 * 1024 * 1024:
        failures.append('MEMORY %d MB %s %s' % (peak_kb // 1024, name, ' '.join(argv)))
    if '\x1b' in err: failures.append('ESCAPE %s: an escape byte reached stderr' % name)
    after = set()
    for root, dirs, files in os.walk(run):
        for x in files + dirs: after.add(os.path.relpath(os.path.join(root, x), run))
    stray = [x for x in after - before if os.path.normpath(x) not in {os.path.normpath(o) for o in outputs}]
    if stray: failures.append('STRAY %s %s wrote %s' % (name, ' '.join(argv), stray))
    for dev in ('null', 'full'):
        node = os.path.join(run, dev)
        if os.geteuid() == 0 and (not os.path.lexists(node) or os.path.isfile(node)):
            failures.append('DEVICE %s: the device node %s was replaced or removed' % (name, dev))
    if not os.path.exists(os.path.join(run, 'in.off')) or read(os.path.join(run, 'in.off')) != cube_off:
        failures.append('CLOBBER %s: the input changed' % name)
    if os.path.islink(os.path.join(run, 'out', 'b.json.tmp-volspline')) and read(os.path.join(run, 'in.off')) != cube_off:
        failures.append('SYMLINK %s: written through the planted link' % name)
    shutil.rmtree(run, ignore_errors=True)
if '--keep' not in sys.argv: shutil.rmtree(work, ignore_errors=True)
for f in failures: print(f)
print('%d inputs, %d runs: exit 0: %d, exit 1: %d, exit 2: %d; %d failures; peak %d MB (%s)' %
      (len(cases), counts['runs'], counts['exit0'], counts['exit1'], counts['exit2'], len(failures), peak_max[0] // 1024,
       peak_max[1][:100]))
sys.exit(1 if failures else 0)
