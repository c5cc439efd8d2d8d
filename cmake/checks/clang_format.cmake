# Fails when a project C++ file differs from what clang-format (.clang-format) would make it.
file(GLOB_RECURSE files
  "${SOURCE_DIR}/include/*.hpp" "${SOURCE_DIR}/tests/*.hpp" "${SOURCE_DIR}/tests/*.cpp"
  "${SOURCE_DIR}/fuzz/*.cpp" "${SOURCE_DIR}/fuzz/*.hpp" "${SOURCE_DIR}/bench/*.cpp"
  "${SOURCE_DIR}/tools/*.cpp" "${SOURCE_DIR}/tools/*.hpp" "${SOURCE_DIR}/examples/*.cpp"
  "${SOURCE_DIR}/examples/*.hpp" "${SOURCE_DIR}/test_package/*.cpp" "${SOURCE_DIR}/c/*.cpp")
execute_process(COMMAND "${CLANG_FORMAT}" --dry-run --Werror ${files}
  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "clang-format: files need formatting (run clang-format -i on them)")
endif()
list(LENGTH files n)
message(STATUS "clang-format: ${n} file(s) formatted")
