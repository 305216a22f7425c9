#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian packages volspline needs, only those that are missing.
# usage: tests/setup_deps.sh [--web | --native]
#   --web adds chromium and npm for the browser tests; --native installs only what the native
#   Release build needs (the demo: no clang, emscripten or node).
set -euo pipefail
packages=(cmake make g++ libeigen3-dev doctest-dev libtinygltf-dev libstb-dev nlohmann-json3-dev zlib1g-dev)
if [ "${1:-}" != "--native" ]; then packages+=(clang libclang-rt-14-dev emscripten python3-vtk9); fi
if [ "${1:-}" = "--web" ]; then packages+=(chromium); fi
missing=()
# node and npm may come from another source (e.g. a nodejs build that bundles npm): look for the
# commands, and install Debian's packages only when they are absent.
if [ "${1:-}" != "--native" ]; then command -v node >/dev/null 2>&1 || missing+=(nodejs); fi
if [ "${1:-}" = "--web" ]; then command -v npm >/dev/null 2>&1 || missing+=(npm); fi
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
