#!/usr/bin/env bash
# One lease for change 15 (per-particle lists built from cluster lists, list_build = clusters;
# docs/force-loop-notes.md): the CUDA tests of the list builds, DualSPHysics' dam break 1.04M
# (Wendland, half cells) over the whole event (0 to 1 s) with the default build and with
# list_build = clusters at skin 0.1 and 0.05, ncu of both builds at the same flowing rebuild, and
# compute-sanitizer's memcheck of a small run. Each part writes under $OUT as it ends.
#
#   here:  tools/gpu-run.sh pack
#   there: bench/lease/cluster-built-lists.sh      (carry .carry; OUT set by the run tool)
#
# Knobs: TESTS=0, WHOLE=0, NCU=0, MEMCHECK=0 skip a part; RUNS ("auto:0.1 clusters:0.1
# clusters:0.05", build:skin each), END (1.0 s), RUN_TIMEOUT (130 s a run).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/runs
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
cp .carry/commit $O/commit.txt 2>/dev/null
CASE="dsph-dambreak --set dp=0.0045 --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2"
summary() { grep -E "^run:|^whole run|^Verlet lists|^time per step|^memory|^neighbour pairs|[Ee]rror" "$1" | sed 's/^/  /'; }

if [ "${TESTS:-1}" = 1 ]; then
  timeout 200 $X sph_tests --gtest_filter='CudaBackend.ListBuildVariants*:CudaBackend.ClusterLists*:*CudaVariants*list_build*' > $O/cuda_tests.txt 2>&1
  grep -E "against the defaults|PASSED|FAILED" $O/cuda_tests.txt | tail -16
fi
if [ "${WHOLE:-1}" = 1 ]; then
  for r in ${RUNS:-auto:0.1 clusters:0.1 clusters:0.05}; do
    b=${r%%:*}; skin=${r##*:}; tag=t${END:-1.0}-$b-skin$skin
    timeout ${RUN_TIMEOUT:-130} $X sphbench simulate $CASE --skin $skin --end-time ${END:-1.0} --list-build $b \
      --out $O/runs/$tag > $O/runs/$tag.txt 2>&1
    echo "== $tag (exit $?)"; summary $O/runs/$tag.txt
  done
fi
if [ "${NCU:-1}" = 1 ]; then
  S="--section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats --section MemoryWorkloadAnalysis"
  $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists_from_clusters|build_cluster_lists|cluster_boxes|column_cluster|fill_column" \
    --launch-skip 250 -c 10 $S sphbench simulate $CASE --skin 0.1 --list-build clusters --steps 400 --out /tmp/ncu-run > $O/ncu-clusters.txt 2>&1
  $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists" \
    --launch-skip 50 -c 2 $S sphbench simulate $CASE --skin 0.1 --steps 400 --out /tmp/ncu-run > $O/ncu-stencil.txt 2>&1
  for f in $O/ncu-*.txt; do
    echo "== $(basename $f)"
    grep -E "^  [a-z_].*kernel|Duration|Compute \(SM\) Throughput|Memory Throughput|Achieved Occupancy|Registers Per|Warp Cycles Per Issued|Avg. Active Threads|No kernels|==ERROR" $f | head -60
  done
fi
if [ "${MEMCHECK:-1}" = 1 ] && $X bash -c 'command -v compute-sanitizer' > /dev/null 2>&1; then
  for tool in memcheck racecheck; do
    timeout 90 $X compute-sanitizer --tool $tool sphbench simulate dsph-dambreak --set dp=0.03 \
      --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1 --list-build clusters --steps 40 \
      --out /tmp/memcheck-run > $O/$tool-clusters.txt 2>&1
    echo "== $tool, list_build=clusters: $(grep -E "ERROR SUMMARY|RACECHECK SUMMARY" $O/$tool-clusters.txt | tail -1)"
  done
fi
# At most 8 files come back from a lease: everything in one archive (the runs' steps CSVs too).
find $O/runs -name '*.h5' -delete 2>/dev/null
tar -czf /tmp/lease.tar.gz -C $O . && find $O -mindepth 1 -delete && mv /tmp/lease.tar.gz $O/
