#!/usr/bin/env bash
# Installs everything impm needs on Debian bookworm, as root, and builds Trilinos 13.2
# with the Kokkos OpenMP backend from Debian's own source package, once per machine.
#
#   cmake/setup-deps.sh            # idempotent: a second run finds the install and skips
#
# Environment:
#   IMPM_TRILINOS_PREFIX  where the OpenMP Trilinos is installed (default /opt/impm/trilinos-13.2.0-openmp-muelu)
#   Trilinos_DIR          a Trilinos of your own: when set, nothing is built (only Debian tools are installed)
#   IMPM_JOBS             parallel build jobs (default: number of cores)
set -euo pipefail
SECONDS=0  # the whole set-up is timed; the elapsed time is printed at the end

PREFIX="${IMPM_TRILINOS_PREFIX:-/opt/impm/trilinos-13.2.0-openmp-muelu}"
WORK="${IMPM_TRILINOS_WORK:-/var/cache/impm/trilinos}"
JOBS="${IMPM_JOBS:-$(nproc)}"

log() { printf '[impm setup] %s\n' "$*"; }

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

# Debian packages: compilers, MPI, BLAS/LAPACK, build tools (clang-format-14 for the format
# check), and the plotting stack.
PACKAGES=(build-essential cmake ninja-build pkg-config clang-format-14 libopenmpi-dev openmpi-bin
          libblas-dev liblapack-dev python3 python3-matplotlib python3-numpy python3-yaml ca-certificates)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing Debian packages: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  log "Debian packages present"
fi

if [ -n "${Trilinos_DIR:-}" ]; then
  log "Trilinos_DIR=${Trilinos_DIR} given: not building Trilinos"
  exit 0
fi

# The configuration that is known to work (see doc/user-guide.md, "Installation"). Its hash is the cache key.
# Only what impm uses is built: Tpetra (double, int, long long, OpenMP node), Belos, Ifpack2,
# Amesos2 (KLU2), MueLu on Xpetra (Tpetra only), NOX with Thyra, Stratimikos (Belos, Amesos2).
TRILINOS_OPTIONS=(
  -G Ninja -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON
  -DTPL_ENABLE_MPI=ON -DTrilinos_ENABLE_OpenMP=ON
  -DTrilinos_ENABLE_ALL_OPTIONAL_PACKAGES=OFF -DTrilinos_ENABLE_TESTS=OFF -DTrilinos_ENABLE_EXAMPLES=OFF
  -DTrilinos_ENABLE_Kokkos=ON -DTrilinos_ENABLE_KokkosKernels=ON -DTrilinos_ENABLE_Teuchos=ON
  -DTrilinos_ENABLE_Tpetra=ON -DTrilinos_ENABLE_Belos=ON -DTrilinos_ENABLE_Ifpack2=ON
  -DTrilinos_ENABLE_Amesos2=ON -DAmesos2_ENABLE_KLU2=ON
  -DTrilinos_ENABLE_NOX=ON -DTrilinos_ENABLE_Thyra=ON
  -DTrilinos_ENABLE_ThyraTpetraAdapters=ON -DTrilinos_ENABLE_Stratimikos=ON
  -DTrilinos_ENABLE_Epetra=OFF
  -DKokkos_ENABLE_SERIAL=ON -DKokkos_ENABLE_OPENMP=ON
  -DTpetra_INST_SERIAL=OFF -DTpetra_INST_OPENMP=ON -DTpetra_INST_DOUBLE=ON
  -DTpetra_INST_COMPLEX_DOUBLE=OFF -DTpetra_INST_FLOAT=OFF
  -DNOX_ENABLE_ABSTRACT_IMPLEMENTATION_THYRA=ON
  -DStratimikos_ENABLE_Belos=ON -DStratimikos_ENABLE_Ifpack2=ON
  -DTrilinos_ENABLE_EXPLICIT_INSTANTIATION=ON
  -DTPL_ENABLE_BLAS=ON -DTPL_ENABLE_LAPACK=ON
  # Algebraic multigrid: MueLu on Xpetra's Tpetra back end (no Epetra, no Thyra/Stratimikos adapters:
  # impm calls MueLu::CreateTpetraPreconditioner itself). MueLu without explicit instantiation: its
  # ETI (some 250 heavy files) took longer than everything else together; impm instantiates the one
  # type it uses in solvers/MueLuPreconditioner.cpp. (MueLu_ENABLE_Kokkos_Refactor=OFF does not
  # compile in 13.2: MueLu_ClassicalMapFactory_def.hpp uses LWGraph_kokkos unconditionally.)
  -DTrilinos_ENABLE_MueLu=ON -DTrilinos_ENABLE_Xpetra=ON -DXpetra_ENABLE_Epetra=OFF -DXpetra_ENABLE_Thyra=OFF
  -DMueLu_ENABLE_Thyra=OFF -DMueLu_ENABLE_ThyraTpetraAdapters=OFF -DMueLu_ENABLE_Stratimikos=OFF
  -DMueLu_ENABLE_EXPLICIT_INSTANTIATION=OFF
  # Trims: the one global ordinal impm uses (core/Types.hpp: GO = long long); no LOCA and no NOX
  # LAPACK groups (impm drives NOX through Thyra); KokkosKernels kernels pre-instantiated only for
  # double / int ordinal / size_t offset / LayoutLeft / OpenMP on host memory (what Tpetra uses).
  -DTpetra_INST_INT_LONG_LONG=ON -DTpetra_INST_INT_INT=OFF -DTpetra_INST_INT_LONG=OFF -DTpetra_INST_INT_UNSIGNED=OFF
  -DNOX_ENABLE_LOCA=OFF -DNOX_ENABLE_ABSTRACT_IMPLEMENTATION_LAPACK=OFF
  -DKokkosKernels_INST_DOUBLE=ON -DKokkosKernels_INST_FLOAT=OFF
  -DKokkosKernels_INST_COMPLEX_DOUBLE=OFF -DKokkosKernels_INST_COMPLEX_FLOAT=OFF
  -DKokkosKernels_INST_ORDINAL_INT=ON -DKokkosKernels_INST_ORDINAL_INT64_T=OFF
  -DKokkosKernels_INST_OFFSET_SIZE_T=ON -DKokkosKernels_INST_OFFSET_INT=OFF
  -DKokkosKernels_INST_LAYOUTLEFT=ON -DKokkosKernels_INST_LAYOUTRIGHT=OFF
  -DKokkosKernels_INST_EXECSPACE_OPENMP=ON -DKokkosKernels_INST_EXECSPACE_SERIAL=OFF
  -DKokkosKernels_INST_MEMSPACE_HOSTSPACE=ON
)
# Fixes to Trilinos 13.2's source (each file says what and why), applied after unpacking; they are
# part of the cache key, so that an install built without one is rebuilt.
PATCHES=("$(cd "$(dirname "$0")" && pwd)"/trilinos-patches/*.patch)
KEY="$({ printf '%s\n' "${TRILINOS_OPTIONS[@]}"; cat "${PATCHES[@]}"; } | sha256sum | cut -c1-16)"
STAMP="$PREFIX/.impm-build-key"

if [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$KEY" ] && [ -f "$PREFIX/lib/cmake/Trilinos/TrilinosConfig.cmake" ]; then
  log "Trilinos with OpenMP found in $PREFIX (key $KEY): skipping the build (${SECONDS} s)"
  exit 0
fi

log "building Trilinos 13.2 with Kokkos OpenMP into $PREFIX (13 to 28 minutes measured on 2 cores, once per machine)"
$SUDO mkdir -p "$WORK"
cd "$WORK"

if [ ! -f trilinos_13.2.0.orig.tar.gz ]; then
  # Debian's source index: add a deb-src entry for bookworm main beside the deb entry.
  if ! grep -rqs "deb-src" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    log "adding a deb-src entry for bookworm main"
    $SUDO tee /etc/apt/sources.list.d/impm-deb-src.sources >/dev/null <<'SRC'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
  fi
  $SUDO apt-get update -qq
  apt-get source --download-only trilinos
fi
if [ ! -d Trilinos-trilinos-release-13-2-0 ]; then
  log "unpacking the source"
  tar xzf trilinos_13.2.0.orig.tar.gz
fi
for p in "${PATCHES[@]}"; do
  if patch -d Trilinos-trilinos-release-13-2-0 -p1 -R -s -f --dry-run < "$p" > /dev/null 2>&1; then
    continue  # applied by an earlier run
  fi
  log "patching the source: $(basename "$p")"
  patch -d Trilinos-trilinos-release-13-2-0 -p1 -s -f < "$p"
done

rm -rf build && mkdir build && cd build
cmake ../Trilinos-trilinos-release-13-2-0 "${TRILINOS_OPTIONS[@]}" -DCMAKE_INSTALL_PREFIX="$PREFIX" > configure.log 2>&1 \
  || { tail -50 configure.log; echo "[impm setup] Trilinos configure failed; full log: $WORK/build/configure.log" >&2; exit 1; }
log "configured; compiling with $JOBS jobs (log: $WORK/build/build.log)"
ninja -j"$JOBS" > build.log 2>&1 || { tail -50 build.log; echo "[impm setup] Trilinos build failed; full log: $WORK/build/build.log" >&2; exit 1; }
$SUDO ninja install > install.log 2>&1
echo "$KEY" | $SUDO tee "$STAMP" >/dev/null
log "Trilinos installed in $PREFIX"
# Keep the unpacked source and tarball out of the way but drop the build tree (about 3 GB).
cd "$WORK" && rm -rf build
log "Trilinos built and installed in $((SECONDS / 60)) min ($SECONDS s wall)"
