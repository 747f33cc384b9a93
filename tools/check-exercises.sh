#!/usr/bin/env bash
# CI check that the exercise tests are not vacuous: built against the untouched stubs, every
# test case of every exercise must fail. (Against the solutions they run in the normal ctest.)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-ci-stubs
# Unoptimised: these tests only have to fail, and -O0 compiles the Eigen-heavy libraries fastest.
cmake -S . -B "$build" -DLEGKIT_EXERCISE_IMPL=stubs -DLEGKIT_BUILD_BENCH=OFF \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O0 >/dev/null
targets=$(sed -n 's/^legkit_exercise_test(\(ex[0-9_]*\) .*/test_\1/p' tests/exercises/CMakeLists.txt)
[[ -n "$targets" ]] || { echo "check-exercises: no exercise tests found" >&2; exit 1; }
# shellcheck disable=SC2086
cmake --build "$build" -j"$(nproc)" --target $targets
status=0
for t in $targets; do
  exe=$(find "$build" -type f -name "$t" -perm -u+x | head -n 1)
  total=$("$exe" --list-test-names-only | grep -c . || true)  # Catch exits with the count
  summary=$("$exe" 2>&1 | grep -E '^test cases:' || true)
  if [[ "$summary" =~ ^test\ cases:\ +${total}\ \|\ +${total}\ failed ]]; then
    echo "ok   $t: all $total test cases fail against the stub"
  else
    echo "FAIL $t: expected all $total test cases to fail against the stub, got: ${summary:-no summary}"
    status=1
  fi
done
exit $status
