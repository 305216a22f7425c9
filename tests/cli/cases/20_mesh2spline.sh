# mesh2spline and eval: outputs, stats keys, round trip, bad input.
expect 0 "$BIN" mesh2spline --help
contains "$TMP/out" "mesh2spline MESH -o OUT.json"
expect 0 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/s.json" --vtk "$TMP/s.vtu" --glb "$TMP/s.glb" --stats-json "$TMP/s_stats.json" --quiet
has_keys "$TMP/s_stats.json" rms_rel max_rel hausdorff_rel rms_geo_rel control_points levels jacobian_certified_fraction det_j_lower_bound_rel uncertified_cells jacobian_samples min_scaled_jacobian negative_jacobian_fraction negative_jacobian_fraction_fit repaired_control_points semi_standard_max_error times_s
contains "$TMP/s_stats.json" "\"measures\""
contains "$TMP/s.vtu" "scaled_jacobian"
contains "$TMP/s.json" "volspline-tspline"
is_glb "$TMP/s.glb"
expect 0 "$BIN" eval "$TMP/s.json" --uvw 0.5,0.5,0.5
expect 2 "$BIN" eval "$TMP/s.json" --uvw 0.5,0.5
contains "$TMP/err" "three comma-separated numbers"
expect 2 "$BIN" eval "$TMP/s.json" --uvw 2,0.5,0.5
expect 0 "$BIN" mesh2spline "$DATA/meshes/cube.off" -o "$TMP/c.json" --fit meshless --quiet
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n' > "$TMP/open.off"
expect 2 "$BIN" mesh2spline "$TMP/open.off" -o "$TMP/o.json" --quiet
contains "$TMP/err" "not closed"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 nan 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$TMP/nan.off"
expect 2 "$BIN" mesh2spline "$TMP/nan.off" -o "$TMP/n.json" --quiet
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" --quiet
contains "$TMP/err" "needs -o"
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/x.json" --fit magic --quiet
printf '1 2 3\n' > "$TMP/corners.txt"
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/x.json" --corners "$TMP/corners.txt" --quiet
contains "$TMP/err" "expected 8 vertex ids"
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/x.json" --max-surface-error 0 --quiet
contains "$TMP/err" "--max-surface-error must be a positive number"
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/x.json" --repair-jacobian 0.9 --quiet
contains "$TMP/err" "Jacobian repair target"
# The Bézier VTU read back by VTK (python3-vtk9): cell type 79, VTK's evaluation equals eval, no
# certified cell with a non-positive scaled Jacobian at VTK's Gauss points; --vtk-linear hexes.
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_bezier_vtu.py" "$BIN" "$TMP/s.json" "$TMP/s.vtu" --gauss
contains "$TMP/out" "check_bezier_vtu: ok"
# The analysis exports (G+Smo XML, MFEM NURBS mesh, Bézier extraction JSON) read back by an
# independent Python reader: every format evaluates to eval's values at random points.
expect 0 "$BIN" mesh2spline "$DATA/meshes/sphere.off" -o "$TMP/s2.json" --gismo "$TMP/s.xml" --mfem "$TMP/s.mesh" --bezier "$TMP/s_bez.json" --quiet
same_bytes "$TMP/s.json" "$TMP/s2.json" "the exports changed the spline"
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_iga_exports.py" "$BIN" "$TMP/s.json" --gismo "$TMP/s.xml" --mfem "$TMP/s.mesh" --bezier "$TMP/s_bez.json"
contains "$TMP/out" "check_iga_exports: ok"
contains "$TMP/s.xml" "<Geometry type=\"TensorBSpline3\" id=\"0\">"
contains "$TMP/s.mesh" "MFEM NURBS mesh v1.0"
expect 0 "$BIN" mesh2spline "$DATA/meshes/cube.off" -o "$TMP/c.json" --vtk "$TMP/c.vtu" --vtk-linear 6 --quiet
contains "$TMP/c.vtu" "NumberOfCells=\"216\""
expect 2 "$BIN" mesh2spline "$DATA/meshes/cube.off" -o "$TMP/c.json" --vtk "$TMP/c.vtu" --vtk-linear 0 --quiet
contains "$TMP/err" "--vtk-linear must be in 1..512"
# Genus 0, automatic corners: of the candidate corner sets the one whose surface map is clearly
# least anisotropic. Bunny's first set (farthest apart) holds cuboid corner (0,0,1) at an ear tip
# (vertex 453) with poly-edges up both rims; the set taken has no corner there.
expect 0 "$BIN" mesh2spline "$DATA/meshes/bunny_closed.obj" -o "$TMP/b.json" --stats-json "$TMP/b_stats.json" --max-levels 0 --no-untangle --quiet
contains "$TMP/b_stats.json" "\"corners\""
holds_453() { tr -d ' \n' < "$1" | grep -qE '"corners":\[([0-9]+,)*453[],]'; }
if holds_453 "$TMP/b_stats.json"; then bad "bunny's layout holds the ear tip 453 as a corner"; else ok; fi
printf '12807 7060 1586 379 453 12431 13283 3025\n' > "$TMP/bunny_first.txt"
expect 0 "$BIN" mesh2spline "$DATA/meshes/bunny_closed.obj" -o "$TMP/b1.json" --stats-json "$TMP/b1_stats.json" --max-levels 0 --no-untangle --corners "$TMP/bunny_first.txt" --quiet
if holds_453 "$TMP/b1_stats.json"; then ok; else bad "--corners with vertex 453 not kept"; fi
