# mesh2spline on a genus-0 solid whose one-cuboid spline folds (a generated fork: handle, flat
# head, three thin tines). With the squeeze rescue off its surface map is not refused as squeezed,
# but its one cube crowds the tines and the spline folds at its Gauss points; the job then makes
# it over the GPC too (the tines as caps), whose spline does not fold, and keeps that one.
expect 0 /usr/bin/python3 "$SRC/tests/bench/make_implicit_solid.py" fork 40 "$TMP/fork.off"
expect 0 "$BIN" mesh2spline "$TMP/fork.off" -o "$TMP/fork.json" --grid-nodes 4000 --max-levels 1 --no-untangle --squeezed-below 0 --stats-json "$TMP/fork_stats.json"
contains "$TMP/err" "the one-cuboid spline folds at"
contains "$TMP/err" "going through the GPC with its limbs as caps too"
contains "$TMP/fork_stats.json" "\"cuboids\": 7"
contains "$TMP/fork_stats.json" "\"negative_jacobian_fraction\": 0.0,"
contains "$TMP/fork.json" "volspline-gpc-spline"
# --one-cuboid keeps the folded one-cuboid spline.
expect 0 "$BIN" mesh2spline "$TMP/fork.off" -o "$TMP/fork1.json" --grid-nodes 4000 --max-levels 1 --no-untangle --squeezed-below 0 --one-cuboid --stats-json "$TMP/fork1_stats.json"
contains "$TMP/fork1_stats.json" "\"cuboids\": 1"
