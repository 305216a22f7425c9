#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs every reader fuzz target (meshes, images, volumes, spline JSON) over its saved corpus
# (regressions), then fuzzes each for SECONDS. Fails on any crash; new crash inputs are left as
# BUILD_DIR/fuzz-artifacts/<reader>/crash-*. The readers run as many at a time as there are cores
# (each fuzzer is one process on one core), so each still gets SECONDS of its own.
# usage: run_fuzz.sh BUILD_DIR SECONDS
set -u
BUILD=${1:?usage: run_fuzz.sh BUILD_DIR SECONDS}
SECONDS_EACH=${2:?usage: run_fuzz.sh BUILD_DIR SECONDS}
HERE=$(cd "$(dirname "$0")" && pwd)
PARALLEL=$(nproc 2>/dev/null || echo 1)

# fuzz_reader NAME: prints one line, ok: or FAIL:, and returns 1 on a failure.
fuzz_reader() {
  local reader=$1 bin corpus work artifacts
  bin=$(find "$BUILD" -type f -name "fuzz_$reader" -perm -u+x | head -n 1)
  if [ -z "$bin" ]; then echo "FAIL: fuzz_$reader not built in $BUILD"; return 1; fi
  corpus=$HERE/corpus/$reader
  work=$BUILD/fuzz-work/$reader
  artifacts=$BUILD/fuzz-artifacts/$reader/
  mkdir -p "$work" "$artifacts"
  local opts=(-rss_limit_mb=2048 -max_len=65536 -timeout=20 -artifact_prefix="$artifacts")
  # Saved corpus first: every file must run clean.
  if ! "$bin" "${opts[@]}" -runs=0 "$corpus" > "$work.regress.log" 2>&1; then
    echo "FAIL: fuzz_$reader crashed on its saved corpus (see $work.regress.log)"; return 1
  fi
  if [ "$SECONDS_EACH" -gt 0 ]; then
    # New inputs go to the scratch dir; the saved corpus is only read.
    if "$bin" "${opts[@]}" -max_total_time="$SECONDS_EACH" -print_final_stats=1 "$work" "$corpus" > "$work.log" 2>&1; then
      echo "ok: fuzz_$reader $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$work.log" | grep -o '[0-9]*$') runs in ${SECONDS_EACH}s"
    else
      echo "FAIL: fuzz_$reader crashed (see $work.log; input in $artifacts)"; return 1
    fi
  else
    echo "ok: fuzz_$reader corpus"
  fi
}

status=0
pids=()
for reader in obj off ply stl gltf image volume spline_json; do
  if [ "${#pids[@]}" -ge "$PARALLEL" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
  fuzz_reader "$reader" &
  pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
exit $status
