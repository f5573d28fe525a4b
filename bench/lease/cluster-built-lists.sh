#!/usr/bin/env bash
# One lease for change 15 (per-particle lists built from cluster lists, list_build = auto on open
# grids; docs/force-loop-notes.md): the CUDA tests of the list builds, DualSPHysics' dam break
# 1.04M (Wendland, half cells) over the whole event (0 to 1 s) with the default build and with
# the stencil's (list_build = in-step), ncu of both builds at the same rebuild from rest, and
# compute-sanitizer's memcheck and racecheck of a small run. One archive comes back (a lease
# returns at most 8 files); the summaries go to the output as each part ends.
#
#   here:  tools/gpu-run.sh pack
#   there: bench/lease/cluster-built-lists.sh      (carry .carry; OUT set by the run tool)
#
# Knobs: TESTS=0, WHOLE=0, NCU=0, SANITIZE=0 skip a part; RUNS ("auto:0.1 in-step:0.1",
# build:skin each), END (1.0 s), RUN_TIMEOUT (130 s a run).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/runs
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
cp .carry/commit $O/commit.txt 2>/dev/null
CASE="dsph-dambreak --set dp=0.0045 --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2"
summary() { grep -E "^run:|^whole run|^Verlet lists|^time per step|^memory|^neighbour pairs|[Ee]rror" "$1" | sed 's/^/  /'; }

if [ "${TESTS:-1}" = 1 ]; then
  timeout 200 $X sph_tests --gtest_filter='CudaBackend.ListBuildVariants*:*CudaVariants*:CudaBackend.*Verlet*' > $O/cuda_tests.txt 2>&1
  grep -E "against the defaults|PASSED|FAILED" $O/cuda_tests.txt | tail -16
fi
if [ "${WHOLE:-1}" = 1 ]; then
  for r in ${RUNS:-auto:0.1 in-step:0.1}; do
    b=${r%%:*}; skin=${r##*:}; tag=t${END:-1.0}-$b-skin$skin
    timeout ${RUN_TIMEOUT:-130} $X sphbench simulate $CASE --skin $skin --end-time ${END:-1.0} --list-build $b \
      --out $O/runs/$tag > $O/runs/$tag.txt 2>&1
    echo "== $tag (exit $?)"; summary $O/runs/$tag.txt
  done
fi
if [ "${NCU:-1}" = 1 ]; then
  # The 5th rebuild from rest (a rebuild every ~28 steps at rest: 700 steps hold it).
  S="--section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis"
  $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_from_clusters|build_cluster_lists" --launch-skip 8 -c 2 $S \
    sphbench simulate $CASE --skin 0.1 --steps 700 --out /tmp/ncu-run > $O/ncu-clusters.txt 2>&1
  $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_in_step" --launch-skip 4 -c 1 $S \
    sphbench simulate $CASE --skin 0.1 --list-build in-step --steps 700 --out /tmp/ncu-run > $O/ncu-stencil.txt 2>&1
  for f in $O/ncu-*.txt; do
    echo "== $(basename $f)"
    grep -E "^  [a-z_].*kernel|Duration|Compute \(SM\) Throughput|L1/TEX Hit|DRAM Throughput|Achieved Occupancy|Registers Per|Warp Cycles Per Issued|Avg. Active Threads|No kernels|==ERROR" $f | head -40
  done
fi
if [ "${SANITIZE:-1}" = 1 ] && $X bash -c 'command -v compute-sanitizer' > /dev/null 2>&1; then
  for tool in memcheck racecheck; do
    timeout 90 $X compute-sanitizer --tool $tool sphbench simulate dsph-dambreak --set dp=0.03 \
      --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1 --steps 40 \
      --out /tmp/sanitizer-run > $O/$tool.txt 2>&1
    echo "== $tool, list_build=auto: $(grep -E "ERROR SUMMARY|RACECHECK SUMMARY" $O/$tool.txt | tail -1)"
  done
fi
tar -czf /tmp/lease.tar.gz -C $O . && find $O -mindepth 1 -delete && mv /tmp/lease.tar.gz $O/
