#!/bin/sh
# Run by mpirun on every rank: rank 1 starts sphbench and kills it (SIGKILL) after a second,
# a rank that dies mid-run; the others run sphbench normally. Arguments: sphbench and its
# arguments.
if [ "${OMPI_COMM_WORLD_RANK:-0}" = 1 ]; then
  "$@" &
  pid=$!
  sleep 1
  kill -9 "$pid"
  wait "$pid"
  exit $?
fi
exec "$@"
