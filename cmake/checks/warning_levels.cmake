# Compiles SOURCE with COMPILER at each optimisation level in LEVELS (a |-list), with the
# project's warning FLAGS (a |-list) as errors and INCLUDE_DIR on the include path; fails on the
# first level that warns. Usage: cmake -DCOMPILER=... -DSOURCE=... -DINCLUDE_DIR=... -DSTD=17
#   "-DFLAGS=-Wall|..." "-DLEVELS=-O0|-O2|-O3|-Os" -DOUT=dir -P warning_levels.cmake
string(REPLACE "|" ";" flags "${FLAGS}")
string(REPLACE "|" ";" levels "${LEVELS}")
file(MAKE_DIRECTORY "${OUT}")
foreach(level IN LISTS levels)
  execute_process(
    COMMAND "${COMPILER}" -std=c++${STD} ${level} ${flags} -I "${INCLUDE_DIR}" -c "${SOURCE}"
            -o "${OUT}/every_level${level}.o"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT err STREQUAL "")
    message(FATAL_ERROR "${level}: ${COMPILER} warned or failed:\n${out}${err}")
  endif()
  message(STATUS "${level}: no warning")
endforeach()
