# The installed package (label `install`): installs the build tree BUILD into BUILD/install-test,
# configures and builds test/install_consumer (CONSUMER) against it with find_package(impm CONFIG
# REQUIRED) and the compiler CXX, runs the consumer on an installed deck for a few steps, and runs
# the installed driver (its run path to Trilinos, its installed plot script).
#   cmake -DBUILD=... -DCONSUMER=... -DCXX=... -DGENERATOR=... [-DMAKE_PROGRAM=...] -P check_install.cmake
set(prefix "${BUILD}/install-test")
set(consumer_build "${BUILD}/install-test-consumer")
set(run_dir "${BUILD}/install-test-run")
file(REMOVE_RECURSE "${prefix}" "${consumer_build}" "${run_dir}")
file(MAKE_DIRECTORY "${run_dir}")

function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(step_out "${out}${err}" PARENT_SCOPE)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${what} failed (exit ${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
endfunction()

step("cmake --install into ${prefix}" "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${prefix}")
foreach(f lib/cmake/impm/impmConfig.cmake lib/cmake/impm/impmConfigVersion.cmake lib/cmake/impm/impmTargets.cmake
          bin/impm include/impm/solvers/Simulation.hpp include/impm/core/InputDeck.hpp
          share/impm/plot_history.py share/impm/decks/bar_explicit_mpm_plane_strain.yaml
          share/doc/impm/README.md share/doc/impm/user-guide.md)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "install test: ${prefix}/${f} was not installed")
  endif()
endforeach()

set(configure "${CMAKE_COMMAND}" -S "${CONSUMER}" -B "${consumer_build}" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}" "-DCMAKE_CXX_COMPILER=${CXX}")
if(MAKE_PROGRAM)
  list(APPEND configure "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
step("configuring the consumer (find_package(impm CONFIG REQUIRED))" ${configure})
if(step_out MATCHES "impm was built with")
  message(FATAL_ERROR "install test: impmConfig.cmake warns about the compiler although it is the same:\n${step_out}")
endif()
step("building the consumer against the installed impm" "${CMAKE_COMMAND}" --build "${consumer_build}" -j 1)

set(deck "${prefix}/share/impm/decks/bar_explicit_mpm_plane_strain.yaml")
step("running the consumer on ${deck}" "${consumer_build}/impm_consumer" "${deck}" "${run_dir}/consumer" 200)
if(NOT step_out MATCHES "impm_consumer: run completed after 200 steps")
  message(FATAL_ERROR "install test: the consumer did not report a completed 200-step run:\n${step_out}")
endif()
if(NOT EXISTS "${run_dir}/consumer/history.csv")
  message(FATAL_ERROR "install test: the consumer's run wrote no ${run_dir}/consumer/history.csv")
endif()
message(STATUS "consumer: ${step_out}")

# The installed driver on the same deck, 20 steps, with its plot: it must run the installed
# share/impm/plot_history.py, replaced here by a stand-in that leaves a mark (so that neither
# matplotlib nor the source tree's script matters).
file(WRITE "${prefix}/share/impm/plot_history.py"
     "import pathlib, sys\npathlib.Path(sys.argv[1], 'installed-plot-script-ran').write_text('yes')\n")
unset(ENV{IMPM_PLOT_SCRIPT})
file(READ "${deck}" text)
string(REGEX REPLACE "Number of Steps: [^\n]*" "Number of Steps: 20" text "${text}")
file(WRITE "${run_dir}/short.yaml" "${text}")
step("running the installed driver ${prefix}/bin/impm" "${prefix}/bin/impm" "${run_dir}/short.yaml" --output "${run_dir}/driver")
if(NOT EXISTS "${run_dir}/driver/installed-plot-script-ran")
  message(FATAL_ERROR "install test: the installed driver did not run ${prefix}/share/impm/plot_history.py:\n${step_out}")
endif()
message(STATUS "installed driver: ${step_out}")
