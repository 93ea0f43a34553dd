#!/usr/bin/env bash
# Builds the libFuzzer targets (tools/fuzz) in ./build-fuzz with ASan and
# UBSan and runs each for SECONDS (default 30) from a seed corpus of every
# .osl in the project (and ../shared, for long runs), and the project's IR; the front-end
# fuzzer mutates with OSL's tokens (tools/fuzz/osl.dict). Exits non-zero on
# any finding (crash, an input over 180 s, sanitizer report) or when a fuzzer
# fails; reproducers land in build-fuzz/findings.
#   scripts/fuzz.sh [SECONDS] [FrontendFuzzer|OslOptFuzzer]   (default: both)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
only=${2:-}
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if [ ! -f build-fuzz/build.ninja ]; then
  cmake -G Ninja -S . -B build-fuzz \
    -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_COMPILER=clang-19 -DCMAKE_CXX_COMPILER=clang++-19 \
    -DLLVM_USE_LINKER=lld \
    -DMLIR_DIR=/usr/lib/llvm-19/lib/cmake/mlir \
    -DOSL_MLIR_FUZZERS=ON -DOSL_MLIR_BUILD_TESTS=OFF \
    "${launcher[@]}"
fi
ninja -C build-fuzz -j2 osl-fuzz-FrontendFuzzer osl-fuzz-OslOptFuzzer

# An input may take 180 s: conformance/tools/noise_probe.osl, a seed,
# indexes a 400-element array 180 times, each a chain of 400 selects
# (arrays are SSA values until memory-backed arrays, issue 17): 6.7 s to
# compile in release, 15 s under the sanitizers on an idle machine, and
# 62 s for a mutation of it while two builds shared the machine's two
# cores (measured: two 30-minute runs stopped on it as a "timeout"). A
# hang still shows, at 180 s.
run() { # name extra-flags... -- seed-dirs...
  local name=$1; shift
  local corpus=build-fuzz/corpus/$name findings=build-fuzz/findings/$name
  local log=build-fuzz/$name.log flags=()
  while [ "$1" != "--" ]; do flags+=("$1"); shift; done; shift
  mkdir -p "$corpus" "$findings"
  echo "== $name: ${seconds}s"
  local rc=0
  build-fuzz/bin/osl-fuzz-$name "$corpus" "$@" "${flags[@]}" -max_total_time="$seconds" \
    -timeout=180 -report_slow_units=180 -rss_limit_mb=4096 -max_len=8192 -print_final_stats=1 \
    -artifact_prefix="$findings/" >"$log" 2>&1 || rc=$?
  grep -E "^(#[0-9]+ *DONE|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY|Done)" "$log" || true
  # A finding leaves a file; any other failure of the fuzzer (a bad flag,
  # an unreadable seed, a crash outside an input) shows in its status.
  if compgen -G "$findings/*" >/dev/null; then
    echo "FINDING in $name:"; ls "$findings"; return 1
  fi
  if [ "$rc" -ne 0 ]; then
    echo "$name exited with status $rc; the end of $log:"; tail -20 "$log"; return 1
  fi
}
# Seeds: every shader of the project, and for runs of 5 minutes or more
# those of ../shared when it is beside the clone (the conformance corpus,
# the render scenes, OSL's testsuite): libFuzzer runs every seed before it
# starts, which takes minutes under the sanitizers for ../shared's ~700.
rm -rf build-fuzz/seeds
mkdir -p build-fuzz/seeds/osl build-fuzz/seeds/mlir
seed_dirs=(shaders test conformance examples render)
if [ "$seconds" -ge 300 ]; then
  for d in ../shared/conformance ../shared/render ../shared/osl-testsuite; do
    if [ -d "$d" ]; then seed_dirs+=("$d"); fi
  done
fi
n=0
while IFS= read -r -d '' f; do
  n=$((n + 1)); cp "$f" "build-fuzz/seeds/osl/$n-$(basename "$f")"
done < <(find "${seed_dirs[@]}" -name '*.osl' -size -8k -print0 2>/dev/null)
find test -name '*.mlir' -exec cp {} build-fuzz/seeds/mlir/ \;
echo "seeds: $n shaders, $(ls build-fuzz/seeds/mlir | wc -l) IR files"
status=0
if [ -z "$only" ] || [ "$only" = FrontendFuzzer ]; then
  run FrontendFuzzer -dict=tools/fuzz/osl.dict -- build-fuzz/seeds/osl || status=1
fi
if [ -z "$only" ] || [ "$only" = OslOptFuzzer ]; then
  run OslOptFuzzer -- build-fuzz/seeds/mlir || status=1
fi
exit $status
