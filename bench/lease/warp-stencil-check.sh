#!/usr/bin/env bash
# One lease for change 13 (one stencil per warp): CUDA tests, the lists against the base
# build's bitwise (whole runs' snapshots), whole events, ncu of both builds' list kernels.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/runs $O/bit
export PATH=$PWD/.carry-base-bin:$PATH
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
if [ "${TESTS:-1}" = 1 ]; then
  $X sph_tests --gtest_filter='CudaBackend.*' > $O/cuda_tests.txt 2>&1; tail -3 $O/cuda_tests.txt
fi
if [ "${BIT:-1}" = 1 ]; then
  for v in "2" "2 --merge" "1" "3 --merge"; do
    tag=n$(echo $v | tr -d ' -'); for b in sphbench sphbench-base; do
      $X $b simulate dsph-dambreak --set dp=0.009 --backend cuda --quiet --warmup 0 --verlet --cells-per-support $v \
        --skin 0.1 --steps 1500 --snapshot-every 750 --out $O/bit/$tag/$b > $O/bit/$tag-$b.txt 2>&1
    done
    if python3 -c "import h5py" 2>/dev/null; then
      echo "$tag: $(python3 tests/mpi/compare_snapshots.py $O/bit/$tag/sphbench/dsph-dambreak_snapshots $O/bit/$tag/sphbench-base/dsph-dambreak_snapshots)"
    fi
  done
  python3 -c "import h5py" 2>/dev/null && rm -rf $O/bit/*/ || tar -czf $O/bit.tar.gz -C $O bit
  rm -rf $O/bit
fi
for skin in ${SKINS:-0.05 0.1 0.15}; do
  $X sphbench simulate dsph-dambreak --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin $skin \
    --steps ${STEPS:-23127} --out $O/runs/vl-$skin > $O/runs/vl-$skin.txt 2>&1
  echo "skin $skin: $(grep -E 'time per step' $O/runs/vl-$skin.txt)"
done
if [ "${NCU:-1}" = 1 ]; then
  for b in ${NCU_BUILDS:-sphbench:warp_stencil sphbench-base:in_step}; do
    $X ncu --clock-control none --kernel-name-base demangled --kernel-name regex:".*${b#*:}.*" --launch-skip 300 --launch-count 1 \
      --section SpeedOfLight --section Occupancy --section WarpStateStats --section MemoryWorkloadAnalysis --section LaunchStats \
      ${b%%:*} simulate dsph-dambreak --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.05 --steps 3000 \
      --out /tmp/ncu-run > $O/ncu-${b#*:}.txt 2>&1
    grep -E "Duration|Memory Throughput|Compute \(SM\) Throughput|Achieved Occupancy|Registers Per|L1/TEX Hit|No kernels" $O/ncu-${b#*:}.txt | head -8
  done
fi
tar -czf $O/runs.tar.gz -C $O runs && rm -rf $O/runs
