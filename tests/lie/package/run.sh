#!/bin/sh
# Proves that lie/ is a standalone package (DESIGN.md): configures lie/ ALONE (so that any
# dependency on the rest of the tree fails), installs it to a private prefix, then configures,
# builds and runs an outside consumer (this folder) that only sees that prefix; it asks for the
# component ceres (target lie::ceres). Then checks that a lie installed WITHOUT that component
# (-DLIE_CERES=OFF) makes find_package(lie REQUIRED COMPONENTS ceres) fail with a clear message.
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

echo "== a lie installed without its ceres component: the consumer's find_package must say so"
"$cmake" -S "$src/lie" -B "$work/build-lie-noceres" "$@" -DLIE_CERES=OFF -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_INSTALL_PREFIX="$work/prefix-noceres" >/dev/null
"$cmake" --install "$work/build-lie-noceres" >/dev/null
if [ -e "$work/prefix-noceres/include/lie/ceres" ]; then
  echo "FAIL: LIE_CERES=OFF installed include/lie/ceres" >&2
  exit 1
fi
if "$cmake" -S "$src/tests/lie/package" -B "$work/build-app-noceres" "$@" -DCMAKE_CXX_COMPILER="$cxx" \
     -DCMAKE_PREFIX_PATH="$work/prefix-noceres" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
     -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF >"$work/noceres.log" 2>&1; then
  echo "FAIL: find_package(lie REQUIRED COMPONENTS ceres) succeeded without the component" >&2
  exit 1
fi
# CMake wraps the message: join its lines before looking for the phrase.
if ! tr -s ' \n' '  ' <"$work/noceres.log" | grep -q "installed without its ceres component"; then
  cat "$work/noceres.log" >&2
  echo "FAIL: the missing component was not reported clearly" >&2
  exit 1
fi
grep -B3 -A3 "installed without" "$work/noceres.log"
echo "== lie package test passed"
