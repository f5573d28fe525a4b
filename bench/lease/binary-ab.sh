#!/usr/bin/env bash
# Two builds of sphbench on one machine, case by case, back to back: another build, packed here
# as .carry-cluster/sphbench-other.xz (stripped, xz; e.g. the build before a change), then the
# carried one (.carry/bin/sphbench). The dam break 1.04M:
#   wendland-lists, cubic-lists: the whole event 0-1 s with lists (half cells, skin 0.1);
#   cubic-merged, wendland-merged, wendland-unmerged: 0-0.3 s with the cell search (half cells,
#   merged or not).
# CASES picks and orders them (default: all five); BUILDS="sphbench-other" runs the other build
# alone (where the carried build's runs come from `make reference`'s items in the same call).
# NCU=1 adds ncu of forces_kernel (the 201st launch) for both builds on the cell-search case
# NCU_CASE (default wendland-unmerged).
# Carry .carry-cluster. Logs, step CSVs and ncu reports come back in $OUT/ab.tar.gz.
set -uo pipefail
# The run tool brings back at most 8 files: everything is written beside $OUT and only the
# archive goes in it.
. "$(dirname "$0")/prologue.sh"
[ -x .carry/bin/sphbench-other ] || { echo "binary-ab: no .carry-cluster/sphbench-other.xz to compare with"; exit 2; }
declare -A CASE=(
  [wendland-lists]="1.0 --set kernel=wendland --cells-per-support 2 --verlet --skin 0.1"
  [cubic-lists]="1.0 --cells-per-support 2 --verlet --skin 0.1"
  [cubic-merged]="0.3 --cells-per-support 2 --merge"
  [wendland-merged]="0.3 --set kernel=wendland --cells-per-support 2 --merge"
  [wendland-unmerged]="0.3 --set kernel=wendland --cells-per-support 2"
)
for label in ${CASES:-wendland-lists cubic-lists cubic-merged wendland-merged wendland-unmerged}; do
  set -- ${CASE[$label]}; end=$1; shift
  for b in ${BUILDS:-sphbench-other sphbench}; do
    $X $b simulate dsph-dambreak --backend cuda --quiet --warmup 0 --end-time "$end" "$@" \
      --out "$W/w/$label-$b" > "$W/r/$label-$b.txt" 2>&1
    echo "$label $b: $(grep -E 's per simulated second|Verlet lists' "$W/r/$label-$b.txt" | tr '\n' ' ')"
    tar -czf "$O/ab.tar.gz" -C "$W" r w
  done
done
if [ "${NCU:-0}" = 1 ]; then
  set -- ${CASE[${NCU_CASE:-wendland-unmerged}]}; shift
  for b in sphbench-other sphbench; do
    $X ncu --clock-control none --kernel-name regex:'^forces_kernel' --launch-skip 200 --launch-count 1 \
      --section SpeedOfLight --section Occupancy --section WarpStateStats --section MemoryWorkloadAnalysis \
      --section LaunchStats --section SourceCounters \
      $b simulate dsph-dambreak --backend cuda --quiet --warmup 0 --steps 210 "$@" \
      --out "$W/w/ncu-$b" > "$W/r/ncu-forces-$b.txt" 2>&1
    echo "ncu $b: $(grep -E 'Duration|Registers Per|Achieved Occupancy|Local Memory|Warp Cycles Per Issued' "$W/r/ncu-forces-$b.txt" | tr -s ' ' | tr '\n' ';')"
    tar -czf "$O/ab.tar.gz" -C "$W" r w
  done
fi
