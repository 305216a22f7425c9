#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on the bundled samples: installs what the native build needs if missing, builds
# the CLI (Release) and runs every job on samples/ (info, mesh2spline + eval, lens, vol2spline),
# writing results to build/demo/ and listing them at the end. Exits non-zero if any job fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tests/setup_deps.sh --native
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j"$(nproc)" --target volspline
VS=build/release/cli/volspline
OUT=build/demo; mkdir -p "$OUT"
for m in samples/meshes/*.off; do
  echo "== volspline info $m"
  "$VS" info "$m"
done
for m in samples/meshes/sphere.off samples/meshes/bimba.off; do
  name=$(basename "$m" .off)
  echo "== volspline mesh2spline $m"
  "$VS" mesh2spline "$m" -o "$OUT/$name.json" --vtk "$OUT/$name.vtu" --glb "$OUT/$name.glb" \
      --stats-json "$OUT/${name}_stats.json" --max-levels 2
  cat "$OUT/${name}_stats.json"; echo
  echo "== volspline eval $OUT/$name.json --uvw 0.5,0.5,0.5"
  "$VS" eval "$OUT/$name.json" --uvw 0.5,0.5,0.5
done
for img in samples/images/*.png; do
  [ -f "$img" ] || continue
  name=$(basename "$img" .png)
  echo "== volspline lens $img  (default ROI: a circle at the image centre)"
  "$VS" lens "$img" -o "$OUT/${name}_lens.png" --stats-json "$OUT/${name}_lens.json"
  cat "$OUT/${name}_lens.json"; echo
done
for vol in samples/volumes/*.raw; do
  [ -f "$vol" ] || continue
  name=$(basename "$vol" .raw)
  echo "== volspline vol2spline $vol"
  "$VS" vol2spline "$vol" -o "$OUT/$name.json" --vtk "$OUT/$name.vtu" --stats-json "$OUT/${name}_stats.json"
  cat "$OUT/${name}_stats.json"; echo
done
echo "== results in $(cd "$OUT" && pwd)/:"
ls -l "$OUT"
