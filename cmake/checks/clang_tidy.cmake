# Runs clang-tidy (.clang-tidy at the top of the repository) over FILE as C++17 and fails on any
# finding. tests/CMakeLists.txt runs it over every public header (through
# tests/tidy/all_headers.cpp), the CLI's sources and the examples, one test per file. A
# deliberate exception is marked in the code with NOLINT(check) and a reason.
execute_process(
  COMMAND "${CLANG_TIDY}" --quiet "--config-file=${SOURCE_DIR}/.clang-tidy" "${FILE}"
          -- -std=c++17 "-I${SOURCE_DIR}/include" "-I${SOURCE_DIR}/tools/motionbus"
  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR out MATCHES "(warning|error):")
  message("${out}")
  message(FATAL_ERROR "clang-tidy: findings in ${FILE} or the headers it includes (see above)")
endif()
message(STATUS "clang-tidy: ${FILE}: no finding")
