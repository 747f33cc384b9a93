#!/usr/bin/env bash
# Installs the Debian 12 packages legkit needs, if any are missing. Run as root.
set -euo pipefail
packages=(
  cmake g++ make ccache clang libclang-rt-14-dev
  libeigen3-dev catch2 librapidcheck-dev libceres-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libyaml-cpp-dev
  libmujoco-dev libqhull-dev libgl-dev
  python3-matplotlib python3-numpy python3-h5py
  parallel
  python3-dev pybind11-dev python3-pybind11 python3-pytest jupyter-nbconvert python3-ipykernel
  liborocos-kdl-dev libkdl-parser-dev liburdfdom-dev libtinyxml-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "legkit: installing missing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
