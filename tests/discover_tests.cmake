# Lists the test cases of TEST_EXECUTABLE and writes CTEST_FILE: one ctest entry per doctest case.
# doctest_discover_tests passes each name to --test-case= as it is, but doctest splits that filter
# at commas, and CMake splits the list of names at semicolons: a case whose name holds either
# selected no case at all and "passed". Here each name is one line, and its filter escapes
# doctest's separators (\ and ,), so every entry runs exactly its own case; and an entry whose
# filter still selects nothing fails instead of passing.
#
#   cmake -D TEST_EXECUTABLE=... -D CTEST_FILE=... -D WORKING_DIR=... [-D TEST_ENV=...] -P discover_tests.cmake
execute_process(COMMAND "${TEST_EXECUTABLE}" --list-test-cases --no-version
                OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "listing the test cases of ${TEST_EXECUTABLE} failed (${rc}):\n${out}")
endif()
# One list element per line, semicolons kept aside.
string(REPLACE ";" "<semicolon>" out "${out}")
string(REPLACE "\n" ";" lines "${out}")
set(script "")
set(count 0)
foreach(line IN LISTS lines)
  if(line STREQUAL "" OR line MATCHES "^\\[doctest\\]" OR line MATCHES "^=====")
    continue()
  endif()
  string(REPLACE "<semicolon>" ";" name "${line}")
  string(REPLACE "\\" "\\\\" filter "${name}")
  string(REPLACE "," "\\," filter "${filter}")
  string(APPEND script "add_test([==[${name}]==] \"${TEST_EXECUTABLE}\" [==[--test-case=${filter}]==])\n")
  # A filter that selects no case makes doctest report "test cases: 0" and exit 0: that entry fails.
  string(APPEND script "set_tests_properties([==[${name}]==] PROPERTIES WORKING_DIRECTORY \"${WORKING_DIR}\" FAIL_REGULAR_EXPRESSION [==[test cases: 0 [|]]==]")
  if(TEST_ENV)
    # Variables come joined by "|" (a ";" would split the command line that passes them).
    string(REPLACE "|" ";" env "${TEST_ENV}")
    string(APPEND script " ENVIRONMENT [==[${env}]==]")
  endif()
  string(APPEND script ")\n")
  math(EXPR count "${count} + 1")
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} listed no test cases:\n${out}")
endif()
file(WRITE "${CTEST_FILE}" "${script}")
