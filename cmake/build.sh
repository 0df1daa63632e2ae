#!/usr/bin/env bash
# Installs the dependencies (once per machine, see setup-deps.sh) and builds impm in ./build.
#   IMPM_BUILD_DIR  build directory (default: build)
#   Trilinos_DIR    use this Trilinos instead of building one
#   IMPM_WERROR     1: a compiler warning in impm's code is an error (-DIMPM_WERROR=ON)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake/setup-deps.sh
BUILD="${IMPM_BUILD_DIR:-build}"
args=(-S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release)
if [ -n "${Trilinos_DIR:-}" ]; then args+=(-DTrilinos_DIR="$Trilinos_DIR"); fi
if [ "${IMPM_WERROR:-0}" = 1 ]; then args+=(-DIMPM_WERROR=ON); else args+=(-DIMPM_WERROR=OFF); fi
cmake "${args[@]}" > /dev/null
# One translation unit with Tpetra/NOX/Belos takes up to ~700 MB to compile: 2 jobs fit anywhere.
cmake --build "$BUILD" -j "${IMPM_JOBS:-$(nproc)}"
# The whole set-up's time: on a fresh machine the Trilinos build (setup-deps.sh prints its share)
# plus impm's, about 35 minutes on 2 cores; afterwards seconds.
echo "[impm setup] dependencies and impm ready in $((SECONDS / 60)) min ($SECONDS s wall)"
