# gpc on the eight: two T-shapes (genus 2), merged across cuts 5 cuboids, unmerged 8; 4 Type-1
# ill-points either way. These counts come from the decomposition and the surface maps, before
# the volumetric grid, so a coarse grid (--grid-nodes 2000) shows them as the default one does.
expect 0 "$BIN" gpc "$DATA/meshes/eight.off" -o "$TMP/ge.json" --stats-json "$TMP/ge_stats.json" --grid-nodes 2000 --quiet
contains "$TMP/ge_stats.json" "\"genus\": 2"
contains "$TMP/ge_stats.json" "\"t_shapes\": 2"
contains "$TMP/ge_stats.json" "\"cuboids\": 5"
contains "$TMP/ge_stats.json" "\"ill_points\": 4"
contains "$TMP/ge_stats.json" "\"flipped_triangles\": 0"
expect 0 "$BIN" gpc "$DATA/meshes/eight.off" -o "$TMP/ge8.json" --stats-json "$TMP/ge8_stats.json" --no-merge --grid-nodes 2000 --quiet
contains "$TMP/ge8_stats.json" "\"cuboids\": 8"
# The eight's level-set cuts are already the shortest (none moves): the stats say so, and
# --level-set-cuts gives the same domain.
contains "$TMP/ge_stats.json" "\"tightened_cuts\": 0"
has_keys "$TMP/ge_stats.json" cut_length_rel cut_disc_intersections
expect 0 "$BIN" gpc "$DATA/meshes/eight.off" -o "$TMP/gel.json" --level-set-cuts --grid-nodes 2000 --quiet
same_bytes "$TMP/ge.json" "$TMP/gel.json" "--level-set-cuts changed the eight's domain"
