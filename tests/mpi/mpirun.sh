#!/usr/bin/env bash
# `adamss ARGS` under mpirun on MPI_RANKS ranks (default 2, oversubscribed if need be), for test
# scripts that take the adamss command as one path (cases/hard/check.cmake):
#   MPIEXEC=/usr/bin/mpiexec ADAMSS_BIN=build/app/adamss tests/mpi/mpirun.sh run SCENE -o OUT
set -euo pipefail
exec "${MPIEXEC:?set MPIEXEC}" --oversubscribe -np "${MPI_RANKS:-2}" "${ADAMSS_BIN:?set ADAMSS_BIN}" "$@"
