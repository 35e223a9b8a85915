# ctest -> cmake -P: fails when a Catch test name holds a semicolon (see tests/CMakeLists.txt).
# PROGRAMS: the test programs, separated by "|".
string(REPLACE "|" ";" programs "${PROGRAMS}")
foreach(program ${programs})
  execute_process(COMMAND ${program} --list-test-names-only OUTPUT_VARIABLE names RESULT_VARIABLE status)
  # Catch 2 exits with the number of tests listed; a program that did not run gives text.
  if(NOT status MATCHES "^[0-9]+$" OR names STREQUAL "")
    message(FATAL_ERROR "${program} --list-test-names-only failed (${status})")
  endif()
  string(FIND "${names}" ";" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "${program}: a test name holds a semicolon, which ctest cuts: ${names}")
  endif()
endforeach()
