# volspline info: genus of every shared mesh (SOURCES.md), broken files exit 2 naming the file.
while read -r file genus; do
  expect 0 "$BIN" info "$DATA/meshes/$file" --json
  contains "$TMP/out" "\"genus\": $genus"
  contains "$TMP/out" "\"closed\": true"
done <<'TABLE'
kitten.off 1
kitten_coarse.off 1
eight.off 2
bimba.off 0
torus.off 1
fertility.off 4
genus3.off 3
bunny_closed.obj 0
sphere.off 0
cube.off 0
dancer.off 1
armadillo.off 0
knot.obj 1
TABLE

expect 0 "$BIN" info "$DATA/meshes/cube.off"
contains "$TMP/out" "vertices             8"
contains "$TMP/out" "faces                12"
contains "$TMP/out" "genus                0"
expect 0 "$BIN" info --help
contains "$TMP/out" "volspline info FILE"

for broken in truncated.off nan_coordinate.obj nonmanifold_edge.off empty.obj wrong_index.off; do
  expect 2 "$BIN" info "$SRC/tests/data/meshes/$broken"
  contains "$TMP/err" "$broken"
done
expect 2 "$BIN" info "$SRC/tests/data/meshes/truncated.off" --json
contains "$TMP/err" "truncated"
expect 2 "$BIN" info "$SRC/tests/data/meshes/nan_coordinate.obj"
contains "$TMP/err" "NaN"
expect 2 "$BIN" info "$SRC/tests/data/meshes/wrong_index.off"
contains "$TMP/err" "out of range"
expect 2 "$BIN" info "$TMP/no_such_mesh.obj"
contains "$TMP/err" "no_such_mesh.obj"
expect 2 "$BIN" info "$SRC/tests/data/meshes/unknown.xyz"
contains "$TMP/err" "unknown.xyz"
expect 2 "$BIN" info

# Volumes written by VTK 9.1 (tests/data/volumes/make_vtk_volumes.py): dims, type, spacing, origin
# and axis directions as written, for legacy VTK colour scalars, compressed MetaImage, every VTI
# data mode and NIfTI (qform, and an sform mirroring x and y).
V="$SRC/tests/data/volumes"
for file in u8_bin.vtk u8_ascii.vtk u8.mha u8.mhd d_ascii_z.vti d_binary_n.vti d_appended_z.vti d_appended_b64.vti n.nii n.nii.gz; do
  expect 0 "$BIN" info "$V/$file"
  contains "$TMP/out" "dims                 5 x 4 x 3"
  contains "$TMP/out" "spacing              0.5 0.25 2"
  contains "$TMP/out" "origin               10 -20 30"
  contains "$TMP/out" "values               0 .. 59"
done
contains "$TMP/out" "type                 int16"
expect 0 "$BIN" info "$V/d_binary_z.vti" --json
contains "$TMP/out" '"type": "uint8"'
tr -d ' \n' < "$TMP/out" > "$TMP/flat.json"
contains "$TMP/flat.json" '"direction":[[-1.0,0.0,0.0],[0.0,-1.0,0.0],[0.0,0.0,1.0]]'
expect 0 "$BIN" info "$V/u16_q.nii.gz"
contains "$TMP/out" "origin               -5 26 37"
contains "$TMP/out" "direction x          -1 0 0"
expect 2 "$BIN" info "$TMP/no_such_volume.nii.gz"
contains "$TMP/err" "no_such_volume.nii.gz"
