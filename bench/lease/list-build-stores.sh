#!/usr/bin/env bash
# The next look at change 15 (docs/force-loop-notes.md, "Against the prediction"): where the list
# builds' DRAM traffic comes from. Both builds (the default here, from cluster lists, and
# list_build = in-step) at the 5th rebuild from rest of the dam break 1.04M (Wendland, half
# cells, skin 0.1): the global stores' requests and sectors (a full row of 32 lanes is 4
# sectors a request; a lane storing alone, 1), the L2's written sectors, DRAM bytes read and
# written, and the loads' requests and sectors. About a minute of device time.
#
#   here:  tools/gpu-run.sh pack      there: bench/lease/list-build-stores.sh
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
CASE="dsph-dambreak --set dp=0.0045 --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1 --steps 700"
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,\
l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_ld.sum,\
lts__t_sectors_op_write.sum,dram__bytes_read.sum,dram__bytes_write.sum,gpu__time_duration.sum,\
smsp__inst_executed.sum,sm__warps_active.avg.pct_of_peak_sustained_active
$X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_from_clusters" --launch-skip 4 -c 1 \
  --metrics $M sphbench simulate $CASE --out /tmp/ncu-run > $O/stores-clusters.txt 2>&1
$X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_in_step" --launch-skip 4 -c 1 \
  --metrics $M sphbench simulate $CASE --list-build in-step --out /tmp/ncu-run > $O/stores-in-step.txt 2>&1
for f in $O/stores-*.txt; do echo "== $(basename $f)"; grep -E "kernel|\.sum|\.pct|No kernels|ERROR" $f | head -20; done
