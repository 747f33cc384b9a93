#!/usr/bin/env bash
# CI check that the exercise tests are not vacuous and that their output stays readable: built
# against the untouched stubs (the test_<id>_stub programs, in the README's tree build/, or
# $LEGKIT_BUILD), every test case of every exercise must fail, each with exactly one failure.
# The Python variants likewise: pytest over tests/exercises/python/test_<id>.py against the
# untouched python/exercise.py must report every test case failed (and none passed or in error).
# (Against the solutions both run in the normal ctest.)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${LEGKIT_BUILD:-build}"
[[ -f "$build/CMakeCache.txt" ]] || cmake -S . -B "$build" >/dev/null
ids=$(sed -n 's/^legkit_exercise_test(\(ex[0-9X_]*\) .*/\1/p' tests/exercises/CMakeLists.txt)
[[ -n "$ids" ]] || { echo "check-exercises: no exercise tests found" >&2; exit 1; }
targets=$(for id in $ids; do echo "test_${id}_stub"; done)
# shellcheck disable=SC2086
cmake --build "$build" -j"$(nproc)" --target $targets
status=0
for t in $targets; do
  exe="$build/tests/exercises/$t"
  total=$("$exe" --list-test-names-only | grep -c . || true)  # Catch exits with the count
  summary=$("$exe" 2>&1 | grep -E '^(test cases|assertions):' | tr '\n' ' ' || true)
  # Catch prints "assertions: N | N failed" when none passed, "N | P passed | F failed" otherwise.
  if [[ "$summary" =~ ^test\ cases:\ +${total}\ \|\ +${total}\ failed\ +assertions:\ +([0-9]+)\ \|\ (.*\ )?([0-9]+)\ failed ]] &&
    [[ "${BASH_REMATCH[3]}" == "$total" ]]; then
    echo "ok   $t: all $total test cases fail against the stub, one failure each"
  else
    echo "FAIL $t: expected all $total test cases to fail against the stub with one failure each, got: ${summary:-no summary}"
    status=1
  fi
done

if grep -q '^LEGKIT_PYTHON:BOOL=OFF$' "$build/CMakeCache.txt"; then
  echo "FAIL the Python exercises: $build/ is configured without the Python package (LEGKIT_PYTHON=OFF)"
  exit 1
fi
cmake --build "$build" -j"$(nproc)" --target legkit_python
python=/usr/bin/python3  # Debian's, with NumPy and pytest
[[ -x "$python" ]] || python=python3
for file in tests/exercises/python/test_*.py; do
  pytest=(env PYTHONPATH="$build/python" "$python" -m pytest -q -p no:cacheprovider "$file")
  total=$("${pytest[@]}" --collect-only | grep -c '::' || true)
  summary=$("${pytest[@]}" 2>&1 | tail -n 1 || true)
  # pytest's last line is "N failed in 0.31s" only when no test case passed or had an error.
  if [[ "$summary" =~ ^([0-9]+)\ failed\ in\  ]] && [[ "${BASH_REMATCH[1]}" == "$total" ]] &&
    ((total > 0)); then
    echo "ok   $file: all $total test cases fail against the stub"
  else
    echo "FAIL $file: expected all $total test cases to fail against the stub, got: ${summary:-no summary}"
    status=1
  fi
done
exit $status
