#!/usr/bin/env bash
# Regenerates the verification report from real runs: builds impm (cmake/build.sh), then runs
# apps/verification/verification_report.py, which writes doc/verification.md and its figures in
# doc/verification/ (decks and runs under output/verification/; unchanged runs are reused).
#
#   cmake/run-verification.sh             # full report (about 30 minutes on 2 cores from scratch)
#   cmake/run-verification.sh --reduced   # short subset (a few minutes), written under output/verification/reduced/
#   cmake/run-verification.sh --check     # also assert the targets: PASS/FAIL lines, exit 1 on a failure
#   cmake/run-verification.sh --force     # rerun every case
#
# Options after these are passed to the script (--build-dir, --output-root, --doc).
# Runs are sequential with OMP_NUM_THREADS=2 (override in the environment).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake/build.sh
BUILD="${IMPM_BUILD_DIR:-build}"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-2}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
export IMPM_VERIFICATION_COMMAND="cmake/run-verification.sh${*:+ $*}"
exec /usr/bin/python3 apps/verification/verification_report.py --build-dir "$BUILD" "$@"
