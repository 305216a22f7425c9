# Lens job: outputs and stats JSON on the samples, every bad input exits 2 with a message.
IMG="$SRC/samples/images/camera.png"
for method in metric fisheye bifocal zoom; do
  expect 0 "$BIN" lens "$IMG" -o "$TMP/lens_$method.png" --roi circle:256,200,60 --grid 48 --method $method \
    --stats-json "$TMP/lens_$method.json" --quiet
  [ -s "$TMP/lens_$method.png" ] && ok || bad "no output image for $method"
  has_keys "$TMP/lens_$method.json" distortion_sum distortion_max distortion_sum_focus distortion_max_focus magnification_center flipped_triangles iterations ms_total ms_factorize ms_per_iteration
done
contains "$TMP/lens_metric.json" '"flipped_triangles": 0'
expect 0 "$BIN" lens "$SRC/samples/images/text.png" -o "$TMP/text.png" --roi rect:150,60,120,50 \
  --roi polygon:20,20,90,20,60,90 --grid 60 --alpha 0.01 --mesh-out "$TMP/text.obj" --quiet
contains "$TMP/text.obj" "vt "
expect 0 "$BIN" lens "$IMG" -o "$TMP/sq.png" --roi circle:256,256,60 --grid 40 --height 1 --square-boundary --quiet
expect 0 "$BIN" lens --help
contains "$TMP/out" "--magnification"

# Bad input: exit 2 and a message naming the problem.
expect 2 "$BIN" lens "$TMP/missing.png" -o "$TMP/x.png" --roi circle:10,10,5
contains "$TMP/err" "missing.png"
echo "not a png" > "$TMP/broken.png"
expect 2 "$BIN" lens "$TMP/broken.png" -o "$TMP/x.png" --roi circle:10,10,5
contains "$TMP/err" "not a PNG or JPEG image"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:900,10,5
contains "$TMP/err" "outside the 512x512 image"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:100,100,0
contains "$TMP/err" "radius must be positive"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:100,100,-4
contains "$TMP/err" "radius must be positive"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:100,100,20 --magnification 1
contains "$TMP/err" "magnification must be > 1"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:100,100,20 --magnification 1e6
contains "$TMP/err" "at most 16"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:100,100,20 --grid 3
contains "$TMP/err" "grid must be at least 4"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi blob:1,2
contains "$TMP/err" "unknown kind"
expect 2 "$BIN" lens "$IMG" --roi circle:100,100,20
contains "$TMP/err" "missing -o"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi circle:100,100,20 --method magic
contains "$TMP/err" "--method expects"
expect 2 "$BIN" lens "$IMG" -o "$TMP/x.png" --roi mask:"$TMP/nomask.png"
contains "$TMP/err" "nomask.png"
