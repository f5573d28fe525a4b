#!/usr/bin/env bash
# Where the list build's time goes in a flowing run (issue 25, change 16's first look): ncu of the
# in-step build kernel (list_build = auto) at the 201st rebuild of the dam break 1.04M from rest
# (Wendland, half cells, skin 0.1: ~0.1 s into the flow), with the warp stall reasons per SASS
# instruction (SourceCounters, exported as CSV) and the stores' sectors per request; the listed
# force loop at a later launch beside it. About three minutes of device time.
#
#   here:  tools/gpu-run.sh pack      there: bench/lease/build-stalls.sh
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/p
X="tools/gpu-run.sh exec"
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1 --steps ${STEPS:-4000}"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/p/gpu.txt
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,\
l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_ld.sum,\
dram__bytes_read.sum,dram__bytes_write.sum,smsp__inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio
for k in "build_lists_in_step ${SKIP_BUILD:-200}" "forces_listed ${SKIP_LISTED:-1500}"; do
  set -- $k
  $X ncu --clock-control none -k regex:$1 --launch-skip $2 -c 1 --metrics $M \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats \
    --section MemoryWorkloadAnalysis --section SourceCounters -o $O/p/$1 -f \
    sphbench simulate $CASE --out /tmp/ncu-run > $O/p/$1.txt 2>&1
  $X ncu -i $O/p/$1.ncu-rep --page source --csv --print-source sass > $O/p/$1-sass.csv 2>&1
  $X ncu -i $O/p/$1.ncu-rep --page details --print-details all > $O/p/$1-details.txt 2>&1
  echo "== $1"; grep -E "Duration|Registers Per|Achieved Occupancy|Warp Cycles Per Issued|Avg. Active Threads|sectors_pipe_lsu_mem_global_op_st|requests_pipe_lsu_mem_global_op_st|dram__bytes|No kernels|ERROR" $O/p/$1-details.txt | head -14
done
tar -czf $O/build-stalls.tar.gz -C $O p && rm -rf $O/p
