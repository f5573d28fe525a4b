#!/usr/bin/env bash
# Changes 16 and 17 (issue 25) against the base build, one lease. Binaries carried in .carry/bin:
# sphbench (change 17), sphbench-c18 (change 18, branch experiment/merged-walk-build),
# sphbench-c16 (change 16, affebfd), sphbench-base (6a05ab5). The CUDA
# tests of change 17 (lists bitwise as the per-lane build's, variants against the host); ncu of
# the build kernel at the 201st rebuild and of the listed loop at its 1501st launch from rest
# (dam break 1.04M, Wendland, half cells, skin 0.1) for each build; the whole event 0-1 s of
# change 17 (whole-run spec) and of the base build.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/r/gpu.txt
$X sph_tests --gtest_filter='CudaBackend.*:*CudaVariants*' > $O/r/cuda_tests.txt 2>&1; tail -3 $O/r/cuda_tests.txt
grep "particles differ" $O/r/cuda_tests.txt
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
M=l1tex__t_requests_pipe_lsu_mem_global_op_st.sum,l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum,dram__bytes_read.sum,dram__bytes_write.sum,smsp__inst_executed.sum
for b in sphbench sphbench-c18 sphbench-c16 sphbench-base; do
  for k in "build_lists_in_step 200" "forces_listed 1500"; do
    set -- $k
    # changes 16 and 18 left the listed loop as it was
    [ $b != sphbench ] && [ $b != sphbench-base ] && [ $1 = forces_listed ] && continue
    $X ncu --clock-control none -k regex:$1 --launch-skip $2 -c 1 --metrics $M \
      --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis \
      $b simulate $CASE --steps 4000 --out /tmp/ncu-run > $O/r/ncu-$b-$1.txt 2>&1
    echo "== $b $1: $(grep -E "^    (Duration|Registers Per|Achieved Occupancy|L1/TEX Hit|Stall Long|dram__bytes_write|l1tex__t_sectors_pipe_lsu_mem_global_op_st)" $O/r/ncu-$b-$1.txt | awk '{print $NF}' | tr '\n' ' ')"
  done
done
PYTHONUNBUFFERED=1 $X sphbench run experiments/whole-run.toml --backend cuda --only dambreak-1.04M-wendland-lists \
  --out $O/r/whole-run > $O/r/whole-run.txt 2>&1; tail -3 $O/r/whole-run.txt
if [ "${BASE_WHOLE:-0}" = 1 ]; then
  $X sphbench-base simulate $CASE --end-time 1.0 --out $O/r/base-wendland > $O/r/base-wendland.txt 2>&1; tail -3 $O/r/base-wendland.txt
fi
tar -czf $O/list-build-changes.tar.gz -C $O r && rm -rf $O/r
# Change 17's whole event at a smaller skin (the rebuild got cheaper: the best skin may move down).
mkdir -p $O/s; $X sphbench simulate ${CASE/--skin 0.1/--skin ${SKIN2:-0.075}} --end-time 1.0 --out $O/s/skin > $O/s/skin.txt 2>&1; tail -3 $O/s/skin.txt
tar -czf $O/skin.tar.gz -C $O s && rm -rf $O/s
