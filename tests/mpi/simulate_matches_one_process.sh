#!/bin/sh
# sphbench simulate with snapshots, once in one process and once under mpirun with the same
# subdomains; rank 0 writes the MPI run's snapshots, which must match the one-process run's
# bitwise by id (the one-process run without the communication overlap, the MPI run with
# it). Arguments: mpirun, ranks, sphbench, python, compare script, a scratch folder.
set -eu
mpirun=$1 ranks=$2 sphbench=$3 python=$4 compare=$5 out=$6
rm -rf "$out"
args="simulate dambreak --set dp=0.05 --backend host --devices 4 --balancer simple --steps 12 --warmup 0 --snapshot-every 3 --quiet"
"$sphbench" $args --no-overlap --out "$out/one"  # paper 5.3's overlap off here, on (the default) under mpirun
"$mpirun" --oversubscribe -np "$ranks" "$sphbench" $args --out "$out/mpi"
[ -f "$out/mpi/dambreak_steps.csv" ] || { echo "rank 0 wrote no step CSV"; exit 1; }
"$python" "$compare" "$out/one/dambreak_snapshots" "$out/mpi/dambreak_snapshots"
