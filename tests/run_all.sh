#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The test command: installs what is missing, builds every configuration and runs every test.
#   1. native Release build: unit tests, CLI integration tests (ctest); then samples/run_demo.sh
#   2. clang Debug build under AddressSanitizer + UndefinedBehaviorSanitizer: the same tests
#   3. libFuzzer targets from that build: the saved corpus, then a short bounded run per reader
#   4. WebAssembly build (em++): the core called from node
#   5. the static site in headless Chromium (playwright-core): upload, run, view, errors
# Ends with one line "N passed, M failed" counting the stages.
set -uo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=$(nproc)
FUZZ_SECONDS=${VOLSPLINE_FUZZ_SECONDS:-15}
bash tests/setup_deps.sh || { echo "setup failed"; echo "0 passed, 1 failed"; exit 1; }

passed=0; failed=0; failures=""
stage() {  # stage NAME COMMAND...
  local name=$1; shift
  echo "=== $name"
  local t0=$SECONDS
  if "$@"; then passed=$((passed+1)); echo "=== $name: ok ($((SECONDS-t0)) s)";
  else failed=$((failed+1)); failures="$failures $name"; echo "=== $name: FAILED ($((SECONDS-t0)) s)"; fi
}

native() {
  cmake --preset release >/dev/null &&
  cmake --build build/release -j"$JOBS" &&
  ctest --test-dir build/release --output-on-failure -j"$JOBS"
}
# The configurations are the presets of CMakePresets.json. One clang Debug build (preset sanitize,
# line tables only) serves both the sanitizer run and the fuzzers: ASan+UBSan everywhere, and the
# core's reader code also carries libFuzzer's coverage instrumentation (tests/fuzz/CMakeLists.txt).
sanitized() {
  cmake --preset sanitize >/dev/null &&
  cmake --build build/sanitize -j"$JOBS" &&
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build/sanitize --output-on-failure -j"$JOBS"
}
fuzz() {
  cmake --build build/sanitize -j"$JOBS" --target fuzz_targets &&
  bash tests/fuzz/run_fuzz.sh build/sanitize "$FUZZ_SECONDS"
}
wasm() {
  export NODE_PATH=/usr/share/nodejs
  emcmake cmake --preset wasm >/dev/null &&
  cmake --build build/wasm -j"$JOBS" &&
  node --no-experimental-fetch tests/wasm/node_smoke_test.cjs build/wasm/wasm/volspline_node.cjs "$ROOT" "$ROOT/../shared/data"
}

web_e2e() {
  export NODE_PATH=/usr/share/nodejs
  bash tests/setup_deps.sh --web &&
  emcmake cmake --preset wasm >/dev/null &&
  cmake --build build/wasm -j"$JOBS" --target volspline_site &&
  (cd tests/e2e && npm ci --no-audit --no-fund) &&
  { [ ! -x build/release/cli/volspline ] || node tests/e2e/validate_glb.cjs build/release/cli/volspline "$ROOT/../shared/data"; } &&
  node tests/e2e/run_e2e.cjs build/wasm/site --shared-data "$ROOT/../shared/data" --artifacts tests/artifacts
}

# The README's main command on a fresh build tree's CLI: every job on samples/ must succeed.
demo() { bash samples/run_demo.sh > build/demo.log 2>&1 || { tail -n 30 build/demo.log; return 1; }; }

stage native-release native
stage demo demo
stage asan-ubsan sanitized
stage fuzz fuzz
stage wasm-node wasm
stage web-e2e web_e2e

[ -n "$failures" ] && echo "failed stages:$failures"
echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
