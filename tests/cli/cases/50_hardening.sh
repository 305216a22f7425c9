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
# and leaves the other outputs untouched.
if [ "$(id -u)" = 0 ] && mknod "$TMP/o/null" c 1 3 2>/dev/null; then
  expect 0 "$BIN" "${M[@]}" -o "$TMP/o/null"
  if [ -c "$TMP/o/null" ]; then ok; else bad "-o onto a character device replaced it"; fi
fi
expect 0 "$BIN" "${M[@]}" -o /dev/null
if [ -c /dev/null ]; then ok; else bad "/dev/null is no longer a device"; fi
rm -f "$TMP/o/full.json"
expect 1 "$BIN" "${M[@]}" -o "$TMP/o/full.json" --stats-json /dev/full
contains "$TMP/err" "/dev/full"
if [ ! -e "$TMP/o/full.json" ]; then ok; else bad "-o was written although --stats-json failed"; fi
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
if cmp -s "$TMP/o/in.off" "$TMP/o/in.bak"; then ok; else bad "the input mesh was overwritten"; fi
cp "$SRC/samples/images/text.png" "$TMP/o/in.png"
expect 2 "$BIN" lens "$TMP/o/in.png" -o "$TMP/o/in.png" --roi circle:10,10,5 --quiet
cp "$SRC/samples/volumes/bucky_32x32x32_uint8.raw" "$TMP/o/b_32x32x32_uint8.raw"
expect 2 "$BIN" vol2spline "$TMP/o/b_32x32x32_uint8.raw" -o "$TMP/o/v.json" --vtk "$TMP/o/b_32x32x32_uint8.raw" --quiet
if cmp -s "$TMP/o/b_32x32x32_uint8.raw" "$SRC/samples/volumes/bucky_32x32x32_uint8.raw"; then ok; else bad "the input volume was overwritten"; fi
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
