#!/usr/bin/env bash
# Change 22: ncu of the warp-per-cell build and the in-step build at the 151st rebuild from rest
# (dam break 1.04M, Wendland, half cells, skin 0.1, 4000 steps: ~0.17 s, in the flow), the
# same binary (carry .carry-cluster). by-cell-build.sh's ncu asked for the 201st of 107.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
for t in .carry-cluster/*.tar.xz; do [ -f "$t" ] && [ ! -x .carry/bin/sphbench ] && tar -xJf "$t"; done
X="tools/gpu-run.sh exec"
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,dram__bytes_read.sum,dram__bytes_write.sum,smsp__inst_executed.sum
for k in "build_lists_by_cell auto" "build_lists_in_step in-step"; do
  set -- $k
  $X ncu --clock-control none -k regex:$1 --launch-skip 150 -c 1 --metrics $M \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section SchedulerStats \
    sphbench simulate $CASE --list-build $2 --steps 4000 --out /tmp/ncu-run > $O/r/ncu-$1.txt 2>&1
  echo "== $1: $(grep -E "^    (Duration|Registers Per|Achieved Occupancy|Avg. Active Threads|Warp Cycles Per Issued|Compute \(SM\) Throughput|smsp__inst_executed|l1tex__t_sectors_pipe_lsu_mem_global_op_st|dram__bytes_write)" $O/r/ncu-$1.txt | awk '{print $NF}' | tr '\n' ' ')"
done
tar -czf $O/ncu.tar.gz -C $O r
