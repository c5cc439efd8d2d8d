// The CLI's analyzer CSV reader (tools/motionbus/capture.cpp) on any text: read (the recording
// keeps its promises) or a usage error naming what is wrong (recording_oracle.hpp).
#include <string>

#include "recording_oracle.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz_cli::check_recording("csv", std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
