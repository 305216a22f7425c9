#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# CLI integration tests: exit codes, messages and outputs of the built volspline binary.
# usage: cli_test.sh VOLSPLINE_BIN SOURCE_DIR SHARED_DATA_DIR [CASE.sh...]
# Runs the named scripts of tests/cli/cases/ (ctest runs one per test), or all of them.
set -u
BIN=$1; SRC=$2; DATA=$3; shift 3
TMP=$(mktemp -d); trap 'rm -rf "$TMP"' EXIT
pass=0; fail=0
ok()   { pass=$((pass+1)); }
bad()  { fail=$((fail+1)); echo "FAIL: $*"; }
# expect CODE CMD... : runs CMD, checks the exit code, keeps stdout/stderr in $TMP/out, $TMP/err
expect() {
  local want=$1; shift
  "$@" >"$TMP/out" 2>"$TMP/err"; local got=$?
  if [ "$got" = "$want" ]; then ok; else bad "exit $got (want $want): $* :: $(head -c 300 "$TMP/err")"; fi
}
# contains FILE TEXT
contains() { if grep -qF -- "$2" "$1"; then ok; else bad "'$2' not in $1: $(head -c 300 "$1")"; fi; }
# has_keys JSON KEY... : every KEY appears as "KEY" in the file
has_keys() { local file=$1 key; shift; for key in "$@"; do contains "$file" "\"$key\""; done; }
# is_glb FILE : starts with the GLB magic
is_glb() { if [ "$(head -c 4 "$1")" = "glTF" ]; then ok; else bad "$(basename "$1") is not a GLB file"; fi; }
# same_bytes A B MESSAGE : the two files are byte-identical
same_bytes() { if cmp -s "$1" "$2"; then ok; else bad "$3"; fi; }

cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=($(cd "$SRC/tests/cli/cases" && ls -- *.sh))
for c in "${cases[@]}"; do
  f=$SRC/tests/cli/cases/$c
  if [ -f "$f" ]; then . "$f"; else bad "no case script $f"; fi
done

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
