# vol2spline: help, outputs and stats keys on the sample volume, bad input exits 2.
VOL="$SRC/samples/volumes/bucky_32x32x32_uint8.raw"
expect 0 "$BIN" vol2spline --help
contains "$TMP/out" "vol2spline VOLUME -o OUT.json"
expect 0 "$BIN" vol2spline "$VOL" -o "$TMP/v.json" --vtk "$TMP/v.vtu" --vti "$TMP/v.vti" --stats-json "$TMP/v_stats.json" --max-rms 0.1 --quiet
has_keys "$TMP/v_stats.json" density_rms_rel density_max_rel control_points voxels patches corners frame_smoothness_initial frame_smoothness_final constraint_angle_max_deg min_scaled_jacobian stop_reason max_control_points curve times_s
contains "$TMP/v_stats.json" "\"voxels\": 32768"
contains "$TMP/v_stats.json" "\"stop_reason\": \"target\""
contains "$TMP/v_stats.json" "\"max_control_points\": 2048"
contains "$TMP/v.json" "\"dimension\": 4"
contains "$TMP/v.vtu" "Name=\"density\""
# The density spline as Bézier cells and the voxels as ImageData, read back by VTK (python3-vtk9).
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_bezier_vtu.py" "$BIN" "$TMP/v.json" "$TMP/v.vtu" --samples 100
contains "$TMP/out" "check_bezier_vtu: ok"
expect 0 /usr/bin/python3 "$SRC/tests/cli/check_vti.py" "$TMP/v.vti" 32 32 32
contains "$TMP/out" "check_vti: ok"
expect 0 "$BIN" eval "$TMP/v.json" --uvw 15.5,15.5,15.5
# The same bytes given as a raw file with explicit dims and type.
cp "$VOL" "$TMP/volume.raw"
expect 0 "$BIN" vol2spline "$TMP/volume.raw" --dims 32,32,32 --type uint8 --spacing 1,1,2 -o "$TMP/w.json" --max-rms 0.2 --max-levels 1 --quiet
# The same bytes as a gzip-encoded NRRD (attached data, compressed by the gzip command): the same spline.
{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 32 32 32\nencoding: gzip\n\n'; gzip -c "$VOL"; } > "$TMP/bucky.nrrd"
expect 0 "$BIN" vol2spline "$TMP/bucky.nrrd" -o "$TMP/g.json" --max-rms 0.1 --quiet
same_bytes "$TMP/g.json" "$TMP/v.json" "gzip NRRD spline differs from the raw one"
head -c 2000 "$TMP/bucky.nrrd" > "$TMP/bucky_cut.nrrd"
expect 2 "$BIN" vol2spline "$TMP/bucky_cut.nrrd" -o "$TMP/x.json" --quiet
contains "$TMP/err" "bucky_cut.nrrd: truncated gzip data"
# Bad input and usage: exit 2 with a message.
expect 2 "$BIN" vol2spline "$TMP/volume.raw" -o "$TMP/x.json" --quiet
expect 2 "$BIN" vol2spline "$TMP/volume.raw" --dims 32,32,31 --type uint8 -o "$TMP/x.json" --quiet
contains "$TMP/err" "volume.raw"
head -c 1000 "$VOL" > "$TMP/cut_32x32x32_uint8.raw"
expect 2 "$BIN" vol2spline "$TMP/cut_32x32x32_uint8.raw" -o "$TMP/x.json" --quiet
contains "$TMP/err" "cut_32x32x32_uint8.raw"
expect 2 "$BIN" vol2spline "$TMP/missing_8x8x8_uint8.raw" -o "$TMP/x.json" --quiet
expect 2 "$BIN" vol2spline "$VOL" -o "$TMP/x.json" --param magic --quiet
contains "$TMP/err" "identity or aligned"
expect 2 "$BIN" vol2spline "$VOL" --quiet
contains "$TMP/err" "needs -o"
expect 2 "$BIN" vol2spline "$VOL" -o "$TMP/x.json" --dims 32,32 --quiet
contains "$TMP/err" "three comma-separated"
expect 2 "$BIN" vol2spline "$VOL" -o "$TMP/x.json" --max-rms -1 --quiet
contains "$TMP/err" "max_rms_rel"
expect 2 "$BIN" vol2spline "$VOL" -o "$TMP/x.json" --min-gain-rate -1 --quiet
contains "$TMP/err" "min_gain_rate"
