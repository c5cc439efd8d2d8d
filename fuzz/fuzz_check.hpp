// Oracle check for fuzz targets: a failed property stops the process (libFuzzer reports it;
// the replay runner exits non-zero).
#ifndef MOTIONBUS_FUZZ_CHECK_HPP
#define MOTIONBUS_FUZZ_CHECK_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#define MOTIONBUS_FUZZ_CHECK(cond)                                                        \
  do {                                                                                    \
    if (!(cond)) {                                                                        \
      std::fprintf(stderr, "%s:%d: fuzz oracle failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                       \
    }                                                                                     \
  } while (false)

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

#endif
