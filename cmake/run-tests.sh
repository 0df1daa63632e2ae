#!/usr/bin/env bash
# Builds impm and runs its test suite with ctest, on 1 and on 2 OpenMP threads.
# Extra arguments go to ctest (e.g. -L unit, -L mpi, -R Transfer).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake/build.sh
BUILD="${IMPM_BUILD_DIR:-build}"
cd "$BUILD"
export OMP_PROC_BIND=false
# Waiting OpenMP threads sleep instead of spinning, so that the suite keeps its pace on a loaded
# machine (ctest sets it for each test too; see test/CMakeLists.txt and doc/user-guide.md, "Tests").
export OMP_WAIT_POLICY=passive
# The verification label (reduced report and refinement studies, a few minutes) and the install
# label (install, then build and run a consumer project) run once, at 2 threads. The mpi label
# runs once, in the first pass: its ranks run one thread each whatever OMP_NUM_THREADS says
# (test/CMakeLists.txt), so a second pass would repeat the same runs; the format label (the
# sources' clang-format layout) does not depend on threads either. The study label
# (verification studies of half an hour: ctest -L study) does not run at all. Everything else
# runs at 1 and at 2 threads.
echo "== ctest, OMP_NUM_THREADS=1 (all but the verification, install and study labels)"
OMP_NUM_THREADS=1 ctest --output-on-failure -LE "verification|install|study" "$@"
echo "== ctest, OMP_NUM_THREADS=2 (all but the mpi, format and study labels)"
OMP_NUM_THREADS=2 ctest --output-on-failure -LE "mpi|format|study" "$@"
