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
