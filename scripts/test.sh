#!/usr/bin/env bash
# Installs, builds and runs every test: GoogleTest suites, lit, the
# end-to-end width tests, the conformance corpus, the differential tester
# and the package check; then builds the libFuzzer targets and runs each
# for a short fixed time (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
(cd build && ctest -j2 --output-on-failure)
scripts/fuzz.sh "${OSL_FUZZ_SECONDS:-20}"
