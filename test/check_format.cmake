# The format check (ctest format_check): every .cpp/.hpp under core, physics, solvers, apps and test
# is what clang-format 14 with the repository's .clang-format makes of it. On a difference it
# names the files and the command that formats them, and fails.
#
#   cmake -DSRC=<source dir> -DCLANG_FORMAT=<clang-format-14> -P test/check_format.cmake
if(NOT CLANG_FORMAT)
  message(FATAL_ERROR "format_check: clang-format-14 not found when impm was configured "
                      "(cmake/setup-deps.sh installs it; then re-run cmake)")
endif()
set(files)
foreach(dir core physics solvers apps test)
  file(GLOB_RECURSE found "${SRC}/${dir}/*.cpp" "${SRC}/${dir}/*.hpp")
  list(APPEND files ${found})
endforeach()
list(LENGTH files count)
if(count LESS 100)
  message(FATAL_ERROR "format_check: only ${count} sources found under ${SRC}")
endif()
set(unformatted)
foreach(file ${files})
  execute_process(COMMAND ${CLANG_FORMAT} --style=file --dry-run --Werror ${file}
                  WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    file(RELATIVE_PATH rel ${SRC} ${file})
    list(APPEND unformatted ${rel})
  endif()
endforeach()
if(unformatted)
  list(LENGTH unformatted n)
  string(REPLACE ";" "\n  " listing "${unformatted}")
  message(FATAL_ERROR "format_check: ${n} of ${count} files differ from clang-format's layout:\n  ${listing}\n"
                      "Format them with cmake/format.sh (or cmake/format.sh FILE...).")
endif()
message(STATUS "format_check: ${count} files formatted")
