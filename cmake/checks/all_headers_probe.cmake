# Compiles tests/footprint/all_headers.cpp (every public header, used) for a cross target and
# fails when it has writable data: the test command's one check of that (the per-use probes
# report their .data and .bss, the host builds compile each header alone).
# Usage: cmake -DCXX=<compiler> -DSIZE=<size tool> -DSOURCE=<all_headers.cpp> -DOBJECT=<out.o>
#              -DFLAGS=<flag|flag|...> -P all_headers_probe.cmake
string(REPLACE "|" ";" FLAGS "${FLAGS}")
execute_process(COMMAND "${CXX}" ${FLAGS} -c "${SOURCE}" -o "${OBJECT}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cross compile failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${SIZE}" -A "${OBJECT}" RESULT_VARIABLE rc OUTPUT_VARIABLE sections)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SIZE} failed")
endif()
include("${CMAKE_CURRENT_LIST_DIR}/section_sizes.cmake")
motionbus_section_sizes("${sections}" probe)
set(text ${probe_text})
set(rodata ${probe_rodata})
math(EXPR writable "${probe_data} + ${probe_bss}")
message(STATUS "probe: .text ${text} B, .rodata ${rodata} B, .data+.bss ${writable} B")
if(NOT writable EQUAL 0)
  message(FATAL_ERROR "the probe has ${writable} bytes of writable data:\n${sections}")
endif()
if(text EQUAL 0)
  message(FATAL_ERROR "the probe has no code: size output not understood:\n${sections}")
endif()
