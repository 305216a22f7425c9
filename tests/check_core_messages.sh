#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Core messages name option fields (`max_rms_rel`), never the flags of one front end (--max-rms):
# the browser has no flags, and each front end translates the fields into its own words. Prints
# every string literal in core/ that holds a --flag as file:line and exits 1.
#   usage: check_core_messages.sh [SOURCE_ROOT]
set -uo pipefail
root=${1:-$(dirname "$0")/..}
cd "$root" || { echo "check_core_messages: no folder $root"; exit 2; }
[ -d core ] || { echo "check_core_messages: $root has no core/"; exit 2; }
# A double-quoted literal (escapes allowed) holding "--" then a letter, after code and whole
# literals only (not inside a // comment).
hits=$(find core -name '*.h' -o -name '*.cpp' | sort |
  xargs grep -nE '^([^/"]|/[^/]|"([^"\\]|\\.)*")*"(([^"\\]|\\.)*[^-[:alnum:]_])?--[a-z][a-z0-9-]*' || true)
if [ -n "$hits" ]; then
  echo "core messages that name CLI flags (name the option field instead):"
  echo "$hits"
  exit 1
fi
echo "core messages: ok"
