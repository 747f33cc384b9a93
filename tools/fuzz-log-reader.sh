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
# -max_len: long enough for a header and a few rows of every layout.
"$build/fuzz/log_reader_fuzz" "$corpus" -max_total_time="$seconds" -max_len=8192 \
  -artifact_prefix="$build/artifacts/" -print_final_stats=1 2>&1 | tail -n 25
