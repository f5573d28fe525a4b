#!/usr/bin/env bash
# One lease: the CUDA tests (variants included) and the whole events of experiments/whole-run.toml
# with Verlet lists (runs named by RUNS), results tarred under $OUT.
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
if [ "${TESTS:-1}" = 1 ]; then
  $X sph_tests --gtest_filter='CudaBackend.*:*CudaVariants*' > $O/cuda_tests.txt 2>&1; tail -4 $O/cuda_tests.txt
fi
only=(); for r in ${RUNS:-dambreak-1.04M-cubic-lists dambreak-1.04M-wendland-lists dambreak-4.04M-wendland-lists armadillo-2980K-lists armadillo-2980K-cells}; do only+=(--only $r); done
PYTHONUNBUFFERED=1 $X sphbench run experiments/whole-run.toml --backend cuda "${only[@]}" --out $O/results > $O/whole-run.txt 2>&1
grep -E "^\[|Verlet|error|failed" $O/whole-run.txt | tail -20
tar -czf $O/results.tar.gz -C $O results && rm -rf $O/results
