#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The layering of the core, checked on every #include: a module may include only itself and the
# modules listed for it below (lower layers); core never includes cli/, wasm/ or tests/; cli/ and
# wasm/ include only core/ and themselves. Prints each offending include as file:line and exits 1.
#   usage: check_layering.sh [SOURCE_ROOT]
set -uo pipefail
root=${1:-$(dirname "$0")/..}
declare -A allowed=(
  [common]="common"
  [linalg]="common linalg"
  [mesh]="common linalg mesh"
  [polycube]="common linalg mesh polycube"
  [param]="common linalg mesh polycube param"
  [spline]="common linalg mesh polycube param spline"
  [volume]="common linalg mesh volume"
  [lens]="common linalg mesh lens"
  [io]="common linalg mesh polycube spline volume io"
  [pipeline]="common linalg mesh polycube param spline volume lens io pipeline"
)
status=0
complain() { echo "$1: $2"; status=1; }
cd "$root" || { echo "check_layering: no folder $root"; exit 2; }
[ -d core ] || { echo "check_layering: $root has no core/"; exit 2; }
while IFS= read -r -d '' file; do
  module=${file#core/}; module=${module%%/*}
  if [ -z "${allowed[$module]+x}" ]; then complain "$file" "module '$module' is not in tests/check_layering.sh"; continue; fi
  while IFS=: read -r line target; do
    case $target in
      core/*) dep=${target#core/}; dep=${dep%%/*}
              [[ " ${allowed[$module]} " == *" $dep "* ]] ||
                complain "$file:$line" "core/$module may not include core/$dep ($target)" ;;
      *) complain "$file:$line" "core includes '$target' (only core/... headers)" ;;
    esac
  done < <(grep -noE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[^"]+"' "$file" | sed -E 's/:.*"([^"]+)"$/:\1/')
done < <(find core -name '*.h' -o -name '*.cpp' | sort | tr '\n' '\0')
for adapter in cli wasm; do
  [ -d "$adapter" ] || continue
  while IFS= read -r -d '' file; do
    while IFS=: read -r line target; do
      case $target in core/*|$adapter/*) ;; *) complain "$file:$line" "$adapter includes '$target'" ;; esac
    done < <(grep -noE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[^"]+"' "$file" | sed -E 's/:.*"([^"]+)"$/:\1/')
  done < <(find "$adapter" -name '*.h' -o -name '*.cpp' | sort | tr '\n' '\0')
done
[ $status = 0 ] && echo "layering: ok"
exit $status
