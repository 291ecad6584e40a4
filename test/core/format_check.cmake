# ctest format_check: clang-format --dry-run -Werror over every C++ file of lib/, apps/ and test/.
# Prints each file that does not follow .clang-format and fails if there is one.
# Usage: cmake -DSOURCE_DIR=... -DCLANG_FORMAT=... -P format_check.cmake
file(GLOB_RECURSE files
  ${SOURCE_DIR}/lib/*.cpp ${SOURCE_DIR}/lib/*.hpp
  ${SOURCE_DIR}/apps/*.cpp ${SOURCE_DIR}/apps/*.hpp
  ${SOURCE_DIR}/test/*.cpp ${SOURCE_DIR}/test/*.hpp)
list(SORT files)
# One clang-format process for every file (a process per file took 40 s of a CI run): its
# diagnostics name each file that differs ("<file>:<line>:<col>: error: code should be
# clang-formatted").
execute_process(COMMAND ${CLANG_FORMAT} --dry-run -Werror ${files}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE diagnostics)
set(bad "")
if(NOT rc EQUAL 0)
  string(REGEX MATCHALL "[^\n]*: error: code should be clang-formatted" lines "${diagnostics}")
  foreach(line ${lines})
    string(REGEX REPLACE ":[0-9]+:[0-9]+: error: code should be clang-formatted$" "" f "${line}")
    file(RELATIVE_PATH rel ${SOURCE_DIR} ${f})
    list(APPEND bad ${rel})
  endforeach()
  list(REMOVE_DUPLICATES bad)
  if(NOT bad)
    message(FATAL_ERROR "format_check: clang-format failed (exit ${rc}):\n${diagnostics}")
  endif()
endif()
list(LENGTH files n)
if(bad)
  list(LENGTH bad nbad)
  string(REPLACE ";" "\n  " listing "${bad}")
  message(FATAL_ERROR "format_check: ${nbad} of ${n} files do not follow .clang-format "
                      "(fix with clang-format -i):\n  ${listing}")
endif()
message(STATUS "format_check: ${n} files follow .clang-format")
