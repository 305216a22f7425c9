# mesh2spline on a genus-0 solid with thin limbs (a generated chair: seat, backrest, four legs).
# Its one-cuboid surface map is squeezed, so the job goes through the GPC with the legs as caps
# and keeps that construction (10 cuboids) whatever its padded hex mesh's folds (on this coarse
# grid `volspline gpc` with mesh2spline's grid options keeps one cuboid, whose padded mesh folds
# less): that one cuboid is the squeezed map the job has just refused.
expect 0 /usr/bin/python3 "$SRC/tests/bench/make_implicit_solid.py" chair 28 "$TMP/chair.off"
expect 0 "$BIN" mesh2spline "$TMP/chair.off" -o "$TMP/chair.json" --grid-nodes 4000 --max-levels 0 --no-untangle --stats-json "$TMP/chair_stats.json"
contains "$TMP/err" "going through the GPC with its limbs as caps"
contains "$TMP/chair_stats.json" "\"genus\": 0"
contains "$TMP/chair_stats.json" "\"cuboids\": 10"
