#!/usr/bin/env bash
# Fuzzes one of the kit's readers with libFuzzer for a number of seconds (default 60), starting
# from its seed corpus. Any crash, sanitizer report, broken read/write round trip or badly formed
# error fails the script and leaves the input in build-fuzz/artifacts/<reader>/.
#   tools/fuzz-reader.sh <reader> [seconds]
# reader   target (fuzz/)              seed corpus            what it reads
#   log    log_reader_fuzz.cpp         fuzz/corpus/           io/log_reader.hpp (a CSV log)
#   settings settings_fuzz.cpp         fuzz/corpus-settings/  estimation/settings.hpp (YAML)
#   poses  pose_log_fuzz.cpp           fuzz/corpus-poses/     estimation/fusion/pose_log.hpp
# Extra arguments after the seconds go to libFuzzer (-jobs=1, -seed=N, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
reader="${1:-}"
case "$reader" in
  log) target=log_reader_fuzz seeds=fuzz/corpus max_len=8192 ;;
  settings) target=settings_fuzz seeds=fuzz/corpus-settings max_len=16384 ;;
  poses) target=pose_log_fuzz seeds=fuzz/corpus-poses max_len=8192 ;;
  *)
    echo "usage: tools/fuzz-reader.sh log|settings|poses [seconds] [libFuzzer options]" >&2
    exit 2
    ;;
esac
seconds="${2:-60}"
shift $(($# < 2 ? $# : 2))
build=build-fuzz
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DLEGKIT_FUZZ=ON -DLEGKIT_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target "$target"
corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
cp "$seeds"/* "$corpus"/
artifacts="$build/artifacts/$reader"
mkdir -p "$artifacts"
# -max_len: long enough for every seed (a header and a few rows of every layout; the full default
# settings file). The whole output goes to build-fuzz/fuzz-<reader>.log; shown are its end without
# the recommended dictionary (which would push the coverage line and a crash report out of view),
# and the size of the corpus it grew.
log="$build/fuzz-$reader.log"
status=0
"$build/fuzz/$target" "$corpus" -max_total_time="$seconds" -max_len="$max_len" \
  -artifact_prefix="$artifacts/" -print_final_stats=1 "$@" >"$log" 2>&1 || status=$?
grep -v '^"' "$log" | tail -n 40
echo "corpus: $(find "$corpus" -type f | wc -l) files, $(du -sk "$corpus" | cut -f1) kB"
[ "$status" -eq 0 ] || echo "FAILED: the $reader fuzzer exited with $status (inputs in $artifacts/)"
exit "$status"
