#!/usr/bin/env bash
# One lease: the CUDA tests (variants included) and the whole events of experiments/whole-run.toml
# with Verlet lists (runs named by RUNS), each run into its own folder and archive under $OUT as
# soon as it ends (a lease taken back mid-call still returns what finished).
set -uo pipefail
O=${OUT:-/tmp/out}; mkdir -p $O
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > $O/gpu.txt
if [ "${TESTS:-1}" = 1 ]; then
  $X sph_tests --gtest_filter='CudaBackend.*:*CudaVariants*' > $O/cuda_tests.txt 2>&1; tail -4 $O/cuda_tests.txt
fi
for r in ${RUNS:-dambreak-1.04M-cubic-lists dambreak-1.04M-wendland-lists armadillo-2980K-lists armadillo-2980K-cells dambreak-4.04M-wendland-lists}; do
  PYTHONUNBUFFERED=1 $X sphbench run experiments/whole-run.toml --backend cuda --only $r --out $O/$r > $O/$r.txt 2>&1
  grep -E "^\[|Verlet|error|failed" $O/$r.txt | tail -3
  tar -czf $O/$r.tar.gz -C $O $r && rm -rf $O/$r
done
