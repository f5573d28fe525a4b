#!/usr/bin/env bash
# Change 16 (issue 25): the in-step list build with its candidates' positions loaded eight at a
# time and tested into a mask before any entry is stored. Against the base build (6a05ab5,
# carried as sphbench-base): the CUDA tests (the lists bitwise as the per-lane build's), ncu
# of the build kernel at the 201st rebuild of the dam break 1.04M (Wendland, half cells, skin
# 0.1), and the whole event 0-1 s of both builds (whole-run spec's run for the new build).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/r/gpu.txt
$X sph_tests --gtest_filter='CudaBackend.*:*CudaVariants*' > $O/r/cuda_tests.txt 2>&1; tail -3 $O/r/cuda_tests.txt
grep "particles differ" $O/r/cuda_tests.txt
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,dram__bytes_read.sum,dram__bytes_write.sum,smsp__inst_executed.sum
for b in sphbench sphbench-base; do
  $X ncu --clock-control none -k regex:build_lists_in_step --launch-skip 200 -c 1 --metrics $M \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis \
    $b simulate $CASE --steps 4000 --out /tmp/ncu-run > $O/r/ncu-$b.txt 2>&1
  echo "== $b"; grep -E "Duration|Registers Per|Achieved Occupancy|Warp Cycles Per Issued|Avg. Active Threads|L1/TEX Hit|Stall Long|inst_executed|No kernels|ERROR" $O/r/ncu-$b.txt | head -10
done
PYTHONUNBUFFERED=1 $X sphbench run experiments/whole-run.toml --backend cuda --only dambreak-1.04M-wendland-lists \
  --out $O/r/whole-run > $O/r/whole-run.txt 2>&1; tail -4 $O/r/whole-run.txt
$X sphbench-base simulate $CASE --end-time 1.0 --out $O/r/base-wendland > $O/r/base-wendland.txt 2>&1; tail -4 $O/r/base-wendland.txt
tar -czf $O/two-phase-build.tar.gz -C $O r && rm -rf $O/r
