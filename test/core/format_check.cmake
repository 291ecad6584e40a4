# ctest format_check: clang-format --dry-run -Werror over every C++ file of lib/, apps/ and test/.
# Prints each file that does not follow .clang-format and fails if there is one.
# Usage: cmake -DSOURCE_DIR=... -DCLANG_FORMAT=... -P format_check.cmake
file(GLOB_RECURSE files
  ${SOURCE_DIR}/lib/*.cpp ${SOURCE_DIR}/lib/*.hpp
  ${SOURCE_DIR}/apps/*.cpp ${SOURCE_DIR}/apps/*.hpp
  ${SOURCE_DIR}/test/*.cpp ${SOURCE_DIR}/test/*.hpp)
list(SORT files)
set(bad "")
foreach(f ${files})
  execute_process(COMMAND ${CLANG_FORMAT} --dry-run -Werror ${f}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    file(RELATIVE_PATH rel ${SOURCE_DIR} ${f})
    list(APPEND bad ${rel})
  endif()
endforeach()
list(LENGTH files n)
if(bad)
  list(LENGTH bad nbad)
  string(REPLACE ";" "\n  " listing "${bad}")
  message(FATAL_ERROR "format_check: ${nbad} of ${n} files do not follow .clang-format "
                      "(fix with clang-format -i):\n  ${listing}")
endif()
message(STATUS "format_check: ${n} files follow .clang-format")
