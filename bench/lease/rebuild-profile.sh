#!/usr/bin/env bash
# One lease: where a flowing dam break's rebuild goes (issue 25). Whole events with lists,
# the cell search (its neighbour_list phase is the sort alone), and ncu of a mid-run build.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/runs
S="tools/gpu-run.sh exec sphbench simulate dsph-dambreak --backend cuda --quiet --warmup 0"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
for skin in ${SKINS:-0.05 0.1}; do
  $S --verlet --cells-per-support 2 --skin $skin --steps ${STEPS:-23127} --out $O/runs/vl-$skin > $O/runs/vl-$skin.txt 2>&1
  tail -8 $O/runs/vl-$skin.txt
done
$S --cells-per-support 2 --merge --steps 6000 --out $O/runs/cells-n2m > $O/runs/cells-n2m.txt 2>&1; tail -6 $O/runs/cells-n2m.txt
if [ "${NCU:-1}" = 1 ]; then
  tools/gpu-run.sh exec ncu --clock-control none --kernel-name regex:build_lists --launch-skip 800 --launch-count 1 \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section MemoryWorkloadAnalysis --section LaunchStats \
    sphbench simulate dsph-dambreak --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.05 --steps 3400 \
    --out /tmp/ncu-run > $O/ncu-build.txt 2>&1
  grep -E "build_lists|Duration|Memory Throughput|DRAM Throughput|Compute \(SM\)|Achieved Occupancy|Registers Per|L1/TEX Hit|Warp Cycles Per Issued|Theoretical Occ" $O/ncu-build.txt | head -20
fi
tar -czf $O/runs.tar.gz -C $O runs && rm -rf $O/runs
