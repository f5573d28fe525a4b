#!/usr/bin/env bash
# The GPU runs behind results/reference/<gpu>/ and the figures of docs/results.md, in one command for a
# GPU machine (through tools/gpu-run.sh exec). Writes everything under $1 (default results/gpu).
# `make reference` (tools/reference.py) now runs single, accuracy and multi, resumably, into
# results/reference/<gpu>[-xN]/; this script keeps the force loop's before/after (forceloop).
#   single: benchmarks against DualSPHysics, the CUDA-vs-host test, fig4, fig3, cll-vs-vl
#   multi:  the multi-gpu experiment (figures 5 to 9), fig10 (with and without the overlap of
#           section 5.3, 1 to 4 GPUs: run it on 4) and the transports; needs 2 GPUs
#   forceloop: the force loop's before/after (issue 12): the CUDA force tests, the
#           benchmark cases with sphbench and with $BASE (an older build, when on PATH),
#           alternating (and the commands named in $EXTRA_BINS), Nsight Compute on the force kernels, and DualSPHysics beside them
#           when DSPH (its anchor folder) is set; CASE_COUNT=N runs the first N cases only,
#           CASES='a;b' these cases, NCU_CASES='a;b' these under Nsight Compute (NCU_KERNELS
#           the kernels, default regex:forces_; NCU_LAUNCH which launches, default
#           '--launch-skip 3 --launch-count 1'; NCU_SECTIONS_EXTRA more, e.g. '--section
#           MemoryWorkloadAnalysis_Tables')
#   accuracy: the CUDA tests, the accuracy sweep (needs sphbench-f64: F64=1 gpu-run.sh pack)
#           and the stability studies (issue 6)
set -uo pipefail
out=${2:-results/gpu}
mkdir -p "$out"
export NCCL_NVLS_ENABLE=0
case "${1:-single}" in
single)
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/gpu.txt"
  sph_tests --gtest_filter='CudaBackend.*:*CudaTransports*:*CudaVariants*' 2>&1 | grep -E 'cuda vs host|OK|FAILED|PASSED' | tee "$out/cuda_vs_host.txt"
  for args in "dsph-dambreak" "dsph-dambreak --set kernel=wendland --cells-per-support 2" \
              "dsph-dambreak --set dp=0.0028" "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2" \
              "armadillo --set particles=2980000" "armadillo --set particles=2980000 --merge --cells-per-support 2"; do
    echo "== sphbench simulate $args" | tee -a "$out/benchmarks.txt"
    sphbench simulate $args --steps 300 --warmup 20 --backend cuda --quiet --out "$out/simulate" 2>&1 | tee -a "$out/benchmarks.txt"
  done
  [ -x "$(command -v sph_bench)" ] && sph_bench --benchmark_format=json --benchmark_out="$out/force_loop_bench.json" \
    --benchmark_min_time=0.5 2>&1 | tail -12 | tee "$out/force_loop_bench.txt"
  for args in "armadillo --set particles=2980000" "bunny --set particles=3049000" "dsph-dambreak"; do
    echo "== sphbench simulate $args --auto-search" | tee -a "$out/calibration.txt"
    sphbench simulate $args --auto-search --steps 100 --warmup 10 --backend cuda --quiet --out "$out/simulate" 2>&1 |
      grep -E 'scene|time per step|calibration' | tee -a "$out/calibration.txt"
  done
  [ "${SKIP_FIGURES:-0}" = 1 ] && exit 0
  for spec in fig4 cll-vs-vl fig3; do sphbench run experiments/$spec.toml --backend cuda --out "$out" --force --quiet; done
  ;;
accuracy)
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/gpu.txt"
  sph_tests --gtest_filter='CudaBackend.*:*CudaTransports*:*CudaVariants*' >"$out/cuda_tests.log" 2>&1
  ok=$?
  grep -E 'cuda |OK|FAILED|PASSED' "$out/cuda_tests.log" | tee "$out/cuda_vs_host.txt"
  [ $ok -eq 0 ] || { echo "reference-runs: the CUDA tests failed; not running the studies"; exit 1; }
  sphbench run experiments/accuracy.toml --backend cuda --float64-binary "$(command -v sphbench-f64)" \
    --out "$out" --force --quiet
  for s in ${STUDIES:-stability-cfl stability-still-water stability-impact stability-armadillo}; do
    echo "== $s"
    sphbench stability experiments/$s.toml --backend cuda --out "$out/stability" --force --quiet
  done
  ;;
forceloop)
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/gpu.txt"
  sph_tests --gtest_filter='*Forces.*:CudaBackend.*:*CudaTransports*:*CudaVariants*:*StencilFluidCells*' >"$out/cuda_tests.log" 2>&1
  grep -E 'cuda |forces against|OK \]|FAILED|PASSED' "$out/cuda_tests.log" | tee "$out/cuda_tests.txt"
  cases=("dsph-dambreak" "dsph-dambreak --set kernel=wendland --cells-per-support 2"
         "dsph-dambreak --set dp=0.0028" "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2"
         "armadillo --set particles=2980000" "armadillo --set particles=2980000 --merge --cells-per-support 2"
         "dsph-dambreak --merge" "dsph-dambreak --set kernel=wendland --cells-per-support 2 --merge"
         "dsph-dambreak --set dp=0.0028 --merge"
         "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2 --merge")
  [ -n "${CASE_COUNT:-}" ] && cases=("${cases[@]:0:$CASE_COUNT}")  # the first N cases only (a short lease)
  [ -n "${CASES:-}" ] && IFS=';' read -r -a cases <<<"$CASES"      # or these cases, separated by ';'
  [ -n "${NCU_CASES:-}" ] && IFS=';' read -r -a ncu_cases <<<"$NCU_CASES" || ncu_cases=("dsph-dambreak" "armadillo --set particles=2980000")
  bins=(sphbench)
  [ -n "${BASE:-}" ] && command -v "$BASE" >/dev/null && bins=("$BASE" sphbench)
  for extra in ${EXTRA_BINS:-}; do command -v "$extra" >/dev/null && bins+=("$extra"); done
  for rep in $(seq 1 "${REPS:-1}"); do
    for args in "${cases[@]}"; do
      for bin in "${bins[@]}"; do
        echo "== $bin simulate $args (repetition $rep)" | tee -a "$out/benchmarks.txt"
        $bin simulate $args --steps 300 --warmup 20 --backend cuda --quiet --out "$out/simulate-$bin" 2>&1 |
          tee -a "$out/benchmarks.txt"
        scene=${args%% *}  # the step CSV is named after the scene: keep a copy per case
        cp "$out/simulate-$bin/${scene}_steps.csv" "$out/simulate-$bin/$(echo "$args" | tr ' =' '__')_rep$rep.csv"
      done
    done
  done
  if [ -n "${DSPH:-}" ] && [ -x "$DSPH/run.sh" ]; then bash "$DSPH/run.sh" "$out/dualsphysics" | tail -8; fi
  if [ "${NCU:-1}" = 1 ] && command -v ncu >/dev/null; then
    for args in "${ncu_cases[@]}"; do
      for bin in "${bins[@]}"; do
        echo "== ncu $bin simulate $args" | tee -a "$out/ncu.txt"
        ncu --clock-control none -k "${NCU_KERNELS:-regex:forces_}" ${NCU_LAUNCH:---launch-skip 3 --launch-count 1} \
          --section SpeedOfLight --section Occupancy --section LaunchStats --section WarpStateStats \
          --section InstructionStats --section MemoryWorkloadAnalysis ${NCU_SECTIONS_EXTRA:-} \
          --metrics smsp__thread_inst_executed_per_inst_executed.ratio,smsp__thread_inst_executed_pred_on_per_inst_executed.ratio,smsp__inst_executed.sum,l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum,l1tex__t_requests_pipe_lsu_mem_local_op_st.sum \
          $bin simulate $args --steps 6 --warmup 0 --backend cuda --quiet --out "$out/ncu-scratch" 2>&1 |
          grep -vE '^==PROF==' | tee -a "$out/ncu.txt"
      done
    done
  fi
  # The run tool brings back a limited number of files: the many small ones go in one archive.
  (cd "$out" && tar -czf runs.tar.gz simulate-* dualsphysics ncu-scratch 2>/dev/null; rm -rf simulate-* ncu-scratch)
  [ -f "$out/dualsphysics/summary.txt" ] && cp "$out/dualsphysics/summary.txt" "$out/dualsphysics-summary.txt"
  rm -rf "$out/dualsphysics"
  ;;
multi)
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/gpu.txt"
  nvidia-smi topo -m | tee "$out/topology.txt"
  sph_tests --gtest_filter='CudaBackend.*:*CudaTransports*:*CudaVariants*' >"$out/cuda_tests.log" 2>&1
  ok=$?
  grep -E 'cuda |OK|FAILED|PASSED' "$out/cuda_tests.log" | tee "$out/cuda_vs_host.txt"
  [ $ok -eq 0 ] || { echo "reference-runs: the CUDA tests failed; not running the experiment"; exit 1; }
  for spec in ${SPECS:-multi-gpu fig10 transports}; do
    sphbench run experiments/$spec.toml --backend cuda --out "$out" --force --quiet
  done
  ;;
esac
