#!/usr/bin/env bash
# Step 7 of docs/lists-with-slabs.md (issue 25; branch experiment/cuda-lists-on-slabs, pack from
# there with tools/gpu-run.sh pack, which also copies sph_mpi_equivalence): Verlet lists on
# several CUDA subdomains. The lists' CUDA test (4 subdomains on one GPU against one, bitwise:
# cell-offset and plain entries, peer and staged transports, overlap on and off), every other
# CUDA test, memcheck of the new test, and the MPI check with the lists (tools/mpi-cuda-check.sh,
# where mpirun is found; it shares the one GPU between two ranks). Results in $OUT.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
$X sph_tests --gtest_filter='CudaBackend.ListsOnSeveralSubdomains*' > $O/cuda_lists_test.txt 2>&1
grep -E "cuda lists|OK|FAILED" $O/cuda_lists_test.txt
$X sph_tests --gtest_filter='Cuda*:*Cuda*' > $O/cuda_tests.txt 2>&1; tail -3 $O/cuda_tests.txt
$X compute-sanitizer --tool memcheck --leak-check full sph_tests \
  --gtest_filter='CudaBackend.ListsOnSeveralSubdomains*' > $O/memcheck.txt 2>&1; tail -2 $O/memcheck.txt
# Skips its MPI part, saying so, where mpirun is missing or cannot start the carried binaries.
$X bash tools/mpi-cuda-check.sh /tmp/mpi-check > $O/mpi_check.txt 2>&1; tail -5 $O/mpi_check.txt
