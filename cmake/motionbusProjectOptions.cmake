# Settings for motionbus's own targets (tests, tools, benches, fuzzers, examples). Nothing here
# reaches consumers of the motionbus target.

# Strict warnings, as errors.
set(MOTIONBUS_STRICT_WARNINGS_COMMON
  -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Wold-style-cast
  -Wcast-align -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wundef -Werror)
set(MOTIONBUS_STRICT_WARNINGS ${MOTIONBUS_STRICT_WARNINGS_COMMON})
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  list(APPEND MOTIONBUS_STRICT_WARNINGS -Wduplicated-cond -Wlogical-op)
endif()

set(MOTIONBUS_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
  -fno-omit-frame-pointer)

# Coverage: gcov counters, no optimisation (lines map one to one), constexpr code evaluated at
# run time where the tests call it so (the static suite's compile-time calls are not counted).
set(MOTIONBUS_COVERAGE_FLAGS --coverage -O0 -fno-inline)
if(MOTIONBUS_COVERAGE AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  message(FATAL_ERROR "MOTIONBUS_COVERAGE needs GCC (gcov)")
endif()

# motionbus_project_target(<target>): strict warnings (and sanitizers or coverage when enabled).
function(motionbus_project_target target)
  target_compile_options(${target} PRIVATE ${MOTIONBUS_STRICT_WARNINGS})
  if(MOTIONBUS_SANITIZE)
    target_compile_options(${target} PRIVATE ${MOTIONBUS_SANITIZER_FLAGS})
    target_link_options(${target} PRIVATE ${MOTIONBUS_SANITIZER_FLAGS})
  endif()
  if(MOTIONBUS_COVERAGE)
    target_compile_options(${target} PRIVATE ${MOTIONBUS_COVERAGE_FLAGS})
    target_link_options(${target} PRIVATE --coverage)
  endif()
endfunction()

find_program(MOTIONBUS_CLANG_FORMAT NAMES clang-format clang-format-14 clang-format-15 clang-format-16)
find_program(MOTIONBUS_CLANG_TIDY NAMES clang-tidy clang-tidy-14 clang-tidy-15 clang-tidy-16)
