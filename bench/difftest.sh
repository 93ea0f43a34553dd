#!/usr/bin/env bash
# Runs the differential tester on COUNT generated shaders from SEED, split
# over JOBS processes: each shader's SIMD kernels (widths 1, 4, 8, 16) must
# equal the one-point reference bit for bit.
#   bench/difftest.sh [COUNT=1000] [SEED=1] [JOBS=2]
set -euo pipefail
cd "$(dirname "$0")/.."
count=${1:-1000}; seed=${2:-1}; jobs=${3:-2}
per=$(( (count + jobs - 1) / jobs ))
pids=()
start=$(date +%s)
for ((j = 0; j < jobs; ++j)); do
  s=$(( seed + j * per )); n=$(( per < count - j * per ? per : count - j * per ))
  (( n > 0 )) || continue
  python3 test/difftest/run.py --difftest build/bin/osl-difftest --seed "$s" --count "$n" \
    > "build/difftest.$j.log" 2>&1 &
  pids+=($!)
done
status=0
for p in "${pids[@]}"; do wait "$p" || status=1; done
cat build/difftest.*.log
echo "seeds $seed..$(( seed + count - 1 )): $(( $(date +%s) - start )) s, exit $status"
exit $status
