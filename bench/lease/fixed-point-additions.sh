#!/usr/bin/env bash
# The rate of j's 64-bit fixed-point additions a symmetric cluster-pair loop would make
# (docs/force-loop-notes.md, "j's side counted"): global (L2-resident accumulators) and shared
# memory, at the 1.04M dam break's size and at 4.04M, 40 listed clusters a warp (a half list at
# rest). Seconds of device time. The loop is worth building if global additions reach ~3e11 a
# second (26-60M a step in under ~0.2 ms).
#
#   here:  tools/gpu-run.sh pack      there: bench/lease/fixed-point-additions.sh
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/fixed-point-additions-gpu.txt
for n in 1040000 4040000; do $X fixed_point_additions $n 40; done 2>&1 | tee $O/fixed-point-additions.txt
