#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian packages volspline needs, only those that are missing.
# usage: tests/setup_deps.sh [--web]   (--web adds chromium and npm for the browser tests)
set -euo pipefail
packages=(cmake make g++ clang libclang-rt-14-dev libeigen3-dev doctest-dev libtinygltf-dev libstb-dev
          nlohmann-json3-dev emscripten nodejs)
if [ "${1:-}" = "--web" ]; then packages+=(chromium npm); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
