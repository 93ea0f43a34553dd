#!/usr/bin/env bash
# The main job from a fresh Debian 12 machine: install, build, then shade
# the article's marble on a 512x512 grid and write marble.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
build/bin/osl-run shaders/marble.osl -g 512 512 -o Cout marble.png --stats
echo "wrote $(pwd)/marble.png"
