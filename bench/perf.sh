#!/usr/bin/env bash
# Every figure of the performance issue in one command: marble against the
# hand-vectorized limit, ns per point and SIMD speedup per shader, JIT time
# and the kernel cache, thread scaling and peak memory, active lanes of the
# divergent shaders. Build first (scripts/build.sh). Needs clang++-19.
#   bench/perf.sh [--rounds N]
set -euo pipefail
exec python3 "$(dirname "$0")/perf.py" "$@"
