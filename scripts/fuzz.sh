#!/usr/bin/env bash
# Builds the libFuzzer targets (tools/fuzz) in ./build-fuzz with ASan and
# UBSan and runs each for SECONDS (default 30) from a seed corpus of the
# project's own shaders and IR. Exits non-zero on any finding (crash, hang
# over 10 s, sanitizer report); reproducers land in build-fuzz/findings.
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
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

run() { # name seed-dirs...
  local name=$1; shift
  local corpus=build-fuzz/corpus/$name findings=build-fuzz/findings/$name
  mkdir -p "$corpus" "$findings"
  echo "== $name: ${seconds}s"
  build-fuzz/bin/osl-fuzz-$name "$corpus" "$@" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=4096 -max_len=8192 -print_final_stats=1 -artifact_prefix="$findings/" \
    2>&1 | grep -E "^(#[0-9]+ *DONE|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY|Done)" || true
  # libFuzzer's exit status is lost in the pipe; a finding leaves a file.
  if compgen -G "$findings/*" >/dev/null; then
    echo "FINDING in $name:"; ls "$findings"; return 1
  fi
}
mkdir -p build-fuzz/seeds/osl build-fuzz/seeds/mlir
find shaders test conformance -name '*.osl' -exec cp {} build-fuzz/seeds/osl/ \;
find test -name '*.mlir' -exec cp {} build-fuzz/seeds/mlir/ \;
status=0
run FrontendFuzzer build-fuzz/seeds/osl || status=1
run OslOptFuzzer build-fuzz/seeds/mlir || status=1
exit $status
