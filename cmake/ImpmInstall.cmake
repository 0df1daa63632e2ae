# `cmake --install <build> --prefix <P>` lays impm out as
#   P/lib/libimpm.a                         the library (CMake target impm::impm)
#   P/include/impm/{core,physics,solvers}/  its headers: `#include "core/InputDeck.hpp"` with
#                                           P/include/impm on the include path (impm::impm adds it)
#   P/bin/impm                              the driver
#   P/share/impm/plot_history.py            the driver's plot script (found relative to P/bin/impm)
#   P/share/impm/decks/*.yaml               the decks of apps/
#   P/share/doc/impm/                       README.md and doc/*.md
#   P/lib/cmake/impm/                       impmConfig.cmake, impmConfigVersion.cmake, impmTargets.cmake
# A consumer: find_package(impm CONFIG REQUIRED) with CMAKE_PREFIX_PATH=P, then link impm::impm
# (doc/user-guide.md, "Install and link").
include(CMakePackageConfigHelpers)

set(IMPM_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/impm")

install(TARGETS impm_lib EXPORT impmTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
install(TARGETS impm RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
install(DIRECTORY core physics solvers
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/impm"
        FILES_MATCHING PATTERN "*.hpp")
install(PROGRAMS apps/plot_history.py DESTINATION "${IMPM_INSTALL_DATADIR}")
file(GLOB impm_decks "${PROJECT_SOURCE_DIR}/apps/*.yaml")
install(FILES ${impm_decks} DESTINATION "${IMPM_INSTALL_DATADIR}/decks")
file(GLOB impm_docs "${PROJECT_SOURCE_DIR}/doc/*.md")
install(FILES "${PROJECT_SOURCE_DIR}/README.md" ${impm_docs} DESTINATION "${CMAKE_INSTALL_DOCDIR}")

install(EXPORT impmTargets NAMESPACE impm:: FILE impmTargets.cmake DESTINATION "${IMPM_INSTALL_CMAKEDIR}")
# What impmConfig.cmake records: the Trilinos and the C++ compiler impm was built with.
set(IMPM_CONFIG_TRILINOS_DIR "${Trilinos_DIR}")
set(IMPM_CONFIG_CXX_COMPILER "${CMAKE_CXX_COMPILER}")
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/impmConfig.cmake.in" "${PROJECT_BINARY_DIR}/impmConfig.cmake"
                              INSTALL_DESTINATION "${IMPM_INSTALL_CMAKEDIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/impmConfigVersion.cmake"
                                 VERSION "${PROJECT_VERSION}" COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/impmConfig.cmake" "${PROJECT_BINARY_DIR}/impmConfigVersion.cmake"
        DESTINATION "${IMPM_INSTALL_CMAKEDIR}")
