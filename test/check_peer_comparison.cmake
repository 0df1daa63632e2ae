# apps/peer_comparison.py against a stand-in peer (fake_karamelo.sh, whose loop takes 1 ms a
# step): the impm figures come out, the peer's loop rate is read from its two log lines (750
# particles at 1 ms a step: 0.75 M particle-steps/s, accepted 0.3-0.8 for a busy machine's sleep),
# and bad arguments exit 2 with one message naming the option.
#   cmake -DPYTHON=... -DSRC=... -DBUILD=... -DWORK=... -P check_peer_comparison.cmake
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${PYTHON} ${SRC}/apps/peer_comparison.py --build-dir ${BUILD} --cells-x 3 --steps 50,400
                        --cores 1 --repeat 2 --karamelo ${SRC}/test/fake_karamelo.sh --out ${WORK}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "peer_comparison.py exited ${rc}")
endif()
if(NOT out MATCHES "\\| impm \\| 1 \\| 750 \\| [0-9.e+]+ \\|")
  message(FATAL_ERROR "no impm row with 750 particles")
endif()
if(NOT out MATCHES "\\| Karamelo \\| 1 \\| 750 \\| (0\\.[0-9]+) \\|")
  message(FATAL_ERROR "no Karamelo row with 750 particles and a rate below 1 M particle-steps/s")
endif()
set(rate ${CMAKE_MATCH_1})
if(rate LESS 0.3 OR rate GREATER 0.8)
  message(FATAL_ERROR "the stand-in peer's loop rate ${rate} M particle-steps/s is not 0.75 (0.3-0.8)")
endif()
if(NOT EXISTS ${WORK}/peer_comparison.yaml OR NOT out MATCHES "impm / Karamelo at 1 cores: loop")
  message(FATAL_ERROR "no ratio line or no peer_comparison.yaml")
endif()

foreach(bad "--steps;60,20;--steps" "--cores;0;--cores" "--karamelo;${WORK}/none;--karamelo")
  list(GET bad 0 option)
  list(GET bad 1 value)
  list(GET bad 2 named)
  execute_process(COMMAND ${PYTHON} ${SRC}/apps/peer_comparison.py --build-dir ${BUILD} ${option} ${value}
                          --out ${WORK}/bad RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "peer_comparison: error: ${named}" OR NOT lines EQUAL 1 OR EXISTS ${WORK}/bad)
    message(FATAL_ERROR "${option} ${value}: exit ${rc}, stderr '${err}' (expected exit 2, one line naming ${named}, "
                        "no output directory)")
  endif()
endforeach()
message("peer_comparison: the stand-in peer's rate ${rate} M particle-steps/s; bad arguments refused")
