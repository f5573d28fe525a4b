#!/usr/bin/env bash
# ncu of change 15's list build (build_lists_from_clusters_kernel) beside the in-step build at
# the same rebuild (the 4th of a run from rest), with the source counters of the new kernel.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
CASE="dsph-dambreak --set dp=0.0045 --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
S="--section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis --section MemoryWorkloadAnalysis_Tables"
$X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_from_clusters" --launch-skip 4 -c 1 $S --section SourceCounters \
  sphbench simulate $CASE --list-build clusters --steps 700 --out /tmp/ncu-run > $O/ncu-clusters.txt 2>&1
$X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_in_step|build_cluster_lists|cluster_boxes|fill_column|column_cluster" --launch-skip 12 -c 5 $S \
  sphbench simulate $CASE --list-build clusters --steps 700 --out /tmp/ncu-run > $O/ncu-cluster-parts.txt 2>&1
$X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_in_step" --launch-skip 4 -c 1 $S \
  sphbench simulate $CASE --steps 700 --out /tmp/ncu-run > $O/ncu-stencil.txt 2>&1
for f in $O/ncu-*.txt; do
  echo "== $(basename $f)"
  grep -E "^  [a-z_].*kernel|Duration|Compute \(SM\) Throughput|Memory Throughput|DRAM Throughput|L1/TEX Hit|L2 Hit|Achieved Occupancy|Theoretical Occupancy|Registers Per|Warp Cycles Per Issued|Avg. Active Threads|Executed Ipc A|Block Limit|No kernels|==ERROR" $f | head -60
done
