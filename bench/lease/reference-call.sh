#!/usr/bin/env bash
# One call of `make reference` on a lent GPU machine (docs/gpu-machines.md), within the run tool's
# 64 MiB carried and 8 files back:
#   here, once:   F64=1 tools/gpu-run.sh pack
#                 LEASE_BINARIES="sphbench sph_tests sph_bench sph_skip_bench sphbench-f64" tools/gpu-run.sh lease
#                 (the archive, and whether the tree and it fit the 64 MiB; it names what to set aside)
#                 python3 tools/reference.py --pack-dsph          (.dsph/, for DualSPHysics' items)
#   there:        call 1 carries .carry-cluster (the tree and it fit; .carry/ is unpacked there and,
#                 being ignored, stays for the calls after it while the machine stays warm);
#                 a call that runs DualSPHysics carries .dsph instead (the tree, .carry-cluster and
#                 .dsph together pass 64 MiB).
#     bash bench/lease/reference-call.sh BUDGET_S [ITEMS...]
#     (FORCE=1: run the items even where their stamps say up to date, e.g. ours again beside
#     DualSPHysics' whole events on the machine that runs those)
#   here, after each call, before the next: tar -xzf <files_at>/reference.tar.gz (or, in parts,
#   cat <files_at>/reference.tar.gz.part* | tar -xz): the next call's tree replaces the machine's
#   results/reference/.
set -uo pipefail
. "$(dirname "$0")/prologue.sh"
[ -x .carry/bin/sphbench ] || { echo "reference-call: no .carry/bin/sphbench: carry .carry-cluster (this machine is a fresh one)"; exit 2; }
[ -d .dsph ] && export DSPH=$PWD/.dsph
budget=${1:?usage: reference-call.sh BUDGET_S [ITEMS...]}; shift
cp "$W/r/gpu.txt" "$O/gpu.txt"
PYTHONUNBUFFERED=1 REFERENCE_ARCHIVE="$O/reference.tar.gz" REFERENCE_BUDGET_S="$budget" REFERENCE_ONLY="$*" \
  tools/gpu-run.sh exec python3 tools/reference.py ${FORCE:+--force} 2>&1 | tee "$O/reference.log" | grep -E "^\[|^reference:|estimate"
