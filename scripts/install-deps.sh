#!/usr/bin/env bash
# Installs the Debian packages axonguide builds against; with --tests also those its
# tests use. Idempotent: it only calls apt-get when something is missing, and runs
# `apt-get update` at most once.
set -euo pipefail

# What building and running the command needs (README, first command). HDF5, MPI and
# pybind11 change the configuration, so they stay here even though only some commands use
# them: installed later, they would make the test command rebuild nearly everything.
packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libtbb-dev libgsl-dev libboost-graph-dev
  libgtest-dev librapidcheck-dev librandom123-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libssl-dev
  python3 python3-matplotlib python3-pil
  # SONATA output (libhdf5) and the Python module (pybind11, numpy)
  libhdf5-dev python3-dev python3-pybind11 python3-numpy
  # sweeps and networks over MPI ranks: Open MPI
  libopenmpi-dev openmpi-bin
)
# What only the tests read our files with (--tests; the README's test command passes it):
test_packages=(
  # pytest, and the clients: h5py, PyNN (SONATA), NEURON (SWC through Import3d), networkx
  python3-pytest python3-h5py python3-pynn python3-neuron python3-networkx
  # the viewer's tests: VTK's reader for the ParaView files, headless Chromium for the page
  python3-vtk9 chromium
  # the fuzzers (fuzz/): clang, and libFuzzer with the sanitizers' runtimes (only a
  # recommendation of clang, which --no-install-recommends leaves out)
  clang libclang-rt-dev
)
case "$*" in
  "") ;;
  --tests) packages+=("${test_packages[@]}") ;;
  *) echo "install-deps.sh: takes no arguments, or --tests (also the test clients)" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# npm (for three.js, which `axonguide view` inlines): Debian's when there is none yet.
command -v npm >/dev/null 2>&1 || missing+=(npm)
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} Debian packages present"
else
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# JavaScript packages pinned by package-lock.json (three.js), into ./node_modules.
cd "$(dirname "$0")/.."
want=$(sed -n 's/.*"three": *"\([0-9.]*\)".*/\1/p' package.json)
have=$(sed -n 's/^ *"version": *"\([0-9.]*\)".*/\1/p' node_modules/three/package.json 2>/dev/null | head -n 1 || true)
if [ "$want" != "$have" ]; then
  echo "install-deps: npm ci (three.js for the viewer)"
  npm ci --no-audit --no-fund --loglevel=error
fi
