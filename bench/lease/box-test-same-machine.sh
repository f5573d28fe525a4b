#!/usr/bin/env bash
# Change 22's box test against its first step on one machine: the whole event 0-1 s (dam break
# 1.04M, Wendland, half cells, skin 0.1) with the box-test build (.carry/bin/sphbench) and the
# build without it (.carry-cluster/extra/sphbench-nobox.xz, main's kernel), then the 4.04M case
# 0-0.3 s with the box-test build. Carry .carry-cluster. Logs and steps CSVs in $OUT/whole.tar.gz.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O/r
for t in .carry-cluster/*.tar.xz; do [ -f "$t" ] && tar -xJf "$t"; done
xz -dc .carry-cluster/extra/sphbench-nobox.xz > .carry/bin/sphbench-nobox && chmod +x .carry/bin/sphbench-nobox
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/r/gpu.txt
CASE="dsph-dambreak --set kernel=wendland --backend cuda --quiet --warmup 0 --verlet --cells-per-support 2 --skin 0.1"
for b in sphbench-nobox sphbench; do
  $X $b simulate $CASE --end-time 1.0 --out $O/w/$b > $O/r/whole-$b.txt 2>&1
  grep -E "whole run|Verlet lists" $O/r/whole-$b.txt
  tar -czf $O/whole.tar.gz -C $O r w
done
$X sphbench simulate $CASE --set dp=0.0028 --end-time 0.3 --out $O/w/box-4.04M > $O/r/whole-box-4.04M.txt 2>&1
grep -E "whole run|Verlet lists|memory" $O/r/whole-box-4.04M.txt
tar -czf $O/whole.tar.gz -C $O r w
