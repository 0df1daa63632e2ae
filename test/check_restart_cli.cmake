# `impm DECK --restart DIR` on bad checkpoints: a truncated rank file, a truncated header.xml, a checkpoint of another
# deck, one whose header names another impm version, a directory that is no checkpoint, one of a
# step beyond the deck's Number of Steps, one without the energy columns the restart asks for
# (and a negative Checkpoint Interval in the deck). Each must exit 2 with one line of impm's on
# stderr naming what differs, and overwrite nothing: the output directory's history.csv and the
# checkpoint stay as they were. Then a good restart of the same checkpoint completes and gives
# the uninterrupted run's history.csv. The truncated case also runs at np 2 (every rank ends
# with exit 2). Invoked by ctest (impm_restart_cli).
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
file(READ "${SRC}/../apps/bar_explicit_mpm_plane_stress.yaml" deck)
string(REGEX REPLACE "Number of Steps: [^\n]*" "Number of Steps: 30" deck "${deck}")
string(REGEX REPLACE "Output Directory: [^\n]*" "Output Directory: ${WORK}/out" deck "${deck}")
string(REPLACE "Plot: true" "Plot: false" deck "${deck}")
string(REGEX REPLACE "(\n  Output:\n)" "\\1    Checkpoint Interval: 20\n" deck "${deck}")
if(NOT deck MATCHES "Checkpoint Interval: 20")
  message(FATAL_ERROR "the test could not add Checkpoint Interval to the deck")
endif()
file(WRITE "${WORK}/bar.yaml" "${deck}")

# The run that writes the checkpoint (step 20 of 30).
execute_process(COMMAND "${IMPM}" "${WORK}/bar.yaml" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc EQUAL 0 OR NOT EXISTS "${WORK}/out/checkpoint/header.xml")
  message(FATAL_ERROR "the run with checkpoints failed (exit ${rc}): ${err}")
endif()
file(READ "${WORK}/out/history.csv" history)
file(READ "${WORK}/out/checkpoint/header.xml" header)
file(READ "${WORK}/out/checkpoint/rank_00000.bin" rank0 HEX)

# Variants of the checkpoint, each in its own directory.
get_filename_component(real "${WORK}/out/checkpoint" REALPATH)
foreach(variant truncated truncated_header version)
  file(COPY "${real}/" DESTINATION "${WORK}/${variant}")
endforeach()
execute_process(COMMAND truncate -s -100 "${WORK}/truncated/rank_00000.bin" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "truncate failed")
endif()
# A header cut off in the middle of its XML (a crash while a copy was made by hand).
string(LENGTH "${header}" header_length)
math(EXPR half "${header_length} / 2")
string(SUBSTRING "${header}" 0 ${half} half_header)
file(WRITE "${WORK}/truncated_header/header.xml" "${half_header}")
string(REGEX REPLACE "(name=\"impm Version\"[^>]*value=\")[^\"]*\"" "\\1 0.0 (another impm)\"" other_version "${header}")
if(other_version STREQUAL header)
  message(FATAL_ERROR "the test could not change the header's impm Version")
endif()
file(WRITE "${WORK}/version/header.xml" "${other_version}")
string(REPLACE "Young Modulus: 200.0e9" "Young Modulus: 210.0e9" other_deck "${deck}")
if(other_deck STREQUAL deck)
  message(FATAL_ERROR "the test could not change the Young Modulus")
endif()
file(WRITE "${WORK}/other.yaml" "${other_deck}")
file(MAKE_DIRECTORY "${WORK}/empty")

# Restarts `deck_file` from `dir` into WORK/out on `np` ranks: exit 2, one line naming `key`,
# nothing in WORK/out or the checkpoint changed.
function(expect_refused name deck_file dir np key)
  set(command "${IMPM}")
  if(NOT np EQUAL 1)
    separate_arguments(flags UNIX_COMMAND "${MPIEXEC_FLAGS}")
    set(command "${MPIEXEC}" ${flags} -np ${np} "${IMPM}")
  endif()
  execute_process(COMMAND ${command} "${deck_file}" --restart "${dir}" RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err TIMEOUT 120)
  if(NOT rc STREQUAL "2")
    message(FATAL_ERROR "${name}: impm exited '${rc}', expected 2: ${err}")
  endif()
  string(REPLACE ";" "," err "${err}")
  string(REGEX MATCHALL "impm:[^\n]*\n" lines "${err}")
  list(LENGTH lines nlines)
  if(NOT nlines EQUAL 1)
    message(FATAL_ERROR "${name}: expected one line of impm's on stderr, got ${nlines}: ${err}")
  endif()
  string(FIND "${lines}" "${key}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "${name}: stderr does not name '${key}': ${err}")
  endif()
  file(READ "${WORK}/out/history.csv" now)
  file(READ "${WORK}/out/checkpoint/header.xml" header_now)
  file(READ "${WORK}/out/checkpoint/rank_00000.bin" rank0_now HEX)
  if(NOT now STREQUAL history OR NOT header_now STREQUAL header OR NOT rank0_now STREQUAL rank0)
    message(FATAL_ERROR "${name}: the output directory or the checkpoint was changed")
  endif()
  message(STATUS "${name} (np ${np}): ok: ${lines}")
endfunction()

expect_refused(truncated "${WORK}/bar.yaml" "${WORK}/truncated" 1 "rank_00000.bin is truncated")
expect_refused(truncated_np2 "${WORK}/bar.yaml" "${WORK}/truncated" 2 "rank_00000.bin is truncated")
expect_refused(truncated_header "${WORK}/bar.yaml" "${WORK}/truncated_header" 1 "header.xml cannot be read")
expect_refused(other_deck "${WORK}/other.yaml" "${WORK}/out/checkpoint" 1 "Young Modulus' is")
expect_refused(other_version "${WORK}/bar.yaml" "${WORK}/version" 1 "impm version ' 0.0 (another impm)'")
expect_refused(not_a_checkpoint "${WORK}/bar.yaml" "${WORK}/empty" 1 "no header.xml")

# A negative interval is a deck error: exit 2, the key named, no output directory.
string(REPLACE "Checkpoint Interval: 20" "Checkpoint Interval: -1" negative "${deck}")
string(REPLACE "${WORK}/out" "${WORK}/negative_out" negative "${negative}")
file(WRITE "${WORK}/negative.yaml" "${negative}")
execute_process(COMMAND "${IMPM}" "${WORK}/negative.yaml" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 2 OR NOT err MATCHES "'Output/Checkpoint Interval' must be 0" OR EXISTS "${WORK}/negative_out")
  message(FATAL_ERROR "negative Checkpoint Interval: exit ${rc}, expected 2 naming the key and no output: ${err}")
endif()
message(STATUS "negative_interval (np 1): ok: ${err}")

# A checkpoint beyond the deck's Number of Steps.
string(REGEX REPLACE "Number of Steps: [^\n]*" "Number of Steps: 10" short "${deck}")
file(WRITE "${WORK}/short.yaml" "${short}")
expect_refused(beyond_steps "${WORK}/short.yaml" "${WORK}/out/checkpoint" 1 "beyond this deck's 'Integrator/Number of Steps' = 10")

# Energy columns asked for by the restart but not recorded before the checkpoint.
string(REPLACE "Checkpoint Interval: 20" "Checkpoint Interval: 20\n    Energy And Momentum: true" energy "${deck}")
file(WRITE "${WORK}/energy.yaml" "${energy}")
expect_refused(energy_columns "${WORK}/energy.yaml" "${WORK}/out/checkpoint" 1 "recorded no energy and momentum")

# The good checkpoint, restarted in place: the same history.csv as the run that wrote it.
execute_process(COMMAND "${IMPM}" "${WORK}/bar.yaml" --restart "${WORK}/out/checkpoint" RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
file(READ "${WORK}/out/history.csv" restarted)
if(NOT rc EQUAL 0 OR NOT restarted STREQUAL history)
  message(FATAL_ERROR "the good restart failed (exit ${rc}) or changed history.csv: ${err}")
endif()
# It resumed at step 21 (the checkpoint was taken after step 20), not from step 0.
file(READ "${WORK}/out/summary.yaml" summary)
if(NOT summary MATCHES "First Step: 21
")
  message(FATAL_ERROR "the good restart's summary.yaml does not say 'First Step: 21'")
endif()
message(STATUS "good restart: history.csv identical, resumed at step 21")
