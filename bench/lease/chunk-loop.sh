#!/usr/bin/env bash
# Change 19 (issue 25): the listed loop over chunks unrolled, against change 17 (carried as
# sphbench-c17): the CUDA list tests, ncu of the listed loop at its 1501st launch from rest (dam
# break 1.04M, Wendland, half cells, skin 0.1), and change 19's whole event (whole-run spec).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/r/gpu.txt
$X sph_tests --gtest_filter='CudaBackend.PerLane*:*CudaVariants*' > $O/r/cuda_tests.txt 2>&1; tail -2 $O/r/cuda_tests.txt
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
for b in sphbench sphbench-c17; do
  $X ncu --clock-control none -k regex:forces_listed --launch-skip 1500 -c 1 --metrics smsp__inst_executed.sum \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats \
    $b simulate $CASE --steps 2000 --out /tmp/ncu-run > $O/r/ncu-$b.txt 2>&1
  echo "== $b: $(grep -E "^    (Duration|Registers Per|Warp Cycles Per Issued|smsp__inst_executed.sum)" $O/r/ncu-$b.txt | awk '{print $NF}' | tr '\n' ' ')"
done
PYTHONUNBUFFERED=1 $X sphbench run experiments/whole-run.toml --backend cuda --only dambreak-1.04M-wendland-lists \
  --out $O/r/whole-run > $O/r/whole-run.txt 2>&1; tail -3 $O/r/whole-run.txt
tar -czf $O/chunk-loop.tar.gz -C $O r && rm -rf $O/r
