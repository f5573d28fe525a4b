#!/usr/bin/env bash
# One lease in three commands (issue 25 and the stale reference results), main at the merge of
# change 20 (listed loop at 56 registers) and step 7 (Verlet lists on several CUDA subdomains):
#   a: the lists' CUDA test on 4 subdomains against one (bitwise), memcheck of it, ncu of the
#      listed loop (this build against change 19, carried as sphbench-c19), then make reference's
#      cuda-tests benchmarks fig4 cll-vs-vl accuracy calibration force-loop-bench;
#   b: make reference's whole-run (the whole events of experiments/whole-run.toml);
#   c: make reference's spheric2 fig3 skip-bench figures, then the MPI check with the lists.
# The build travels xz-packed under the 64 MiB a call carries: .carry-cluster/lease-a.tar.xz (all
# but sph_skip_bench and sph_mpi_equivalence) with call a, .carry-c/lease-c.tar.xz (those two) with
# call c; .carry/ stays on the machine between the calls (an ignored path).
# Usage there: bash bench/lease/session5.sh a|b|c   (results in $OUT; each call's reference.tar.gz
# holds all of results/reference/h200: take from it only what that call's items wrote)
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
for t in .carry-cluster/*.tar.xz .carry-c/*.tar.xz; do [ -f "$t" ] && tar -xJf "$t"; done
[ -x .carry/bin/sphbench ] || { echo "session5: no .carry/bin/sphbench: carry .carry-cluster (a fresh machine)"; exit 2; }
X="tools/gpu-run.sh exec"
export REFERENCE_ARCHIVE=$O/reference.tar.gz PYTHONUNBUFFERED=1
ref() { REFERENCE_BUDGET_S=$1 REFERENCE_ONLY="$2" $X python3 tools/reference.py > $O/reference-$3.log 2>&1
        grep -E "done|failed|skipped|left|error" $O/reference-$3.log | tail -12; }
case "$1" in
a)
  nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
  $X sph_tests --gtest_filter='CudaBackend.ListsOnSeveralSubdomains*' > $O/cuda_lists_test.txt 2>&1
  grep -E "OK|FAILED|PASSED" $O/cuda_lists_test.txt | tail -4
  timeout 90 $X compute-sanitizer --tool memcheck --leak-check full sph_tests \
    --gtest_filter='CudaBackend.ListsOnSeveralSubdomains*' > $O/memcheck.txt 2>&1; echo "memcheck rc $?"; tail -2 $O/memcheck.txt
  CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
  for b in sphbench sphbench-c19; do
    $X ncu --clock-control none -k regex:forces_listed --launch-skip 1500 -c 1 --metrics smsp__inst_executed.sum \
      --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats \
      $b simulate $CASE --steps 1600 --out /tmp/ncu-run > /tmp/ncu-$b.txt 2>&1
    echo "== $b: $(grep -E "^    (Duration|Registers Per|Warp Cycles Per Issued|smsp__inst_executed.sum)" /tmp/ncu-$b.txt | awk '{print $NF}' | tr '\n' ' ')"
  done
  cat /tmp/ncu-sphbench.txt > $O/ncu.txt; echo "=== sphbench-c19" >> $O/ncu.txt; cat /tmp/ncu-sphbench-c19.txt >> $O/ncu.txt
  ref 380 "cuda-tests benchmarks fig4 cll-vs-vl accuracy calibration force-loop-bench" a
  ;;
b) ref 560 "whole-run" b ;;
c)
  ref 470 "spheric2 fig3 skip-bench figures" c
  timeout 80 $X bash tools/mpi-cuda-check.sh /tmp/mpi-check > $O/mpi_check.txt 2>&1; echo "mpi check rc $?"; tail -4 $O/mpi_check.txt
  ;;
esac
