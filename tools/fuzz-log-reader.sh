#!/usr/bin/env bash
# Fuzzes the log reader (fuzz/log_reader_fuzz.cpp) with libFuzzer for a number of seconds
# (default 60), starting from the seed corpus in fuzz/corpus/. Any crash, sanitizer report or
# broken read/write round trip fails the script and leaves the input in build-fuzz/artifacts/.
#   tools/fuzz-log-reader.sh [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
build=build-fuzz
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DLEGKIT_FUZZ=ON -DLEGKIT_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target log_reader_fuzz
corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
cp fuzz/corpus/* "$corpus"/
mkdir -p "$build/artifacts"
# -max_len: long enough for a header and a few rows of every layout. The whole output goes to
# build-fuzz/fuzz.log; shown are its end without the recommended dictionary (which would push the
# coverage line and a crash report out of view), and the size of the corpus it grew.
status=0
"$build/fuzz/log_reader_fuzz" "$corpus" -max_total_time="$seconds" -max_len=8192 \
  -artifact_prefix="$build/artifacts/" -print_final_stats=1 >"$build/fuzz.log" 2>&1 || status=$?
grep -v '^"' "$build/fuzz.log" | tail -n 40
echo "corpus: $(find "$corpus" -type f | wc -l) files, $(du -sk "$corpus" | cut -f1) kB"
[ "$status" -eq 0 ] || echo "FAILED: the fuzzer exited with $status (inputs in $build/artifacts/)"
exit "$status"
