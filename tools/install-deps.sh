#!/usr/bin/env bash
# Installs what `make test` and the figure targets need and is missing: system packages
# from the distribution's registry, Python packages from PyPI. Does nothing when all is there.
set -euo pipefail

need_apt=()
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
# OpenMPI: runs across processes (mpirun -np R sphbench ...) and their tests.
for pkg in cmake g++ make libhdf5-dev libcli11-dev libtomlplusplus-dev libgtest-dev libbenchmark-dev libopenmpi-dev openmpi-bin; do
  have_pkg "$pkg" || need_apt+=("$pkg")
done
if [ ${#need_apt[@]} -gt 0 ]; then
  echo "install-deps: installing ${need_apt[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}" >/dev/null
fi

PY=${PYTHON:-python3}  # the same interpreter the Makefile gives CMake for the plot tests
missing_py=()
for mod in numpy matplotlib pandas h5py; do
  $PY -c "import $mod" 2>/dev/null || missing_py+=("$mod")
done
if [ ${#missing_py[@]} -gt 0 ]; then
  echo "install-deps: installing Python packages ${missing_py[*]}"
  $PY -m pip install -q "${missing_py[@]}"
fi
