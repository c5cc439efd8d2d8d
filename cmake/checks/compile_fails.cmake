# Compiles SOURCE with COMPILER once without a case (it must compile: the check itself works)
# and once with -DCASE_<CASE>: that compilation must fail, and its diagnostics must match EXPECT
# (a regular expression: the static_assert message meant for the case, not any other error).
# Usage: cmake -DCOMPILER=... -DSOURCE=... -DINCLUDE_DIR=... -DSTD=17 -DCASE=name
#   "-DEXPECT=regex" -DOUT=dir -P compile_fails.cmake
file(MAKE_DIRECTORY "${OUT}")
execute_process(
  COMMAND "${COMPILER}" -std=c++${STD} -Wall -Wextra -Werror -I "${INCLUDE_DIR}" -c "${SOURCE}"
          -o "${OUT}/valid.o"
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
message(STATUS "${CASE}: refused with /${EXPECT}/")
