#!/usr/bin/env bash
# Change 15, a look at why: the ring's rows (SPH_EXP_STAGE_ROWS; its shared memory comes out of
# the L1) and the grouped kernel (SPH_EXP_GROUPED=1: 8 lanes a cluster, candidates through shared
# memory); ncu of the build at the 5th rebuild from rest and 0 to 0.3 s of the dam break 1.04M
# with each, beside the default build; the bitwise CUDA test with the grouped kernel.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/runs
X="tools/gpu-run.sh exec"
CASE="dsph-dambreak --set dp=0.0045 --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
S="--section SpeedOfLight --section Occupancy --section WarpStateStats --section MemoryWorkloadAnalysis"
SPH_EXP_GROUPED=1 timeout 120 $X sph_tests --gtest_filter='CudaBackend.ListBuildVariants*' > $O/runs/tests-grouped.txt 2>&1
grep -E "against the defaults|PASSED|FAILED" $O/runs/tests-grouped.txt
for v in 0:32 0:8 1:32 1:16; do
  g=${v%%:*}; rows=${v##*:}
  SPH_EXP_GROUPED=$g SPH_EXP_STAGE_ROWS=$rows $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_from_clusters" --launch-skip 4 -c 1 $S \
    sphbench simulate $CASE --list-build clusters --steps 700 --out /tmp/ncu-run > $O/runs/ncu-g$g-rows$rows.txt 2>&1
  echo "== ncu grouped $g rows $rows"; grep -E "Duration|Compute \(SM\) Throughput|L1/TEX Hit|L2 Hit|DRAM Throughput|Achieved Occupancy|Warp Cycles Per Issued|Registers Per|No kernels" $O/runs/ncu-g$g-rows$rows.txt
done
for r in auto:0:32 clusters:0:32 clusters:0:8 clusters:1:32 clusters:1:16; do
  IFS=: read b g rows <<< "$r"; tag=t0.3-$b-g$g-rows$rows
  SPH_EXP_GROUPED=$g SPH_EXP_STAGE_ROWS=$rows timeout 100 $X sphbench simulate $CASE --end-time 0.3 --list-build $b --out $O/runs/$tag > $O/runs/$tag.txt 2>&1
  echo "== $tag"; grep -E "^whole run|^Verlet lists" $O/runs/$tag.txt
done
tar -czf /tmp/lease.tar.gz -C $O . && find $O -mindepth 1 -delete && mv /tmp/lease.tar.gz $O/
