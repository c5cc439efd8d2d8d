# Builds one footprint probe for one target, links it with section garbage collection from its
# entry function, and checks its sections against the recorded budget (docs/footprint.md).
# Usage: cmake -DCXX=<compiler> -DSIZE=<size tool> [-DLD=<linker>] -DPROBE=<probe.cpp>
#              -DSUPPORT=<support.cpp> -DOUT=<dir> -DNAME=<probe-target> -DFLAGS=<f|f|...>
#              [-DLINK_FLAGS=<f|f|...>] [-DLIBS=<f|f|...>] -DBUDGET_TEXT=<bytes>
#              -DBUDGET_RODATA=<bytes>
#              -P footprint_probe.cmake
# With LD, objects are linked by that linker (rv32: binutils' ld -m elf32lriscv); otherwise by
# the compiler driver. .text and .rodata within budget; .data and .bss reported (the library
# has none: tests/footprint/all_headers.cpp checks that once, for every header).
string(REPLACE "|" ";" FLAGS "${FLAGS}")
string(REPLACE "|" ";" LINK_FLAGS "${LINK_FLAGS}")
string(REPLACE "|" ";" LIBS "${LIBS}")
file(MAKE_DIRECTORY "${OUT}")
set(elf "${OUT}/${NAME}.elf")
foreach(src probe support)
  if(src STREQUAL "probe")
    set(file "${PROBE}")
  else()
    set(file "${SUPPORT}")
  endif()
  execute_process(COMMAND "${CXX}" ${FLAGS} -c "${file}" -o "${OUT}/${NAME}.${src}.o"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "compiling ${file} failed:\n${out}\n${err}")
  endif()
endforeach()
if(LD)
  set(link_command "${LD}" ${LINK_FLAGS})
else()
  set(link_command "${CXX}" ${FLAGS} ${LINK_FLAGS})
endif()
execute_process(COMMAND ${link_command} "${OUT}/${NAME}.probe.o" "${OUT}/${NAME}.support.o"
  ${LIBS} -o "${elf}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "linking ${NAME} failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${SIZE}" -A "${elf}" RESULT_VARIABLE rc OUTPUT_VARIABLE sections)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SIZE} failed")
endif()
include("${CMAKE_CURRENT_LIST_DIR}/section_sizes.cmake")
motionbus_section_sizes("${sections}" probe)
set(text ${probe_text})
set(rodata ${probe_rodata})
set(data ${probe_data})
set(bss ${probe_bss})
set(line "${NAME}: .text ${text} B (budget ${BUDGET_TEXT}), .rodata ${rodata} B (budget ${BUDGET_RODATA}), .data ${data} B, .bss ${bss} B")
message(STATUS "${line}")
file(APPEND "${OUT}/footprint-report.txt" "${line}\n")
if(text EQUAL 0)
  message(FATAL_ERROR "no code in ${NAME}: size output not understood:\n${sections}")
endif()
if(text GREATER BUDGET_TEXT OR rodata GREATER BUDGET_RODATA)
  message(FATAL_ERROR "${NAME} grew past its budget:\n${line}")
endif()
