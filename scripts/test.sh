#!/usr/bin/env bash
# Installs, builds and runs every test: GoogleTest suites, lit, the
# end-to-end width tests, the conformance subset and the package check.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
ctest -j2 --output-on-failure
