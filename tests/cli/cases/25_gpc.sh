# gpc: the GPC domain of a solid of any genus; outputs, stats keys, bad input.
expect 0 "$BIN" gpc --help
contains "$TMP/out" "gpc MESH -o DOMAIN.json"
expect 0 "$BIN" gpc "$DATA/meshes/torus.off" -o "$TMP/g.json" --glb "$TMP/g.glb" --vtk "$TMP/g.vtu" --stats-json "$TMP/g_stats.json" --quiet
has_keys "$TMP/g_stats.json" genus t_shapes tubes caps cuboids ill_points flipped_triangles grid_inverted_hexes grid_min_scaled_jacobian interface_gap_rel face_area_ratio_min face_area_ratio_max times_s
contains "$TMP/g_stats.json" "\"genus\": 1"
contains "$TMP/g_stats.json" "\"cuboids\": 1"
contains "$TMP/g_stats.json" "\"ill_points\": 0"
contains "$TMP/g_stats.json" "\"grid_inverted_hexes\": 0"
contains "$TMP/g.json" "volspline-gpc"
contains "$TMP/g.vtu" "cuboid"
is_glb "$TMP/g.glb"
# Same input, same bytes.
expect 0 "$BIN" gpc "$DATA/meshes/torus.off" -o "$TMP/g2.json" --quiet
same_bytes "$TMP/g.json" "$TMP/g2.json" "gpc output differs between two runs"
# Genus 0 is one cuboid; the count comes from the decomposition, a coarse grid shows it.
expect 0 "$BIN" gpc "$DATA/meshes/sphere.off" -o "$TMP/gs.json" --stats-json "$TMP/gs_stats.json" --grid-nodes 2000 --quiet
contains "$TMP/gs_stats.json" "\"cuboids\": 1"
# The layout's balance: a cube is laid out on its own faces, every face's area share equals its
# domain face's (ratio 1).
expect 0 "$BIN" gpc "$DATA/meshes/cube.off" -o "$TMP/gc.json" --stats-json "$TMP/gc_stats.json" --grid-nodes 2000 --quiet
expect 0 python3 -c "import json, sys; s = json.load(open(sys.argv[1])); sys.exit(0 if abs(s['face_area_ratio_min'] - 1) < 1e-9 and abs(s['face_area_ratio_max'] - 1) < 1e-9 else 1)" "$TMP/gc_stats.json"
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n' > "$TMP/gopen.off"
expect 2 "$BIN" gpc "$TMP/gopen.off" -o "$TMP/go.json" --quiet
contains "$TMP/err" "not closed"
expect 2 "$BIN" gpc "$DATA/meshes/torus.off" --quiet
contains "$TMP/err" "needs -o"
printf '1 2 3 4 5 6 7 8\n' > "$TMP/gcorners.txt"
expect 2 "$BIN" gpc "$DATA/meshes/torus.off" -o "$TMP/gx.json" --corners "$TMP/gcorners.txt" --quiet
contains "$TMP/err" "genus-0"
# The hex mesh's least scaled Jacobian, as VTK computes it (python3-vtk9), equals the file's and is
# raised by the last stage (surface nodes sliding): kitten on a coarse grid 0.065 without it.
expect 0 "$BIN" gpc "$DATA/meshes/kitten.off" -o "$TMP/gk.json" --vtk "$TMP/gk.vtu" --grid-nodes 4000 --quiet
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_hex_quality.py" "$TMP/gk.vtu" 0.29
expect 0 "$BIN" gpc "$DATA/meshes/kitten.off" -o "$TMP/gk0.json" --vtk "$TMP/gk0.vtu" --grid-nodes 4000 --quality-sweeps 0 --quiet
expect 1 /usr/bin/python3 "$SRC/tests/cli/check_hex_quality.py" "$TMP/gk0.vtu" 0.2
contains "$TMP/err" "below 0.200"
# The padded mesh's folds that the surface-held untangling leaves, kept (mesh2spline's setting).
expect 0 "$BIN" gpc --help
contains "$TMP/out" "--no-face-sliding"
expect 0 "$BIN" gpc "$DATA/meshes/eight.off" -o "$TMP/gf.json" --stats-json "$TMP/gf_stats.json" --grid-nodes 4000 --no-face-sliding --quality-sweeps 0 --quiet
has_keys "$TMP/gf_stats.json" grid_inverted_hexes grid_min_scaled_jacobian
expect 2 "$BIN" gpc "$DATA/meshes/torus.off" -o "$TMP/gq.json" --quality-sweeps -1 --quiet
contains "$TMP/err" "grid.min_quality_sweeps"
expect 2 "$BIN" gpc "$DATA/meshes/torus.off" -o "$TMP/ga.json" --area-balance 21 --quiet
contains "$TMP/err" "grid.area_balance_iterations"
if [ -e "$TMP/ga.json" ]; then bad "gpc --area-balance 21 wrote its output"; else ok; fi
expect 2 "$BIN" gpc "$DATA/meshes/torus.off" -o "$TMP/gs.json" --squeezed-below 1 --quiet
contains "$TMP/err" "grid.squeezed_below"
