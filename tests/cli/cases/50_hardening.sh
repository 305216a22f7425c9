# Hostile input (issue #23): tiny knot spans, overflowing numbers, deep nesting, bad JPEG tables,
# unsafe outputs, non-regular inputs, size limits, ROIs, messages.
# spline_one KNOTS WEIGHT POINT: a one-function spline file in $TMP/h.json
spline_one() {
  printf '{"format":"volspline-tspline","version":1,"dimension":3,"functions":[{"knots":[%s,%s,%s],"weight":%s,"point":%s}]}' \
    "$1" "$1" "$1" "$2" "$3" > "$TMP/h.json"
}
spline_one '[0,1,2,3,4]' 1 '[1,2,3]'
expect 0 "$BIN" eval "$TMP/h.json" --uvw 2,2,2
spline_one '[0,0,0,0,1e-320]' 1 '[1,2,3]'
expect 2 "$BIN" eval "$TMP/h.json" --uvw 0,0,0
contains "$TMP/err" "knot"
spline_one '[0,1,1.0000000000001,3,4]' 1 '[1,2,3]'
expect 2 "$BIN" eval "$TMP/h.json" --uvw 2,2,2
contains "$TMP/err" "below 1e-12 of the domain"
spline_one '[1e300,1e300,1e300,1e300,1.0000000000001e300]' 1 '[1,2,3]'
expect 2 "$BIN" eval "$TMP/h.json" --uvw 1e300,1e300,1e300
spline_one '[0,1,2,3,4]' 1e400 '[1,2,3]'
expect 2 "$BIN" eval "$TMP/h.json" --uvw 2,2,2
contains "$TMP/err" "outside the range of doubles"
spline_one '[0,1,2,3,4]' 1e308 '[1e308,2,3]'
expect 2 "$BIN" eval "$TMP/h.json" --uvw 2,2,2
contains "$TMP/err" "overflows"
# Finite values whose Jacobian overflows (1.7e307 times a derivative near 1 / 0.001): refused, and
# nothing printed, not even the point before it (finite there).
printf '{"format":"volspline-tspline","version":1,"dimension":3,"functions":[{"knots":[[0,0.001,0.002,0.003,0.004],[0,1,2,3,4],[0,1,2,3,4]],"weight":1e307,"point":[1.7,1,1]}]}' > "$TMP/h.json"
expect 0 "$BIN" eval "$TMP/h.json" --uvw 0.00001,2,2 --jacobian
expect 2 "$BIN" eval "$TMP/h.json" --uvw 0.00001,2,2 --uvw 0.0015,2,2 --jacobian
contains "$TMP/err" "the Jacobian at 0.0015,2,2 is not finite"
if [ ! -s "$TMP/out" ]; then ok; else bad "eval printed values before refusing a point: $(head -c 200 "$TMP/out")"; fi
# glTF whose extras nest 20,000 deep: refused before tinygltf's recursive parse.
python3 -c "import sys; d=20000; sys.stdout.write('{\"asset\":{\"version\":\"2.0\"},\"extras\":' + '['*d + ']'*d + '}')" > "$TMP/deep.gltf"
expect 2 "$BIN" info "$TMP/deep.gltf"
contains "$TMP/err" "nests deeper than 512 levels"
expect 2 "$BIN" mesh2spline "$TMP/deep.gltf" -o "$TMP/deep.json" --quiet
contains "$TMP/err" "nests deeper than 512 levels"
# Outputs: a symlink at the old fixed temporary name is never followed.
M=(mesh2spline "$DATA/meshes/cube.off" --max-levels 0 --quiet)
mkdir -p "$TMP/o"; echo precious > "$TMP/o/victim"
ln -s "$TMP/o/victim" "$TMP/o/c.json.tmp-volspline"
expect 0 "$BIN" "${M[@]}" -o "$TMP/o/c.json"
contains "$TMP/o/victim" "precious"
contains "$TMP/o/c.json" "volspline-tspline"
if [ -z "$(ls -A "$TMP/o" | grep -v '^victim$\|^c.json$\|^c.json.tmp-volspline$')" ]; then ok; else bad "temporaries left: $(ls -A "$TMP/o")"; fi
# The target keeps its permissions; a symlinked output keeps its link.
chmod 600 "$TMP/o/c.json"
expect 0 "$BIN" "${M[@]}" -o "$TMP/o/c.json"
if [ "$(stat -c %a "$TMP/o/c.json")" = 600 ]; then ok; else bad "output mode $(stat -c %a "$TMP/o/c.json"), want 600"; fi
ln -s c.json "$TMP/o/link.json"
expect 0 "$BIN" "${M[@]}" -o "$TMP/o/link.json"
if [ -L "$TMP/o/link.json" ]; then ok; else bad "the symlinked output was replaced by a file"; fi
# Character devices are written directly, never replaced; a device that refuses the bytes is exit 1
# and leaves the other outputs untouched. Private device nodes only (root: mknod), never the
# system's /dev/null or /dev/full, which a broken binary would replace.
if [ "$(id -u)" = 0 ] && mknod "$TMP/o/null" c 1 3 2>/dev/null && mknod "$TMP/o/full" c 1 7 2>/dev/null; then
  expect 0 "$BIN" "${M[@]}" -o "$TMP/o/null"
  if [ -c "$TMP/o/null" ]; then ok; else bad "-o onto a character device replaced it"; fi
  rm -f "$TMP/o/full.json"
  expect 1 "$BIN" "${M[@]}" -o "$TMP/o/full.json" --stats-json "$TMP/o/full"
  contains "$TMP/err" "$TMP/o/full"
  if [ ! -e "$TMP/o/full.json" ]; then ok; else bad "-o was written although --stats-json failed"; fi
  if [ -z "$(ls -A "$TMP/o" | grep 'tmp-volspline-')" ]; then ok; else bad "temporaries left after a failed write: $(ls -A "$TMP/o")"; fi
  if [ -c "$TMP/o/full" ]; then ok; else bad "--stats-json onto a character device replaced it"; fi
fi
# Outputs equal to an input or to each other are refused by resolved path, before any work.
cp "$DATA/meshes/cube.off" "$TMP/o/in.off"; cp "$TMP/o/in.off" "$TMP/o/in.bak"
expect 2 "$BIN" mesh2spline "$TMP/o/in.off" -o "$TMP/o/in.off" --quiet
contains "$TMP/err" "is the input"
expect 2 "$BIN" mesh2spline "$TMP/o/in.off" -o "$TMP/o/x.json" --vtk "$TMP/o/../o/./in.off" --quiet
ln -s in.off "$TMP/o/in_link.off"; ln "$TMP/o/in.off" "$TMP/o/in_hard.off"
expect 2 "$BIN" mesh2spline "$TMP/o/in_link.off" -o "$TMP/o/in.off" --quiet
expect 2 "$BIN" mesh2spline "$TMP/o/in.off" -o "$TMP/o/in_hard.off" --quiet
expect 2 "$BIN" mesh2spline "$TMP/o/in.off" -o "$TMP/o/x.json" --stats-json "$TMP/o/x.json" --quiet
contains "$TMP/err" "also the -o output"
same_bytes "$TMP/o/in.off" "$TMP/o/in.bak" "the input mesh was overwritten"
cp "$SRC/samples/images/text.png" "$TMP/o/in.png"
expect 2 "$BIN" lens "$TMP/o/in.png" -o "$TMP/o/in.png" --roi circle:10,10,5 --quiet
cp "$SRC/samples/volumes/bucky_32x32x32_uint8.raw" "$TMP/o/b_32x32x32_uint8.raw"
expect 2 "$BIN" vol2spline "$TMP/o/b_32x32x32_uint8.raw" -o "$TMP/o/v.json" --vtk "$TMP/o/b_32x32x32_uint8.raw" --quiet
same_bytes "$TMP/o/b_32x32x32_uint8.raw" "$SRC/samples/volumes/bucky_32x32x32_uint8.raw" "the input volume was overwritten"
# Every output folder is checked before the work starts (exit 2, -o not written).
rm -f "$TMP/o/x.json"
expect 2 "$BIN" "${M[@]}" -o "$TMP/o/x.json" --stats-json "$TMP/no/such/folder/s.json"
contains "$TMP/err" "does not exist"
if [ ! -e "$TMP/o/x.json" ]; then ok; else bad "-o written although --stats-json's folder is missing"; fi
expect 2 "$BIN" "${M[@]}" -o "$TMP/o"
contains "$TMP/err" "is a folder"
# Inputs that are not regular files are refused at once (no endless read, no hang).
expect 2 timeout 20 "$BIN" info /dev/zero
contains "$TMP/err" "character device, not a regular file"
mkfifo "$TMP/o/fifo.off"
expect 2 timeout 20 "$BIN" info "$TMP/o/fifo.off"
contains "$TMP/err" "a FIFO, not a regular file"
expect 2 "$BIN" info "$TMP/o"
contains "$TMP/err" "is a folder, not a regular file"
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: /dev/zero\n\n' > "$TMP/o/z.nhdr"
expect 2 timeout 20 "$BIN" vol2spline "$TMP/o/z.nhdr" -o "$TMP/o/z.json" --quiet
contains "$TMP/err" "not a regular file"
# Size limits are checked on the header, before allocating; an option raises them.
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1024 1024 1024\nencoding: gzip\n\n' > "$TMP/o/bomb.nrrd"
head -c 1000 /dev/zero | gzip -c >> "$TMP/o/bomb.nrrd"
expect 2 "$BIN" vol2spline "$TMP/o/bomb.nrrd" -o "$TMP/o/bomb.json" --quiet
contains "$TMP/err" "1024x1024x1024 voxels is above the limit --max-voxels = 16777216"
expect 2 "$BIN" vol2spline "$SRC/samples/volumes/bucky_32x32x32_uint8.raw" -o "$TMP/o/b.json" --max-voxels 1000 --quiet
contains "$TMP/err" "32x32x32 voxels is above the limit --max-voxels = 1000"
python3 -c "
import struct, zlib, sys
def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
ihdr = struct.pack('>IIBBBBB', 20000, 20000, 8, 0, 0, 0, 0)
sys.stdout.buffer.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', ihdr) + chunk(b'IDAT', zlib.compress(b'\0' * 1000)) + chunk(b'IEND', b''))
" > "$TMP/o/big.png"
expect 2 "$BIN" lens "$TMP/o/big.png" -o "$TMP/o/big_out.png" --roi circle:10,10,5 --quiet
contains "$TMP/err" "PNG of 20000 x 20000 pixels is above the limit --max-pixels = 67108864"
expect 2 "$BIN" lens "$SRC/samples/images/text.png" -o "$TMP/o/t.png" --roi circle:10,10,5 --max-pixels 100 --quiet
contains "$TMP/err" "is above the limit --max-pixels = 100"
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/o/x.json" --initial-cells 64 --quiet
contains "$TMP/err" "control points at level 0, above --max-control-points = 50000"
# Messages: the real problem, control bytes escaped, core fields shown as flags.
expect 2 "$BIN" vol2spline "$TMP/o/x_64x64x64_uint7.raw" -o "$TMP/o/x.json" --quiet
contains "$TMP/err" "sample type 'uint7' is not uint8"
expect 2 "$BIN" vol2spline "$TMP/o/x_0x64x64_uint8.raw" -o "$TMP/o/x.json" --quiet
contains "$TMP/err" "dims '0x64x64' are not three positive sizes"
expect 2 "$BIN" vol2spline "$TMP/o/plain.raw" -o "$TMP/o/x.json" --quiet
contains "$TMP/err" "needs its dims and type (--dims X,Y,Z and --type T)"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n\033[31mred\n' > "$TMP/o/esc.off"
expect 2 "$BIN" info "$TMP/o/esc.off"
if grep -q "$(printf '\033')" "$TMP/err"; then bad "an escape byte reached the terminal: $(cat -v "$TMP/err")"; else ok; fi
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/o/x.json" --max-rms -1 --quiet
contains "$TMP/err" "--max-rms must be a positive number"
# ROIs: refused when they cover the image many times over; without --roi a centred circle.
expect 2 "$BIN" lens "$SRC/samples/images/text.png" -o "$TMP/o/r.png" --roi circle:100,100,1e9 --quiet
contains "$TMP/err" "times the"
expect 0 "$BIN" lens "$SRC/samples/images/text.png" -o "$TMP/o/r.png" --grid 40 --stats-json "$TMP/o/r.json" --quiet
contains "$TMP/o/r.json" "\"magnification_center\""
# Progress to a file or pipe: plain lines (shown from 1 s on), never carriage-return frames.
expect 0 "$BIN" mesh2spline "$DATA/meshes/bimba.off" -o "$TMP/o/p.json" --max-levels 2
if grep -q "$(printf '\r')" "$TMP/err"; then bad "progress wrote \\r frames to a non-terminal"; else ok; fi
