#!/usr/bin/env bash
# Change 20 (issue 25; branch experiment/listed-56-registers, pack from there): the listed loop
# capped at 56 registers (min_blocks 9: 9 blocks of 128 an SM), against change 19 (main at
# b1b2397, carried as sphbench-c19; /work/basebin/sphbench-c19-b1b2397 here). The whole event
# first (whole-run spec, Wendland 1.04M lists, 0 to 1 s), the CUDA tests, then ncu of the
# listed loop at its 1501st launch from rest for both builds. Each result goes to $OUT as soon
# as it exists, so that a lease cut short still returns what ran.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
PYTHONUNBUFFERED=1 $X sphbench run experiments/whole-run.toml --backend cuda --only dambreak-1.04M-wendland-lists \
  --out /tmp/wr > /tmp/wr.txt 2>&1; tail -3 /tmp/wr.txt
cp /tmp/wr.txt /tmp/wr/ 2>/dev/null; tar -czf $O/whole-run.tar.gz -C /tmp wr
$X sph_tests --gtest_filter='Cuda*:*Cuda*' > $O/cuda_tests.txt 2>&1; tail -2 $O/cuda_tests.txt
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
for b in sphbench sphbench-c19; do
  $X ncu --clock-control none -k regex:forces_listed --launch-skip 1500 -c 1 --metrics smsp__inst_executed.sum \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats \
    $b simulate $CASE --steps 1600 --out /tmp/ncu-run > $O/ncu-$b.txt 2>&1
  echo "== $b: $(grep -E "^    (Duration|Registers Per|Warp Cycles Per Issued|smsp__inst_executed.sum)" $O/ncu-$b.txt | awk '{print $NF}' | tr '\n' ' ')"
done
