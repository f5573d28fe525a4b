#!/usr/bin/env bash
# Change 26's A/B (docs/force-loop-notes.md, "Change 26"): main's build (.carry/bin/sphbench)
# against the branch experiment/pair-body-reciprocals (its sphbench, built for sm_90, stripped
# and packed here as .carry-cluster/sphbench-b.xz) on one machine, case by case, A then B:
#   the whole event 0-1 s of the dam break 1.04M, Wendland, half cells, lists (skin 0.1): the
#   listed kernel the change is for;
#   0-0.3 s of the same case on merged half cells, cubic, and on unmerged half cells, Wendland:
#   the per-thread cell-search kernels whose registers the change moved (perf-check).
# Carry .carry-cluster. Logs and step CSVs come back in $OUT/ab.tar.gz.
set -uo pipefail
# The run tool brings back at most 8 files: the logs and CSVs are written beside $OUT and only
# the archive goes in it.
O=${OUT:-/tmp/out}; W=$(mktemp -d); mkdir -p "$O" "$W/r"
for t in .carry-cluster/*.tar.xz; do [ -f "$t" ] && tar -xJf "$t"; done
xz -dc .carry-cluster/sphbench-b.xz > .carry/bin/sphbench-b && chmod +x .carry/bin/sphbench-b
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > "$W/r/gpu.txt"
run() {  # label end-time args...
  local label=$1 end=$2; shift 2
  for b in sphbench sphbench-b; do
    $X $b simulate dsph-dambreak --backend cuda --quiet --warmup 0 --end-time "$end" "$@" \
      --out "$W/w/$label-$b" > "$W/r/$label-$b.txt" 2>&1
    echo "$label $b: $(grep -E 'whole run|s per simulated second|Verlet lists' "$W/r/$label-$b.txt" | tr '\n' ' ')"
    tar -czf "$O/ab.tar.gz" -C "$W" r w
  done
}
run wendland-lists 1.0 --set kernel=wendland --cells-per-support 2 --verlet --skin 0.1
run cubic-merged 0.3 --cells-per-support 2 --merge
run wendland-unmerged 0.3 --set kernel=wendland --cells-per-support 2
