#!/usr/bin/env bash
# Builds for sm_90 here and runs a command on a GPU machine that lacks this project's build
# dependencies (CLI11, toml++, GoogleTest, the HDF5 of this distribution).
#
#   tools/gpu-run.sh pack            on the build machine: build into build-gpu/ and gather the
#                                    binaries, the shared libraries they need and the meshes
#                                    into .carry/ (ignored by git; copy it to the GPU machine);
#                                    F64=1 adds the float64 sphbench (build-gpu-f64/)
#   tools/gpu-run.sh lease           after pack: .carry-cluster/lease.tar.xz, the one file a lent
#                                    machine needs (LEASE_BINARIES, default "sphbench sph_tests",
#                                    their libraries, the meshes, the commit), and whether the
#                                    tree and it fit the run tool's 64 MiB (which folders to set
#                                    aside for the call when they do not)
#   tools/gpu-run.sh exec CMD ...    on the GPU machine, in the repository root: run CMD with
#                                    .carry/bin on PATH, its libraries and meshes found
#   tools/gpu-run.sh --help          this text
#
# Example (the GPU results of docs/results.md were made this way):
#   tools/gpu-run.sh pack
#   # ... copy the working tree with .carry/ to the GPU machine, then there:
#   tools/gpu-run.sh exec sphbench simulate dsph-dambreak --steps 200 --backend cuda
#   tools/gpu-run.sh exec sph_tests --gtest_filter='CudaBackend.*'
#
# All reference results on a machine lent for commands of at most 10 minutes (`make reference`;
# `python3 tools/reference.py --help` says more):
#   F64=1 tools/gpu-run.sh pack      here, once
#   there, per command (carry .carry/; stops before its budget, resumes on the next call):
#     REFERENCE_BUDGET_S=480 tools/gpu-run.sh exec python3 tools/reference.py
#   here, after each command: tar -xzf reference.tar.gz (from $OUT), then call again until it
#   prints "nothing left to run"; then `make claims` and commit results/reference/ and
#   docs/results.md. More: docs/gpu-machines.md.
set -euo pipefail
cd "$(dirname "$0")/.."
CARRY=.carry

case "${1:-}" in
pack)
  tools/install-deps.sh
  cmake -S . -B build-gpu -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_ARCHITECTURES=90 >/dev/null
  cmake --build build-gpu -j"${JOBS:-2}"
  rm -rf "$CARRY" && mkdir -p "$CARRY/bin" "$CARRY/lib" "$CARRY/meshes"
  cp build-gpu/harness/sphbench build-gpu/tests/sph_tests "$CARRY/bin/"
  [ -x build-gpu/bench/sph_bench ] && cp build-gpu/bench/sph_bench "$CARRY/bin/"
  [ -x build-gpu/bench/sph_skip_bench ] && cp build-gpu/bench/sph_skip_bench "$CARRY/bin/"
  [ -x build-gpu/bench/fixed_point_additions ] && cp build-gpu/bench/fixed_point_additions "$CARRY/bin/"
  # MPI runs against one process, every step (tools/mpi-cuda-check.sh; built where MPI is found).
  [ -x build-gpu/tests/sph_mpi_equivalence ] && cp build-gpu/tests/sph_mpi_equivalence "$CARRY/bin/"
  # F64=1: also the float64 sphbench (the accuracy sweep's precision = "float64" runs).
  if [ "${F64:-0}" = 1 ]; then
    cmake -S . -B build-gpu-f64 -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_ARCHITECTURES=90 -DSPH_DOUBLE=ON \
      -DSPH_BUILD_TESTS=OFF >/dev/null
    cmake --build build-gpu-f64 -j"${JOBS:-2}" --target sphbench
    cp build-gpu-f64/harness/sphbench "$CARRY/bin/sphbench-f64"
  fi
  strip --strip-unneeded "$CARRY"/bin/*  # the run tool carries at most 64 MiB with the tree
  # Every shared library but the C runtime and the C++ runtime (the GPU machine's are newer).
  ldd "$CARRY"/bin/* | awk '$3 ~ /^\// {print $3}' | sort -u |
    grep -v -E '/(libc|libm|libdl|libpthread|librt|libresolv|ld-linux[^/]*|libstdc\+\+|libgcc_s)\.so' |
    xargs -r -I{} cp -L {} "$CARRY/lib/"
  MESHES=${SPH_MESH_DIR:-../shared/meshes}
  [ -d "$MESHES" ] && cp "$MESHES"/*.obj "$CARRY/meshes/" || echo "gpu-run: no meshes found at $MESHES"
  git rev-parse HEAD >"$CARRY/commit" 2>/dev/null || echo unknown >"$CARRY/commit"
  [ -z "$(git status --porcelain --untracked-files=no 2>/dev/null)" ] && echo clean >"$CARRY/dirty" || echo dirty >"$CARRY/dirty"
  du -sh "$CARRY"
  ;;
lease)
  # The run tool carries the tree (tracked and untracked, not ignored) with the named ignored
  # paths, 64 MiB in all: the whole .carry (every bench binary, the float64 sphbench) is more
  # than most calls need.
  [ -x "$CARRY/bin/sphbench" ] || { echo "gpu-run: no $CARRY/bin/sphbench; run 'tools/gpu-run.sh pack' first"; exit 2; }
  files=()
  for b in ${LEASE_BINARIES:-sphbench sph_tests}; do
    [ -x "$CARRY/bin/$b" ] || { echo "gpu-run: LEASE_BINARIES names '$b', which $CARRY/bin does not hold (it holds: $(ls $CARRY/bin | tr '\n' ' '))"; exit 2; }
    files+=("$CARRY/bin/$b")
  done
  mkdir -p .carry-cluster && rm -f .carry-cluster/*.tar.xz
  tar -cf - "${files[@]}" "$CARRY/lib" "$CARRY/meshes" "$CARRY/commit" "$CARRY/dirty" | xz -T"${JOBS:-2}" -6 > .carry-cluster/lease.tar.xz
  archive=$(stat -c %s .carry-cluster/lease.tar.xz)
  # Files set aside for the call (tracked, absent) count nothing: stat fails on them, so xargs's
  # status is not the pipeline's.
  tree=$({ git ls-files -z --cached --others --exclude-standard | xargs -0 -r stat -c %s 2>/dev/null || true; } |
    awk '{s += $1} END {print s + 0}')
  limit=$((64 * 1024 * 1024))
  echo "gpu-run: .carry-cluster/lease.tar.xz $((archive / 1048576)) MiB, the tree $((tree / 1048576)) MiB, the limit 64 MiB"
  if [ $((archive + tree)) -gt $limit ]; then
    echo "gpu-run: over the limit by $(((archive + tree - limit) / 1048576 + 1)) MiB; the largest result folders (move them aside for the call and back after, or name fewer LEASE_BINARIES):"
    du -sm results/reference/* 2>/dev/null | sort -rn | head -4 | sed 's/^/  /'
    exit 3
  fi
  ;;
exec)
  shift
  [ -x "$CARRY/bin/sphbench" ] || { echo "gpu-run: no $CARRY/bin/sphbench; run 'tools/gpu-run.sh pack' first"; exit 2; }
  export PATH="$PWD/$CARRY/bin:$PATH"
  export LD_LIBRARY_PATH="$PWD/$CARRY/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export SPH_MESH_DIR="$PWD/$CARRY/meshes"
  export SPH_GIT_COMMIT="$(cat $CARRY/commit)" SPH_GIT_DIRTY="$(cat $CARRY/dirty)"
  export NCCL_NVLS_ENABLE=0  # never NVLink multicast on shared machines
  "$@"
  ;;
-h|--help|help)
  sed -n '2,/^[^#]/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
  ;;
*)
  sed -n '2,/^[^#]/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  if [ -z "${1:-}" ]; then echo "gpu-run: no command given; use pack, lease or exec" >&2
  else echo "gpu-run: unknown command '$1'; use pack, lease or exec" >&2; fi
  exit 2
  ;;
esac
