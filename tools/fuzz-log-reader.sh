#!/usr/bin/env bash
# Fuzzes the log reader for a number of seconds (default 60): tools/fuzz-reader.sh log, kept
# under its old name. tools/fuzz-reader.sh fuzzes the settings and pose-file readers too.
#   tools/fuzz-log-reader.sh [seconds]
set -euo pipefail
exec "$(dirname "$0")/fuzz-reader.sh" log "${1:-60}"
