#!/usr/bin/env bash
# Is skin 0.1 still the cheapest over the whole event now that a rebuild costs less?
# (docs/force-loop-notes.md, "The skin after change 22: predicted"). The dam break 1.04M,
# Wendland, half cells, lists, 0-1 s, at skin 0.05, 0.07 and 0.1, one binary (.carry/bin/sphbench)
# on one machine. Carry .carry-cluster. Logs and step CSVs come back in $OUT/skin.tar.gz.
set -uo pipefail
# The run tool brings back at most 8 files: the logs and CSVs are written beside $OUT and only
# the archive goes in it.
. "$(dirname "$0")/prologue.sh"
for skin in ${SKINS:-0.07 0.05 0.1}; do
  $X sphbench simulate dsph-dambreak --backend cuda --quiet --warmup 0 --end-time 1.0 --set kernel=wendland \
    --cells-per-support 2 --verlet --skin "$skin" --out "$W/w/skin-$skin" > "$W/r/skin-$skin.txt" 2>&1
  echo "skin $skin: $(grep -E 's per simulated second|Verlet lists' "$W/r/skin-$skin.txt" | tr '\n' ' ')"
  tar -czf "$O/skin.tar.gz" -C "$W" r w
done
