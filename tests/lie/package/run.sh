#!/bin/sh
# Proves that lie/ is a standalone package (DESIGN.md): configures lie/ ALONE (so that any
# dependency on the rest of the tree fails), installs it to a private prefix, then configures,
# builds and runs an outside consumer (this folder) that only sees that prefix.
#   usage: run.sh <legkit-source-dir> <work-dir> [c++-compiler] [cmake]
set -eu
src=$1
work=$2
cxx=${3:-c++}
cmake=${4:-cmake}
prefix="$work/prefix"

rm -rf "$work"
mkdir -p "$work"
if command -v ninja >/dev/null 2>&1; then set -- -G Ninja; else set --; fi

echo "== configure, build and install lie/ alone"
"$cmake" -S "$src/lie" -B "$work/build-lie" "$@" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_INSTALL_PREFIX="$prefix"
"$cmake" --build "$work/build-lie" -j 1
"$cmake" --install "$work/build-lie"

echo "== the installed headers include only lie/ headers (quoted) and Eigen / the standard library"
if grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$prefix/include/lie" | grep -v '"lie/'; then
  echo "FAIL: an installed lie header includes a file outside lie/" >&2
  exit 1
fi

echo "== configure, build and run the consumer against the prefix only"
"$cmake" -S "$src/tests/lie/package" -B "$work/build-app" "$@" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
found=$(sed -n 's/^lie_DIR:PATH=//p' "$work/build-app/CMakeCache.txt")
case "$found" in
  "$prefix"/*) echo "lie_DIR = $found" ;;
  *) echo "FAIL: find_package(lie) found '$found', not the package installed in $prefix" >&2; exit 1 ;;
esac
"$cmake" --build "$work/build-app" -j 1
"$work/build-app/lie_package_app"
echo "== lie package test passed"
