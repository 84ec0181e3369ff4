#!/usr/bin/env bash
# Installs the Debian packages icobrdf needs that are missing. Quiet when everything is present.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libhwy-dev libopenmesh-dev libhdf5-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libbenchmark-dev libcairo2-dev libopenblas-dev libboost-dev
  python3 python3-numpy python3-h5py python3-matplotlib
  python3-dev pybind11-dev python3-pytest   # the Python module (python/) and its tests
  clang libclang-rt-14-dev libomp-dev llvm   # scripts/fuzz.sh: libFuzzer, sanitizer runtimes, OpenMP for clang, llvm-symbolizer
  openmpi-bin libopenmpi-dev   # the MPI layer (icobrdf/cluster, docs/cluster.md): mpirun -np R icobrdf bank build
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
