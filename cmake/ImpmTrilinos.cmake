# Finds Trilinos (Trilinos_DIR, or the prefix cmake/setup-deps.sh installs into) and stops
# with one clear message if it lacks what impm needs: the Kokkos OpenMP backend, Tpetra,
# Belos, Ifpack2, Amesos2, NOX, Thyra with its Tpetra adapters, and Stratimikos. MueLu (with
# Xpetra) is optional: IMPM_TRILINOS_HAS_MUELU says whether `Preconditioner: MUELU` is available.

set(IMPM_DEFAULT_TRILINOS_PREFIX "/opt/impm/trilinos-13.2.0-openmp-muelu")
find_package(Trilinos 13.2 CONFIG QUIET HINTS "${IMPM_DEFAULT_TRILINOS_PREFIX}")
if(NOT Trilinos_FOUND)
  message(FATAL_ERROR
    "impm: Trilinos 13.2 not found. Run cmake/setup-deps.sh (it builds Trilinos with OpenMP into "
    "${IMPM_DEFAULT_TRILINOS_PREFIX}), or pass -DTrilinos_DIR=<prefix>/lib/cmake/Trilinos.")
endif()
message(STATUS "impm: Trilinos ${Trilinos_VERSION} from ${Trilinos_DIR}")

set(IMPM_REQUIRED_TRILINOS_PACKAGES
  Kokkos KokkosKernels Teuchos Tpetra Belos Ifpack2 Amesos2 NOX Thyra ThyraTpetraAdapters Stratimikos)
set(_impm_missing "")
foreach(pkg IN LISTS IMPM_REQUIRED_TRILINOS_PACKAGES)
  list(FIND Trilinos_PACKAGE_LIST ${pkg} _idx)
  if(_idx EQUAL -1)
    list(APPEND _impm_missing ${pkg})
  endif()
endforeach()
if(_impm_missing)
  message(FATAL_ERROR "impm: the Trilinos in ${Trilinos_DIR} lacks: ${_impm_missing}. "
    "Build one with cmake/setup-deps.sh or enable these packages.")
endif()

list(FIND Trilinos_PACKAGE_LIST MueLu _impm_muelu)
list(FIND Trilinos_PACKAGE_LIST Xpetra _impm_xpetra)
if(_impm_muelu EQUAL -1 OR _impm_xpetra EQUAL -1)
  set(IMPM_TRILINOS_HAS_MUELU OFF)
  message(STATUS "impm: no MueLu in this Trilinos: 'Implicit Solver/Preconditioner: MUELU' will be refused")
else()
  set(IMPM_TRILINOS_HAS_MUELU ON)
  message(STATUS "impm: MueLu found: 'Implicit Solver/Preconditioner: MUELU' available")
endif()

# The Kokkos OpenMP backend: look for KOKKOS_ENABLE_OPENMP in KokkosCore_config.h.
find_file(IMPM_KOKKOS_CONFIG KokkosCore_config.h PATHS ${Trilinos_INCLUDE_DIRS} NO_DEFAULT_PATH)
if(NOT IMPM_KOKKOS_CONFIG)
  message(FATAL_ERROR "impm: KokkosCore_config.h not found under ${Trilinos_INCLUDE_DIRS}")
endif()
file(STRINGS "${IMPM_KOKKOS_CONFIG}" _impm_openmp REGEX "^#define KOKKOS_ENABLE_OPENMP")
if(NOT _impm_openmp)
  message(FATAL_ERROR "impm: the Kokkos in ${Trilinos_DIR} has no OpenMP backend "
    "(${IMPM_KOKKOS_CONFIG} does not define KOKKOS_ENABLE_OPENMP). Debian's binary Trilinos is Serial only; "
    "run cmake/setup-deps.sh to build Trilinos 13.2 with OpenMP.")
endif()
