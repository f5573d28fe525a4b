#!/usr/bin/env bash
# Change 22's second step (the box test, docs/force-loop-notes.md) measured, and the whole-run
# reference items on the same binary, in one call (the run tool's machine stays warm only 30 s
# between calls). Carry .carry-cluster (tools/gpu-run.sh pack && tools/gpu-run.sh lease).
#   1. the CUDA tests of the list builds (the lists entry by entry against the host's, the
#      forces bitwise against the per-lane build, every variant against the host); memcheck and
#      racecheck of the builds on random clouds;
#   2. ncu of the warp-per-cell build (auto) and the in-step build at the 151st rebuild from rest
#      (dam break 1.04M, Wendland, half cells, skin 0.1);
#   3. the whole event 0-1 s with --list-build in-step (the baseline on this binary);
#   4. `make reference`'s item whole-run-1.04M (its Wendland lists run is the auto build's
#      whole event) within BUDGET_S seconds (default 300).
# Each piece is archived under $OUT as soon as it ends (tests.tar.gz; reference.tar.gz).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
budget=${1:-300}
for t in .carry-cluster/*.tar.xz; do [ -f "$t" ] && tar -xJf "$t"; done
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/r/gpu.txt
cat .carry/commit .carry/dirty > $O/r/build.txt
$X sph_tests --gtest_filter='CudaBackend.ListBuild*:*CudaVariants*' > $O/r/cuda_tests.txt 2>&1; tail -3 $O/r/cuda_tests.txt
grep -E "differ|FAILED|seed" $O/r/cuda_tests.txt | head -30
for tool in memcheck racecheck; do
  $X compute-sanitizer --tool $tool --error-exitcode 9 sph_tests \
    --gtest_filter='CudaBackend.ListBuildsGiveTheSameForcesOnRandomClouds:CudaBackend.ListBuildsStoreTheHostsEntries' > $O/r/$tool.txt 2>&1
  echo "$tool rc=$? $(grep -E 'ERROR SUMMARY|PASSED|FAILED' $O/r/$tool.txt | tr '\n' ' ')"
done
tar -czf $O/tests.tar.gz -C $O r
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,dram__bytes_read.sum,dram__bytes_write.sum,smsp__inst_executed.sum
for k in "build_lists_by_cell auto" "build_lists_in_step in-step"; do
  set -- $k
  timeout 120 $X ncu --clock-control none -k regex:$1 --launch-skip 150 -c 1 --metrics $M \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis \
    sphbench simulate $CASE --list-build $2 --steps 4000 --out /tmp/ncu-run > $O/r/ncu-$1.txt 2>&1
  echo "== $1: $(grep -E "^    (Duration|Registers Per|Achieved Occupancy|Avg. Active Threads|Warp Cycles Per Issued|smsp__inst_executed|l1tex__t_sectors_pipe_lsu_mem_global_op_st|dram__bytes_write)" $O/r/ncu-$1.txt | awk '{print $NF}' | tr '\n' ' ')"
done
tar -czf $O/tests.tar.gz -C $O r
$X sphbench simulate $CASE --list-build in-step --end-time 1.0 --out $O/w/in-step > $O/r/whole-in-step.txt 2>&1
tail -2 $O/r/whole-in-step.txt
tar -czf $O/tests.tar.gz -C $O r w  # here: bench/lease/step_windows.py LABEL=w/in-step/*_steps.csv
PYTHONUNBUFFERED=1 REFERENCE_ARCHIVE="$O/reference.tar.gz" REFERENCE_BUDGET_S="$budget" REFERENCE_ONLY="whole-run-1.04M" \
  $X python3 tools/reference.py 2>&1 | tee "$O/reference.log" | grep -E "^\[|^reference:|estimate"
