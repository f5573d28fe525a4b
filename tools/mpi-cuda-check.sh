#!/usr/bin/env bash
# MPI runs with CUDA subdomains on a GPU machine (issue 13, item 2), through the carried
# binaries:
#
#   tools/gpu-run.sh exec bash tools/mpi-cuda-check.sh OUT_DIR
#
# 0. CudaBackend.PinnedRankStagingCarriesPiecesBitwise: the staging alone, without MPI.
# 1. `sphbench simulate` of a small dam break on the CUDA backend with 2 subdomains, in one
#    process and under `mpirun -np 2` (with --share-gpus when the machine has one GPU), with
#    paper 5.3's overlap and with --no-overlap: the snapshots of every MPI run must be bitwise
#    those of the one-process run without overlap (tests/mpi/compare_snapshots.py, as the
#    mpi_sphbench_simulate_* ctests; it needs h5py), and each run's time per step and
#    rank_transport are printed.
# 2. sph_mpi_equivalence (the mpi_*_match_one_process ctests' program) with the cuda word: every
#    step, every particle against one process in the same job; 2 subdomains, and 4 with the
#    simple balancer moving slabs across the rank boundary; overlap on and off; the cell search
#    and Verlet lists (rebuilt every 5 steps, ghosts refreshed in place between rebuilds).
# 3. Bad input, each a non-zero exit with its sentence: more ranks than GPUs without
#    --share-gpus, a device map naming a GPU the rank lacks, --gpu-direct of an MPI without
#    CUDA support (a CUDA-aware MPI runs it, staged, and says so), also in one process.
# Everything goes under OUT_DIR (logs, snapshots, summary.txt). Exit 1 on any mismatch or a
# refusal that did not come; 0 otherwise. Without mpirun, or when mpirun cannot start this
# sphbench (its libmpi is the build machine's, carried in .carry/lib), the MPI part is skipped
# with a line saying so, and the rest still runs.
set -uo pipefail
OUT=${1:?usage: tools/mpi-cuda-check.sh OUT_DIR}
cd "$(dirname "$0")/.."
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
SUMMARY=$OUT/summary.txt
: >"$SUMMARY"
FAILED=0
note() { echo "$*" | tee -a "$SUMMARY"; }
fail() { note "FAIL: $*"; FAILED=1; }

SPHBENCH=${SPHBENCH:-$(command -v sphbench || true)}
EQUIV=${SPH_MPI_EQUIVALENCE:-$(command -v sph_mpi_equivalence || true)}
[ -n "$SPHBENCH" ] || { note "FAIL: no sphbench on PATH (run through tools/gpu-run.sh exec after pack)"; exit 1; }
PYTHON=${PYTHON:-python3}
COMPARE=tests/mpi/compare_snapshots.py
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}

note "which mpirun: $(command -v mpirun || echo 'not found')"
command -v mpirun >/dev/null && mpirun --version 2>&1 | head -1 | sed 's/^/mpirun version: /' | tee -a "$SUMMARY"
note "sphbench: $SPHBENCH"
"$SPHBENCH" info 2>&1 | grep -E '^(commit|GPUs)' | tee -a "$SUMMARY"
GPUS=$(nvidia-smi -L 2>/dev/null | grep -c '^GPU' || true)
[ "${GPUS:-0}" -ge 1 ] || GPUS=1
note "GPU count (nvidia-smi -L): $GPUS"
SHARE=()
[ "$GPUS" -lt 2 ] && SHARE=(--share-gpus)
HAVE_H5PY=1
"$PYTHON" -c 'import h5py' 2>/dev/null || { HAVE_H5PY=0; note "python3 has no h5py: snapshots are not compared (sph_mpi_equivalence still compares every step)"; }

# mpirun with the carried binaries' environment passed to every rank.
MPIRUN=(mpirun --oversubscribe --allow-run-as-root -x PATH -x LD_LIBRARY_PATH -x SPH_MESH_DIR -x OMP_NUM_THREADS
        -x OMPI_ALLOW_RUN_AS_ROOT -x OMPI_ALLOW_RUN_AS_ROOT_CONFIRM)
MPI_OK=0
if ! command -v mpirun >/dev/null; then
  note "SKIPPED: mpirun is not on this machine, so the MPI part is skipped (OpenMPI would have to be carried)"
elif ! "${MPIRUN[@]}" -np 2 "$SPHBENCH" info >"$OUT/mpirun-sanity.log" 2>&1; then
  note "SKIPPED: mpirun is here but could not start 2 ranks of this sphbench (see $OUT/mpirun-sanity.log: the carried libmpi and this mpirun may disagree), so the MPI part is skipped"
else
  MPI_OK=1
fi

# SPH_CHECK_BACKEND=host tries parts 1 and 2 of this script on a machine without a GPU.
BACKEND=${SPH_CHECK_BACKEND:-cuda}
EXPECTED_RANK_TRANSPORT=staged-pinned
[ "$BACKEND" = host ] && EXPECTED_RANK_TRANSPORT=host-memory
SCENE=(dambreak --set dp=0.02 --backend "$BACKEND" --devices 2 --steps 40 --warmup 5 --snapshot-every 10 --quiet)
# simulate NAME [mpirun args --] sphbench args...: runs, logs, prints the time per step and rank_transport.
simulate() {
  local name=$1; shift
  local log=$OUT/$name.log
  if "$@" --out "$OUT/$name" >"$log" 2>&1; then
    note "$name: $(grep -m1 '^time per step' "$log"); rank_transport: $(grep -m1 '^rank_transport' "$log" | cut -d' ' -f2- || true)"
    grep -m1 '^transport between' "$log" | sed "s/^/  $name: /" | tee -a "$SUMMARY"
  else
    fail "$name exited $? (see $log): $(tail -3 "$log" | tr '\n' ' ')"
  fi
}
compare() {  # compare REFERENCE CANDIDATE
  [ "$HAVE_H5PY" = 1 ] || return 0
  if "$PYTHON" "$COMPARE" "$OUT/$1/dambreak_snapshots" "$OUT/$2/dambreak_snapshots" >"$OUT/compare-$2.log" 2>&1; then
    note "$2 against $1: $(cat "$OUT/compare-$2.log")"
  else
    fail "$2 against $1: $(cat "$OUT/compare-$2.log")"
  fi
}

note "--- 0. the pinned staging without MPI (sph_tests CudaBackend.PinnedRankStaging*)"
if command -v sph_tests >/dev/null; then
  if sph_tests --gtest_filter='CudaBackend.PinnedRankStaging*' >"$OUT/pinned-staging.log" 2>&1; then
    note "pinned staging: $(grep -m1 -E '^\[ +(PASSED|SKIPPED) +\]' "$OUT/pinned-staging.log")"
  else
    fail "pinned staging (see $OUT/pinned-staging.log)"
  fi
else
  note "SKIPPED: no sph_tests on PATH"
fi

note "--- 1. sphbench simulate, $BACKEND backend, 2 subdomains"
simulate one-process-no-overlap "$SPHBENCH" simulate "${SCENE[@]}" --no-overlap
simulate one-process-overlap "$SPHBENCH" simulate "${SCENE[@]}"
compare one-process-no-overlap one-process-overlap
if [ "$MPI_OK" = 1 ]; then
  simulate mpi-2-ranks-overlap "${MPIRUN[@]}" -np 2 "$SPHBENCH" simulate "${SCENE[@]}" "${SHARE[@]}"
  simulate mpi-2-ranks-no-overlap "${MPIRUN[@]}" -np 2 "$SPHBENCH" simulate "${SCENE[@]}" "${SHARE[@]}" --no-overlap
  for run in mpi-2-ranks-overlap mpi-2-ranks-no-overlap; do
    [ -f "$OUT/$run/dambreak_steps.csv" ] || fail "$run: rank 0 wrote no step CSV"
    grep -q "^# rank_transport: $EXPECTED_RANK_TRANSPORT" "$OUT/$run/dambreak_steps.csv" 2>/dev/null ||
      fail "$run: the step CSV does not say rank_transport: $EXPECTED_RANK_TRANSPORT"
    compare one-process-no-overlap "$run"
  done
fi

note "--- 2. sph_mpi_equivalence on the $BACKEND backend (every step, against one process)"
if [ "$MPI_OK" = 1 ] && [ -n "$EQUIV" ]; then
  share_word=() backend_word=()
  [ "$BACKEND" = cuda ] && backend_word=(cuda)
  [ "$GPUS" -lt 2 ] && share_word=(share-gpus)
  # Each with the cell search, and with Verlet lists (ghosts refreshed between rebuilds).
  for c in "2 none" "4 simple"; do
    for o in "" no-overlap; do
      for l in "" verlet; do
        name="equivalence-${c// /-}${o:+-$o}${l:+-$l}"
        if "${MPIRUN[@]}" -np 2 "$EQUIV" $c 40 $o $l "${backend_word[@]}" "${share_word[@]}" >"$OUT/$name.log" 2>&1; then
          note "$name: $(grep -m1 'bitwise' "$OUT/$name.log")"
        else
          fail "$name (see $OUT/$name.log): $(grep -v '^\s*$' "$OUT/$name.log" | head -3 | tr '\n' ' ')"
        fi
      done
    done
  done
elif [ "$MPI_OK" = 1 ]; then
  note "SKIPPED: no sph_mpi_equivalence on PATH (tools/gpu-run.sh pack copies it from build-gpu/tests/)"
fi

note "--- 3. bad input: a non-zero exit and one sentence each"
# refused NAME PATTERN CMD...: the command must exit non-zero and say PATTERN.
refused() {
  local name=$1 pattern=$2; shift 2
  local log=$OUT/bad-$name.log
  "$@" >"$log" 2>&1
  local rc=$?
  local sentence
  sentence=$(grep -m1 -E "$pattern" "$log" || true)
  if [ "$rc" -ne 0 ] && [ -n "$sentence" ]; then
    note "$name: exit $rc: $sentence"
  else
    fail "$name: exit $rc, expected a non-zero exit saying /$pattern/ (see $log)"
  fi
}
TINY=(dambreak --set dp=0.05 --steps 2 --warmup 0 --quiet --out "$OUT/bad")
CUDA=(--backend cuda)
MISSING_GPU=7
[ "$GPUS" -gt 7 ] && MISSING_GPU=$GPUS
refused one-process-device-map-gpu-$MISSING_GPU "puts subdomain 1 on GPU $MISSING_GPU" \
  "$SPHBENCH" simulate "${TINY[@]}" "${CUDA[@]}" --devices 2 --device-map 0 "$MISSING_GPU"
refused one-process-gpu-direct "GPU-direct .*one process" "$SPHBENCH" simulate "${TINY[@]}" "${CUDA[@]}" --devices 2 --gpu-direct
if [ "$MPI_OK" = 1 ]; then
  np=$((GPUS + 1))
  refused "$np-ranks-on-$GPUS-gpus-without-share" "share-gpus" \
    "${MPIRUN[@]}" -np "$np" "$SPHBENCH" simulate "${TINY[@]}" "${CUDA[@]}" --devices "$np"
  refused mpi-device-map-gpu-$MISSING_GPU "the device map .* puts subdomain 1 on GPU $MISSING_GPU, but rank 1 sees" \
    "${MPIRUN[@]}" -np 2 "$SPHBENCH" simulate "${TINY[@]}" "${CUDA[@]}" --devices 2 --device-map 0 "$MISSING_GPU" "${SHARE[@]}"
  refused mpi-gpu-direct-on-host "GPU-direct .*host backend" \
    "${MPIRUN[@]}" -np 2 "$SPHBENCH" simulate "${TINY[@]}" --devices 2 --backend host --gpu-direct
  # An MPI without CUDA support refuses; a CUDA-aware one runs it staged and says so.
  log=$OUT/bad-mpi-gpu-direct.log
  if "${MPIRUN[@]}" -np 2 "$SPHBENCH" simulate "${TINY[@]}" "${CUDA[@]}" --devices 2 --gpu-direct "${SHARE[@]}" >"$log" 2>&1; then
    note "mpi-gpu-direct: this MPI is CUDA-aware; ran staged: $(grep -m1 '^rank_transport' "$log")"
  else
    rc=$?
    sentence=$(grep -m1 'has no CUDA support' "$log" || true)
    if [ -n "$sentence" ]; then note "mpi-gpu-direct: exit $rc: $sentence"
    else fail "mpi-gpu-direct: exit $rc without the sentence (see $log)"; fi
  fi
fi

if [ "$FAILED" = 0 ]; then note "mpi-cuda-check: all passed$([ "$MPI_OK" = 1 ] || echo ' (MPI PART SKIPPED)')"
else note "mpi-cuda-check: FAILED (see $SUMMARY)"; fi
exit "$FAILED"
