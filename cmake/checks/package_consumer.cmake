# Builds and runs test_package/ against motionbus in one MODE:
#   install          cmake --install to a prefix, then find_package via CMAKE_PREFIX_PATH
#   build_tree       find_package via motionbus_DIR pointing at the build tree
#   add_subdirectory the checkout added as a subdirectory
#   fetchcontent     FetchContent from the local checkout
#   include_only     the compiler alone with -I include
foreach(v MODE SOURCE_DIR BUILD_DIR WORK_DIR CXX)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "${v} not set")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

set(gen "")
if(GENERATOR)
  set(gen -G "${GENERATOR}")
endif()
set(common -S "${SOURCE_DIR}/test_package" -B "${WORK_DIR}/build" ${gen}
  "-DCMAKE_CXX_COMPILER=${CXX}")

if(MODE STREQUAL "include_only")
  run("${CXX}" -std=c++17 -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow
      -Wold-style-cast -Werror -fno-exceptions -fno-rtti "-I${SOURCE_DIR}/include"
      "${SOURCE_DIR}/test_package/main.cpp" -o "${WORK_DIR}/consumer")
  run("${WORK_DIR}/consumer")
  message(STATUS "${last_output}")
  return()
elseif(MODE STREQUAL "install")
  run("${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
  if(NOT EXISTS "${WORK_DIR}/prefix/share/cmake/motionbus/motionbusConfigVersion.cmake")
    message(FATAL_ERROR "installed package config missing")
  endif()
  run("${CMAKE_COMMAND}" ${common} "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix")
  # An incompatible major version must be refused by the version file.
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/test_package"
      -B "${WORK_DIR}/build-wrong-version" ${gen} "-DCMAKE_CXX_COMPILER=${CXX}"
      "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DMOTIONBUS_REQUIRED_VERSION=99.0
    RESULT_VARIABLE wrong OUTPUT_QUIET ERROR_QUIET)
  if(wrong EQUAL 0)
    message(FATAL_ERROR "find_package(motionbus 99.0) was accepted")
  endif()
elseif(MODE STREQUAL "build_tree")
  run("${CMAKE_COMMAND}" ${common} "-Dmotionbus_DIR=${BUILD_DIR}")
elseif(MODE STREQUAL "add_subdirectory")
  run("${CMAKE_COMMAND}" ${common} -DMOTIONBUS_CONSUME=add_subdirectory
      "-DMOTIONBUS_SOURCE_DIR=${SOURCE_DIR}")
elseif(MODE STREQUAL "fetchcontent")
  run("${CMAKE_COMMAND}" ${common} -DMOTIONBUS_CONSUME=fetchcontent
      "-DMOTIONBUS_SOURCE_DIR=${SOURCE_DIR}")
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()
run("${CMAKE_COMMAND}" --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer")
message(STATUS "${last_output}")
