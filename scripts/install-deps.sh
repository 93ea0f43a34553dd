#!/usr/bin/env bash
# Installs everything osl-mlir needs on Debian 12 (bookworm). Idempotent; needs root or sudo.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
PKGS=(cmake ninja-build ccache pkg-config python3
      clang-19 lld-19 llvm-19-dev llvm-19-tools libmlir-19-dev mlir-19-tools
      libclang-rt-19-dev
      libopenimageio-dev openimageio-tools libtiff-dev libopenexr-dev libpng-dev libgtest-dev libopenvdb-dev libboost-dev
      python3-matplotlib python3-distributed)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
