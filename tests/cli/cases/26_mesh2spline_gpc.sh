# mesh2spline on a solid of genus > 0: one spline over the GPC; JSON, eval --cuboid, VTU, GLB, stats.
expect 0 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gt.json" --vtk "$TMP/gt.vtu" --vtk-linear 24 --glb "$TMP/gt.glb" --stats-json "$TMP/gt_stats.json" --quiet
contains "$TMP/gt.json" "\"format\": \"volspline-gpc-spline\""
has_keys "$TMP/gt_stats.json" untangle_surface_shift_rel untangle_path certificate_passes local_certificate_passes rms_rel hausdorff_rel control_points min_scaled_jacobian negative_jacobian_fraction lattice_negative_fraction semi_standard_max_error genus t_shapes cuboids ill_points interface_gap_rel interface_normal_jump_deg times_s
contains "$TMP/gt_stats.json" "\"genus\": 1"
contains "$TMP/gt_stats.json" "\"cuboids\": 1"
# The det J certificate over every cell of the cuboid box (6 cells; the tube's square section
# puts every cell on its 4 edges, where the fitted surface folds slightly, until the untangler's
# certificate rounds crease it: certified 1).
has_keys "$TMP/gt_stats.json" jacobian_certified_fraction det_j_lower_bound_rel certificate_cells uncertified_cells
contains "$TMP/gt_stats.json" "\"certificate_cells\": 6"
contains "$TMP/gt_stats.json" "\"jacobian_certified_fraction\": 1.0"
contains "$TMP/gt_stats.json" "\"negative_jacobian_fraction\": 0.0"
is_glb "$TMP/gt.glb"
# Same input, same bytes.
expect 0 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gt2.json" --quiet
same_bytes "$TMP/gt.json" "$TMP/gt2.json" "GPC spline JSON differs between two runs"
# eval in cuboid 0's local coordinates; the glued face: u = 0 and u = size meet (torus: a self-glued tube).
expect 0 "$BIN" eval "$TMP/gt.json" --cuboid 0 --uvw 0.01,0.01,0.01 --jacobian
if [ "$(wc -l < "$TMP/out")" = 4 ]; then ok; else bad "eval --jacobian prints 4 lines: $(cat "$TMP/out")"; fi
expect 2 "$BIN" eval "$TMP/gt.json" --cuboid 3 --uvw 0.01,0.01,0.01
contains "$TMP/err" "--cuboid must be in 0..0"
expect 2 "$BIN" eval "$TMP/gt.json" --cuboid 0 --uvw 5,0.01,0.01
sed 's/"points"/"pointz"/' "$TMP/gt.json" > "$TMP/gt_bad.json"
expect 2 "$BIN" eval "$TMP/gt_bad.json" --uvw 0.01,0.01,0.01
contains "$TMP/err" "gt_bad.json"
# The VTU read by VTK: hexahedra with cell data cuboid and scaled_jacobian, points on the spline.
cat > "$TMP/read_gpc_vtu.py" <<'PY'
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput(); cd = g.GetCellData()
assert g.GetNumberOfCells() > 0 and g.GetCellType(0) == 12, "not hexahedra"
assert cd.GetArray("cuboid") is not None and cd.GetArray("scaled_jacobian") is not None, "cell data missing"
lo = min(cd.GetArray("scaled_jacobian").GetValue(i) for i in range(g.GetNumberOfCells()))
assert lo > 0, f"folded cell {lo}"
print(g.GetNumberOfCells())
PY
expect 0 /usr/bin/python3 "$TMP/read_gpc_vtu.py" "$TMP/gt.vtu"
# --hierarchical: T-spline splits past the uniform levels; the JSON holds them, eval reads it, and
# the same input gives the same bytes.
expect 0 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gh.json" --quiet --hierarchical --max-rms 0.0003 --stats-json "$TMP/gh_stats.json" --compare-uniform
contains "$TMP/gh.json" "\"splits\""
# --compare-uniform: the fewest functions of a uniform spline over the same GPC at the same rms.
has_keys "$TMP/gh_stats.json" uniform_control_points uniform_rms_rel
expect 0 /usr/bin/python3 -c "import json,sys; s=json.load(open(sys.argv[1])); assert s['uniform_control_points'] >= 64 and s['uniform_rms_rel'] <= s['rms_rel'], s" "$TMP/gh_stats.json"
contains "$TMP/gh_stats.json" "\"knot_refinement\": \"hierarchical\""
expect 0 "$BIN" eval "$TMP/gh.json" --cuboid 0 --uvw 0.1,0.05,0.05 --jacobian
expect 0 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gh2.json" --quiet --hierarchical --max-rms 0.0003 --gismo "$TMP/gh.xml" --mfem "$TMP/gh.mesh" --bezier "$TMP/gh_bez.json" --vtk "$TMP/gh.vtu"
# --vtk of a GPC spline: the Bézier cells of every cuboid box, read by VTK, equal to eval --cuboid.
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_bezier_vtu.py" "$BIN" "$TMP/gh.json" "$TMP/gh.vtu" --samples 100 --gauss
contains "$TMP/out" "check_bezier_vtu: ok"
# The exports of a GPC spline: one G+Smo patch glued to itself; MFEM's vertex-based topology
# needs the tube in thirds (27 patches); all read back and evaluated by an independent reader.
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_iga_exports.py" "$BIN" "$TMP/gh.json" --gismo "$TMP/gh.xml" --mfem "$TMP/gh.mesh" --bezier "$TMP/gh_bez.json" --samples 100
contains "$TMP/out" "check_iga_exports: ok"
contains "$TMP/out" "G+Smo: 1 interfaces, 4 boundary sides"
contains "$TMP/out" "MFEM: 27 patches"
same_bytes "$TMP/gh.json" "$TMP/gh2.json" "hierarchical GPC spline JSON differs between two runs"
expect 2 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gh_bad.json" --quiet --hierarchical --hierarchy-depth 0
contains "$TMP/err" "--hierarchy-depth"
expect 2 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gh_bad.json" --quiet --certificate-rounds 65
contains "$TMP/err" "--certificate-rounds"
# --untangle-start passes: the per-cuboid passes first; still certified. A bad value is refused.
expect 0 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gp.json" --quiet --untangle-start passes --stats-json "$TMP/gp_stats.json"
contains "$TMP/gp_stats.json" "\"jacobian_certified_fraction\": 1.0"
expect 2 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gh_bad.json" --quiet --untangle-start both
contains "$TMP/err" "--untangle-start must be rounds or passes"
# A genus-0 solid whose one-cuboid surface map is squeezed goes through the GPC (the shared
# sphere's least density 0.886 is squeezed below 0.9); --one-cuboid keeps one cuboid.
expect 0 "$BIN" mesh2spline "$DATA/meshes/sphere.off" --squeezed-below 0.9 -o "$TMP/sq.json" --stats-json "$TMP/sq_stats.json"
contains "$TMP/sq.json" "\"format\": \"volspline-gpc-spline\""
contains "$TMP/err" "its one-cuboid surface map is squeezed"
contains "$TMP/err" "--one-cuboid keeps one cuboid"
contains "$TMP/sq_stats.json" "\"hierarchy_depth\": 6"
contains "$TMP/sq_stats.json" "\"centroid_samples\": true"
expect 0 "$BIN" mesh2spline "$DATA/meshes/sphere.off" --squeezed-below 0.9 --one-cuboid -o "$TMP/sq1.json" --quiet
contains "$TMP/sq1.json" "\"format\": \"volspline-tspline\""
# --limbs P > 0 sends a genus-0 solid through the GPC; the sphere has no limb: one cuboid.
expect 0 "$BIN" mesh2spline "$DATA/meshes/sphere.off" --limbs 0.15 -o "$TMP/gs.json" --stats-json "$TMP/gs_stats.json" --quiet
contains "$TMP/gs.json" "\"format\": \"volspline-gpc-spline\""
contains "$TMP/gs_stats.json" "\"genus\": 0"
contains "$TMP/gs_stats.json" "\"cuboids\": 1"
expect 2 "$BIN" mesh2spline "$DATA/meshes/sphere.off" --limbs 1.5 -o "$TMP/gs.json" --quiet
contains "$TMP/err" "--limbs"
# The sphere's map has room everywhere: no squeeze rescue round; a bound out of range is refused.
contains "$TMP/gs_stats.json" "\"squeeze_rounds\": 0"
expect 2 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gq_bad.json" --squeezed-below 1 --quiet
contains "$TMP/err" "--squeezed-below"
# --centroid-samples: every surface triangle's centroid is a sample too (the surface refined along
# the cut has at least the input's triangles).
expect 0 "$BIN" mesh2spline "$DATA/meshes/torus.off" -o "$TMP/gc.json" --stats-json "$TMP/gc_stats.json" --quiet --centroid-samples
samples_plain=$(grep -o '"samples": [0-9]*' "$TMP/gt_stats.json" | grep -o '[0-9]*$')
samples_centroids=$(grep -o '"samples": [0-9]*' "$TMP/gc_stats.json" | grep -o '[0-9]*$')
faces=$(sed -n 2p "$DATA/meshes/torus.off" | awk '{print $2}')
if [ "$samples_centroids" -ge "$((samples_plain + faces))" ]; then ok; else bad "--centroid-samples: $samples_centroids samples < $samples_plain + $faces triangles"; fi
# Placement and units do not matter: the torus turned by an arbitrary rotation, scaled by 3.7 and
# moved gives the same spline size and the same relative accuracy (the core normalizes).
cat > "$TMP/turn_off.py" <<'PY'
import math, sys
t = open(sys.argv[1]).read().split()
nv, nf = int(t[1]), int(t[2])
q = [0.48, -0.31, 0.66, 0.49]; n = math.sqrt(sum(a * a for a in q)); w, x, y, z = (a / n for a in q)
r = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
with open(sys.argv[2], "w") as f:
    f.write("OFF\n%d %d 0\n" % (nv, nf))
    for i in range(nv):
        p = [float(v) for v in t[4 + 3 * i:7 + 3 * i]]
        f.write("%.17g %.17g %.17g\n" % tuple(3.7 * sum(r[a][b] * p[b] for b in range(3)) + (120.5, -40.0, 7.25)[a] for a in range(3)))
    i = 4 + 3 * nv
    for _ in range(nf):
        k = int(t[i]); f.write(" ".join(t[i:i + k + 1]) + "\n"); i += k + 1
PY
expect 0 /usr/bin/python3 "$TMP/turn_off.py" "$DATA/meshes/torus.off" "$TMP/torus_turned.off"
expect 0 "$BIN" mesh2spline "$TMP/torus_turned.off" -o "$TMP/gr.json" --stats-json "$TMP/gr_stats.json" --quiet
expect 0 /usr/bin/python3 -c "
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert (a['genus'], a['cuboids'], a['control_points']) == (b['genus'], b['cuboids'], b['control_points']), (a['control_points'], b['control_points'])
for k in ('rms_rel', 'hausdorff_rel'): assert abs(a[k] - b[k]) <= 0.1 * a[k], (k, a[k], b[k])
assert b['negative_jacobian_fraction'] == 0 and b['lattice_negative_fraction'] == 0, b
" "$TMP/gt_stats.json" "$TMP/gr_stats.json"
# Cells the untangling leaves uncertified (eight on a coarse grid, 2,000 nodes: its hex mesh keeps
# inverted hexes): a second fit without their grid nodes; the spline kept never has a worse
# certificate than the first fit's (--no-refit), and a kept refit has a better one.
expect 0 "$BIN" mesh2spline "$DATA/meshes/eight.off" -o "$TMP/rf.json" --grid-nodes 2000 --max-levels 2 --stats-json "$TMP/rf_stats.json" --quiet
expect 0 "$BIN" mesh2spline "$DATA/meshes/eight.off" -o "$TMP/rf0.json" --grid-nodes 2000 --max-levels 2 --no-refit --stats-json "$TMP/rf0_stats.json" --quiet
expect 0 /usr/bin/python3 -c "
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert b['refit_dropped_nodes'] == 0 and 'refit_untangle' not in b['times_s'], b['times_s']
na, nb = len(a['uncertified_cells']), len(b['uncertified_cells'])
better = na < nb or (na == nb and a['det_j_lower_bound_rel'] > b['det_j_lower_bound_rel'])
assert better or (na == nb and a['det_j_lower_bound_rel'] == b['det_j_lower_bound_rel']), (na, nb)
assert (a['refit_dropped_nodes'] > 0) == better, (a['refit_dropped_nodes'], na, nb)
assert 'refit_untangle' not in a['times_s'] or nb > 0, (nb, a['times_s'])
" "$TMP/rf_stats.json" "$TMP/rf0_stats.json"
if cmp -s "$TMP/rf.json" "$TMP/rf0.json"; then
  grep -q '"refit_dropped_nodes": 0,' "$TMP/rf_stats.json" && ok || bad "same spline, but a refit was kept"
else
  grep -q '"refit_dropped_nodes": 0,' "$TMP/rf_stats.json" && bad "a different spline, but no refit kept" || ok
fi
