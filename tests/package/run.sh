#!/bin/sh
# The porter's first hour, checked: installs the kit's build tree into a private prefix
# (cmake --install), then configures, builds and runs an outside project (consumer/) that sees only
# that prefix: find_package(legkit 0.2 REQUIRED COMPONENTS estimation), the estimator manager from
# the kit's settings file on a log that `legkit sim` writes. Then checks the package's refusals: a
# component it does not have, a version it is not compatible with.
# With a Python interpreter given, also imports the installed Python package from the prefix and
# runs an estimator on a simulated log with it.
#   usage: run.sh <legkit-source-dir> <legkit-build-dir> <work-dir> <legkit-exe> [cmake [python]]
set -eu
src=$1
build=$2
work=$3
legkit=$4
cmake=${5:-cmake}
python=${6:-}
prefix="$work/prefix"

rm -rf "$work"
mkdir -p "$work"
if command -v ninja >/dev/null 2>&1; then set -- -G Ninja; else set --; fi

echo "== install the kit into $prefix"
"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log"
for dir in lib/cmake/legkit lib/cmake/lie include/legkit/estimation include/lie; do
  [ -d "$prefix/$dir" ] || { echo "FAIL: the install has no $dir" >&2; exit 1; }
done

echo "== configure, build and run the consumer against the prefix only"
"$cmake" -S "$src/tests/package/consumer" -B "$work/build-app" "$@" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF >"$work/configure.log"
found=$(sed -n 's/^legkit_DIR:PATH=//p' "$work/build-app/CMakeCache.txt")
case "$found" in
  "$prefix"/*) echo "legkit_DIR = $found" ;;
  *) echo "FAIL: find_package(legkit) found '$found', not the package in $prefix" >&2; exit 1 ;;
esac
"$cmake" --build "$work/build-app" -j 2
# The kit's settings file, with the still window that the simulated robot's 1 s stand allows.
sed 's/^  duration: 2$/  duration: 0.5/; s/^  max_wait: 10$/  max_wait: 0.9/' "$src/config/legkit.yaml" \
  >"$work/settings.yaml"
grep -q '^  duration: 0.5$' "$work/settings.yaml" && grep -q '^  max_wait: 0.9$' "$work/settings.yaml" ||
  { echo "FAIL: config/legkit.yaml's initialisation keys changed: update this script" >&2; exit 1; }
"$legkit" sim --scenario physics-trot --duration 4 --out "$work/trot.csv" >/dev/null
"$work/build-app/estimate" "$work/settings.yaml" "$work/trot.csv"

if [ -n "$python" ]; then
  echo "== the Python package from the prefix"
  PYTHONPATH="$prefix/lib/python3/dist-packages" "$python" -c '
import sys, legkit
assert legkit.__file__.startswith(sys.argv[1]), legkit.__file__
log = legkit.sim.simulate("trot", duration=1.0)
run = legkit.estimators.run(log, legkit.sim.settings_for("trot"), estimators=["invariant-ekf"])
print("legkit", legkit.__version__, "from", legkit.__file__, "ran", len(run["invariant-ekf"]["t"]), "rows")
' "$prefix"
fi

echo "== refusals: an unknown component, an incompatible version"
refuse() {  # refuse <name> <find_package arguments> <expected message>
  mkdir -p "$work/$1"
  printf 'cmake_minimum_required(VERSION 3.20)\nproject(p LANGUAGES CXX)\nfind_package(%s)\n' "$2" \
    >"$work/$1/CMakeLists.txt"
  if "$cmake" -S "$work/$1" -B "$work/$1/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/$1.log" 2>&1; then
    echo "FAIL: find_package($2) was accepted" >&2; exit 1
  fi
  grep -q "$3" "$work/$1.log" || { echo "FAIL: find_package($2) did not say '$3':" >&2; cat "$work/$1.log" >&2; exit 1; }
  echo "ok: find_package($2) refused: $3"
}
refuse unknown "legkit REQUIRED COMPONENTS nosuch" "legkit has no component 'nosuch'"
refuse version "legkit 0.1 REQUIRED" "The following configuration files were considered but not accepted"
echo "== a component finds only its own dependencies: io does not look for Ceres"
mkdir -p "$work/io-only"
printf 'cmake_minimum_required(VERSION 3.20)\nproject(p LANGUAGES CXX)\nfind_package(legkit 0.2 REQUIRED COMPONENTS io)\nif(NOT TARGET legkit::io OR TARGET legkit::estimation)\n  message(FATAL_ERROR "wrong targets")\nendif()\n' \
  >"$work/io-only/CMakeLists.txt"
"$cmake" -S "$work/io-only" -B "$work/io-only/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/io-only.log"
if grep -q '^Ceres_DIR' "$work/io-only/build/CMakeCache.txt"; then
  echo "FAIL: find_package(legkit COMPONENTS io) looked for Ceres" >&2; exit 1
fi
echo "ok: COMPONENTS io gives legkit::io without Ceres"
echo "package: ok"
