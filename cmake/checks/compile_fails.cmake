# Compiles SOURCE with COMPILER once without a case (it must compile: the check itself works)
# and once with -DCASE_<CASE>: that compilation must fail with exactly one static_assert message
# of MESSAGES (a regular expression for their common start), and that message must match EXPECT
# (a regular expression: the message meant for the case, not any other error).
# Each case writes its own objects: the cases run in parallel (ctest -j).
# Usage: cmake -DCOMPILER=... -DSOURCE=... -DINCLUDE_DIR=... -DSTD=17 -DCASE=name
#   "-DEXPECT=regex" "-DMESSAGES=regex" -DOUT=dir -P compile_fails.cmake
file(MAKE_DIRECTORY "${OUT}")
execute_process(
  COMMAND "${COMPILER}" -std=c++${STD} -Wall -Wextra -Werror -I "${INCLUDE_DIR}" -c "${SOURCE}"
          -o "${OUT}/${CASE}.valid.o"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the valid case does not compile:\n${out}${err}")
endif()
execute_process(
  COMMAND "${COMPILER}" -std=c++${STD} -I "${INCLUDE_DIR}" "-DCASE_${CASE}" -c "${SOURCE}"
          -o "${OUT}/${CASE}.o"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "${CASE}: compiled, and must not")
endif()
if(NOT "${out}${err}" MATCHES "${EXPECT}")
  message(FATAL_ERROR "${CASE}: failed, but without the message /${EXPECT}/:\n${out}${err}")
endif()
# one message: g++ says "static assertion failed: <message>", clang++ "static_assert failed due
# to requirement '...' "<message>"" (14) or "static assertion failed due to ...: <message>", each
# on one line
string(REGEX MATCHALL "(static assertion|static_assert) failed[^\n]*${MESSAGES}" messages
             "${out}${err}")
list(LENGTH messages count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "${CASE}: ${count} messages /${MESSAGES}/, one expected:\n${out}${err}")
endif()
message(STATUS "${CASE}: refused with /${EXPECT}/ alone")
