# Runs clang-tidy (.clang-tidy at the top of the repository) over FILE as C++17 and fails on any
# finding. tests/CMakeLists.txt runs it over every public header (through
# tests/tidy/all_headers.cpp), the CLI's sources and the examples, one test per file. A
# deliberate exception is marked in the code with NOLINT(check) and a reason.
# The static analyzer does not inline the C++ standard library's functions (it models them
# as calls it cannot see into; its std-specific checkers stay): what it analyses is this
# project's code, inlined into its callers as deep as ever, not libstdc++'s. Measured on three
# of the CLI's sources, clang-tidy CPU seconds, the same session (docs/testing.md):
# tformat_command 56.3 -> 44.7, biss_command 41.0 -> 31.7, options 50.1 -> 31.8; a planted
# null dereference through an inlined call of the project's own is found either way.
execute_process(
  COMMAND "${CLANG_TIDY}" --quiet "--config-file=${SOURCE_DIR}/.clang-tidy"
          --extra-arg=-Xclang --extra-arg=-analyzer-config --extra-arg=-Xclang
          --extra-arg=c++-stdlib-inlining=false "${FILE}"
          -- -std=c++17 "-I${SOURCE_DIR}/include" "-I${SOURCE_DIR}/tools/motionbus"
  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR out MATCHES "(warning|error):")
  message("${out}")
  message(FATAL_ERROR "clang-tidy: findings in ${FILE} or the headers it includes (see above)")
endif()
message(STATUS "clang-tidy: ${FILE}: no finding")
