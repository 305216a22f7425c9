#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# check_layering.sh must pass a tree with downward includes and name an upward one.
set -u
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/core/linalg" "$tmp/core/spline" "$tmp/core/pipeline"
printf '#include "core/linalg/a.h"\n' > "$tmp/core/spline/b.h"
printf '#pragma once\n' > "$tmp/core/linalg/a.h"
printf '#pragma once\n' > "$tmp/core/pipeline/c.h"
bash "$here/check_layering.sh" "$tmp" >/dev/null || { echo "FAIL: a downward include was refused"; exit 1; }
printf '#include "core/pipeline/c.h"\n' > "$tmp/core/linalg/d.cpp"
out=$(bash "$here/check_layering.sh" "$tmp") && { echo "FAIL: an upward include passed"; exit 1; }
case $out in *"core/linalg/d.cpp:1: core/linalg may not include core/pipeline"*) ;;
  *) echo "FAIL: unexpected message: $out"; exit 1 ;; esac
echo "check_layering self-test: ok"
