#!/usr/bin/env bash
# Change 22 (issue 25, docs/force-loop-notes.md): the lists built by one warp per cell, against
# the in-step build it replaces as the default, in one call. Carry .carry-cluster (the packed
# build of this commit). The CUDA tests of the list builds (bitwise against the per-lane build,
# against the host), memcheck and racecheck of the new kernel; ncu of both builds at the 151st
# rebuild from rest (dam break 1.04M, Wendland, half cells, skin 0.1); the whole event 0-1 s
# with each build on the same binary. Each piece is archived under $OUT as soon as it ends.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
for t in .carry-cluster/*.tar.xz; do [ -f "$t" ] && tar -xJf "$t"; done
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/r/gpu.txt
cat .carry/commit .carry/dirty > $O/r/build.txt
$X sph_tests --gtest_filter='CudaBackend.ListBuild*:*CudaVariants*' > $O/r/cuda_tests.txt 2>&1; tail -3 $O/r/cuda_tests.txt
grep -E "particles differ|FAILED" $O/r/cuda_tests.txt | head -20
for tool in memcheck racecheck; do
  $X compute-sanitizer --tool $tool --error-exitcode 9 sph_tests \
    --gtest_filter='CudaBackend.ListBuildsGiveTheSameForcesOnRandomClouds' > $O/r/$tool.txt 2>&1
  echo "$tool rc=$? $(grep -E 'ERROR SUMMARY|PASSED|FAILED' $O/r/$tool.txt | tr '\n' ' ')"
done
tar -czf $O/tests.tar.gz -C $O r
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,dram__bytes_read.sum,dram__bytes_write.sum,smsp__inst_executed.sum
for k in "build_lists_by_cell auto" "build_lists_in_step in-step"; do
  set -- $k
  $X ncu --clock-control none -k regex:$1 --launch-skip 150 -c 1 --metrics $M \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis \
    sphbench simulate $CASE --list-build $2 --steps 4000 --out /tmp/ncu-run > $O/r/ncu-$1.txt 2>&1
  echo "== $1: $(grep -E "^    (Duration|Registers Per|Achieved Occupancy|Avg. Active Threads|Warp Cycles Per Issued|smsp__inst_executed|l1tex__t_sectors_pipe_lsu_mem_global_op_st|dram__bytes_write)" $O/r/ncu-$1.txt | awk '{print $NF}' | tr '\n' ' ')"
done
tar -czf $O/tests.tar.gz -C $O r
for b in auto in-step; do
  $X sphbench simulate $CASE --list-build $b --end-time 1.0 --out $O/w/$b > $O/r/whole-$b.txt 2>&1
  tail -2 $O/r/whole-$b.txt
  tar -czf $O/tests.tar.gz -C $O r w  # here: bench/lease/step_windows.py LABEL=w/B/*_steps.csv
done
