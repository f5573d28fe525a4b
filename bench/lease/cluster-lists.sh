#!/usr/bin/env bash
# One lease for change 14 (cluster pair lists, list_layout = cluster; docs/force-loop-notes.md):
# the CUDA tests of the lists, DualSPHysics' dam break 1.04M (Wendland, half cells, skin 0.1)
# with per-particle lists and with cluster lists (both walks) to 0.2 s (a quick look), with
# per-particle and cluster lists over the whole event (0 to 1 s), ncu of the new kernels (and of
# the per-particle lists' beside them), and compute-sanitizer's memcheck of a small run. Each part
# writes under $OUT as soon as it ends (a lease taken back mid-call still returns what finished);
# about 5 minutes of device time, most of it the two whole events (~50-70 s each).
#
#   here:  tools/gpu-run.sh pack             (builds build-gpu/ for sm_90 and fills .carry/)
#   there: bench/lease/cluster-lists.sh      (carry .carry; through the run tool: OUT is set)
#
# Knobs: TESTS=0, QUICK=0, WHOLE=0, NCU=0, MEMCHECK=0 skip a part; LAYOUTS (whole events,
# "auto cluster"), QUICK_LAYOUTS ("auto cluster cluster-hit-masks"), NCU_LAYOUT ("cluster"),
# RUN_TIMEOUT (130 s a run).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/runs
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
cp .carry/commit $O/commit.txt 2>/dev/null
CASE="dsph-dambreak --set dp=0.0045 --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
# What a run's summary says of the whole run and its lists (s_per_sim_s, list_rebuilds,
# rebuild_step_ms, listed_step_ms, list_bytes_per_particle), one block per run.
summary() { grep -E "^run:|^whole run|^Verlet lists|^time per step|^memory|^neighbour pairs|[Ee]rror" "$1" | sed 's/^/  /'; }

if [ "${TESTS:-1}" = 1 ]; then
  timeout 200 $X sph_tests --gtest_filter='CudaBackend.ClusterLists*:*CudaVariants*list_layout*' > $O/cuda_tests.txt 2>&1
  grep -E "cuda vs host|cuda, cluster|PASSED|FAILED" $O/cuda_tests.txt | tail -16
fi
run() {  # tag, end time, layout
  timeout ${RUN_TIMEOUT:-130} $X sphbench simulate $CASE --end-time $2 --list-layout $3 --out $O/runs/$1 > $O/runs/$1.txt 2>&1
  echo "== $1 (end time $2 s, list_layout=$3, exit $?)"; summary $O/runs/$1.txt
}
if [ "${QUICK:-1}" = 1 ]; then
  for l in ${QUICK_LAYOUTS:-auto cluster cluster-hit-masks}; do run t0.2-$l 0.2 $l; done
fi
if [ "${WHOLE:-1}" = 1 ]; then
  for l in ${LAYOUTS:-auto cluster}; do run t1.0-$l 1.0 $l; done
fi
if [ "${NCU:-1}" = 1 ]; then
  NCU_SECTIONS="--section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats"
  # The new kernels of the first rebuild (each column's clusters, their first particles, the
  # boxes, the lists); then a stretch of a flowing run (~0.01 s in: a rebuild and its listed
  # steps) with cluster lists, and the same stretch with per-particle lists for comparison.
  $X ncu --clock-control none --kernel-name-base demangled -k regex:cluster -c 4 $NCU_SECTIONS \
    sphbench simulate $CASE --list-layout cluster --steps 20 --out /tmp/ncu-run > $O/ncu-cluster-build.txt 2>&1
  $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_cluster_lists|forces_cluster_listed" \
    --launch-skip 300 -c 12 $NCU_SECTIONS --section MemoryWorkloadAnalysis \
    sphbench simulate $CASE --list-layout ${NCU_LAYOUT:-cluster} --steps 400 --out /tmp/ncu-run > $O/ncu-cluster-flow.txt 2>&1
  $X ncu --clock-control none --kernel-name-base demangled -k regex:"build_lists|forces_listed" \
    --launch-skip 300 -c 12 $NCU_SECTIONS --section MemoryWorkloadAnalysis \
    sphbench simulate $CASE --list-layout auto --steps 400 --out /tmp/ncu-run > $O/ncu-particle-flow.txt 2>&1
  for f in $O/ncu-*.txt; do
    echo "== $(basename $f)"
    grep -E "^  [a-z_].*kernel|Duration|Compute \(SM\) Throughput|Memory Throughput|Achieved Occupancy|Registers Per|Warp Cycles Per Issued|No kernels|==ERROR" $f | head -40
  done
fi
if [ "${MEMCHECK:-1}" = 1 ] && $X bash -c 'command -v compute-sanitizer' > /dev/null 2>&1; then
  for l in cluster cluster-hit-masks; do
    timeout 60 $X compute-sanitizer --tool memcheck --leak-check no sphbench simulate dsph-dambreak --set dp=0.03 \
      --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1 --list-layout $l --steps 40 \
      --out /tmp/memcheck-run > $O/memcheck-$l.txt 2>&1
    echo "== memcheck, list_layout=$l: $(grep -E "ERROR SUMMARY" $O/memcheck-$l.txt | tail -1)"
  done
fi
tar -czf $O/runs.tar.gz -C $O runs && rm -rf $O/runs
