#!/usr/bin/env bash
# Builds osl-run with AddressSanitizer and UndefinedBehaviorSanitizer in
# ./build-asan (OSL_MLIR_SANITIZE) and runs the conformance corpus (every
# `pass` test of test/conformance/status.txt, widths 1/4/8/16) and, when it
# is beside the clone, OSL's testsuite with it. The kernel cache starts
# empty so every shader goes through the instrumented compiler. Exits
# non-zero when any sanitizer report (ASan, LeakSanitizer, UBSan) was
# written or a test run failed; reports are kept in build-asan/reports.
#   scripts/sanitize.sh [conformance] [testsuite]   (default: both)
set -euo pipefail
cd "$(dirname "$0")/.."
parts=("$@")
if [ ${#parts[@]} -eq 0 ]; then parts=(conformance testsuite); fi
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if [ ! -f build-asan/build.ninja ]; then
  cmake -G Ninja -S . -B build-asan \
    -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_COMPILER=clang-19 -DCMAKE_CXX_COMPILER=clang++-19 \
    -DLLVM_USE_LINKER=lld \
    -DMLIR_DIR=/usr/lib/llvm-19/lib/cmake/mlir \
    -DOSL_MLIR_SANITIZE=ON -DOSL_MLIR_BUILD_TESTS=OFF \
    "${launcher[@]}"
fi
ninja -C build-asan -j2 osl-run

osl_run=$PWD/build-asan/bin/osl-run
reports=$PWD/build-asan/reports
rm -rf "$reports" build-asan/kernel-cache
mkdir -p "$reports"
# Each process writes its report, if any, to a file of its own (the test
# runners capture stderr, so a report there could go unseen).
export ASAN_OPTIONS="log_path=$reports/asan:detect_leaks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="log_path=$reports/ubsan:print_stacktrace=1:halt_on_error=1"
export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-19/bin/llvm-symbolizer
export OSL_MLIR_CACHE_DIR=$PWD/build-asan/kernel-cache

status=0
for part in "${parts[@]}"; do
  start=$SECONDS
  case $part in
    conformance)
      tests=$(sed -nE 's/^([A-Za-z0-9_]+\/[A-Za-z0-9_]+) +pass *$/\1/p' test/conformance/status.txt)
      echo "== conformance: $(echo "$tests" | wc -l) tests at widths 1, 4, 8, 16"
      log=build-asan/conformance.log
      # One line per test; xargs exits non-zero when any test failed.
      echo "$tests" | xargs -P 2 -I{} sh -c \
        'python3 test/conformance/run_test.py --osl-run "$0" --corpus conformance --test {} \
           >/dev/null 2>&1 && echo "PASS {}" || echo "FAIL {}"' "$osl_run" >"$log" || true
      echo "$(grep -c '^PASS' "$log") passed, $(grep -c '^FAIL' "$log") failed" \
           "($((SECONDS - start)) s)"
      if grep '^FAIL' "$log"; then status=1; fi
      ;;
    testsuite)
      if [ ! -f ../shared/osl-testsuite/runtest.py ]; then
        echo "== testsuite: ../shared/osl-testsuite is not there; skipped"; continue
      fi
      echo "== OSL testsuite"
      python3 test/osl-testsuite/run_testsuite.py --suite ../shared/osl-testsuite \
        --osl-run "$osl_run" -j 2 >build-asan/testsuite.log 2>&1 || status=1
      tail -3 build-asan/testsuite.log
      echo "($((SECONDS - start)) s)"
      ;;
    *) echo "unknown part '$part' (conformance, testsuite)"; exit 2 ;;
  esac
done

count=$(find "$reports" -type f | wc -l)
echo "sanitizer reports: $count"
if [ "$count" -ne 0 ]; then
  for f in "$reports"/*; do echo "--- $f"; head -40 "$f"; done
  status=1
fi
exit $status
