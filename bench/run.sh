#!/usr/bin/env bash
# ns per shading point (one thread, 512x512) at widths 1/4/8/16 and JIT
# time, for the shipped shaders and the conformance perf/ shaders that the
# front end supports. Build first (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
exec build/bin/osl-bench "$@" shaders/*.osl conformance/perf/marble.osl \
  conformance/perf/wood.osl conformance/perf/brick.osl conformance/perf/voronoi.osl
