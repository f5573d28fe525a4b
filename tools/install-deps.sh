#!/usr/bin/env bash
# Installs what `make test` and the figure targets need and is missing: system packages
# from the distribution's registry, Python packages from PyPI. Does nothing when all is there.
set -euo pipefail

need_apt=()
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
# OpenMPI: runs across processes (mpirun -np R sphbench ...) and their tests; valgrind: perf-check.
for pkg in cmake g++ make libhdf5-dev libcli11-dev libtomlplusplus-dev libgtest-dev libbenchmark-dev valgrind libopenmpi-dev openmpi-bin; do
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

# make perf-check reads the CUDA kernels with cuobjdump (and nvdisasm for the SASS), which this
# toolkit's wheels leave out: the NVIDIA wheels of both, pinned so the listing format stays put.
if command -v nvcc >/dev/null 2>&1 && ! $PY -c "
import glob, nvidia, os
assert all(any(glob.glob(os.path.join(p, 'cu*', 'bin', t)) for p in nvidia.__path__) for t in ['cuobjdump', 'nvdisasm'])
" 2>/dev/null && ! { command -v cuobjdump && command -v nvdisasm; } >/dev/null 2>&1; then
  echo "install-deps: installing cuobjdump and nvdisasm"
  $PY -m pip install -q "nvidia-cuda-cuobjdump==13.5.37" "nvidia-cuda-nvdisasm==13.5.37"
fi
