#!/usr/bin/env bash
# Builds impm and runs its test suite with ctest, on 1 and on 2 OpenMP threads.
# Extra arguments go to ctest (e.g. -L unit, -L mpi, -R Transfer).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake/build.sh
BUILD="${IMPM_BUILD_DIR:-build}"
cd "$BUILD"
export OMP_PROC_BIND=false
echo "== ctest, OMP_NUM_THREADS=1"
OMP_NUM_THREADS=1 ctest --output-on-failure "$@"
echo "== ctest, OMP_NUM_THREADS=2"
OMP_NUM_THREADS=2 ctest --output-on-failure "$@"
