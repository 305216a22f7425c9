# vol2spline --threads: the same output bytes for every thread count (fixed work partitions,
# sums in fixed order), for both parameterizations; a count below 1 is bad usage.
VOL="$SRC/samples/volumes/bucky_32x32x32_uint8.raw"
expect 0 "$BIN" vol2spline "$VOL" -o "$TMP/t1.json" --max-rms 0.05 --threads 1 --quiet
expect 0 "$BIN" vol2spline "$VOL" -o "$TMP/t2.json" --max-rms 0.05 --threads 2 --quiet
same_bytes "$TMP/t1.json" "$TMP/t2.json" "identity spline differs between --threads 1 and 2"
expect 0 "$BIN" vol2spline "$VOL" -o "$TMP/a1.json" --param aligned --max-levels 2 --threads 1 --quiet
expect 0 "$BIN" vol2spline "$VOL" -o "$TMP/a3.json" --param aligned --max-levels 2 --threads 3 --quiet
same_bytes "$TMP/a1.json" "$TMP/a3.json" "aligned spline differs between --threads 1 and 3"
expect 2 "$BIN" vol2spline "$VOL" -o "$TMP/x.json" --threads 0 --quiet
contains "$TMP/err" "threads must be in [1, 256]"
