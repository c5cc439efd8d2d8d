// BiSS electronic data sheet parsers on arbitrary banks. Oracles: no out-of-bounds access;
// a bank that parses re-encodes to a bank that parses to the same values, with every defined
// byte equal to the input's and a checksum that then verifies.
#include <motionbus/biss/eds.hpp>

#include <cstddef>
#include <cstdint>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

// The bytes each bank defines (the rest are reserved / undefined and re-encode as 0).
constexpr bool common_defined(std::size_t i) {
  return i <= 0x03 || (i >= 0x10 && i <= 0x12) || (i >= 0x14 && i <= 0x17);
}
constexpr bool bp3_defined(std::size_t i) {
  return i <= 0x06 || (i >= 0x08 && i <= 0x23);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const mb::byte_view in(data, size);
  std::uint8_t out[bs::bank_size] = {};
  const auto c = bs::decode_eds_common(in);
  if (c.is_complete()) {
    MOTIONBUS_FUZZ_CHECK(size >= bs::bank_size);
    MOTIONBUS_FUZZ_CHECK(bs::encode_eds_common(*c, mb::mutable_byte_view(out, bs::bank_size)) ==
                         mb::errc::ok);
    const auto again = bs::decode_eds_common(mb::byte_view(out, bs::bank_size), {true});
    MOTIONBUS_FUZZ_CHECK(again.is_complete() && *again == *c);
    for (std::size_t i = 0; i < bs::bank_size - 1U; ++i) {
      MOTIONBUS_FUZZ_CHECK(out[i] == (common_defined(i) ? data[i] : 0U));
    }
  } else {
    MOTIONBUS_FUZZ_CHECK(size < bs::bank_size ? c.needed() == bs::bank_size - size
                                              : c.error() == mb::errc::biss_eds);
  }
  const auto p = bs::decode_bp3(in);
  if (p.is_complete()) {
    MOTIONBUS_FUZZ_CHECK(bs::encode_bp3(*p, mb::mutable_byte_view(out, bs::bank_size)) ==
                         mb::errc::ok);
    const auto again = bs::decode_bp3(mb::byte_view(out, bs::bank_size), {true});
    MOTIONBUS_FUZZ_CHECK(again.is_complete() && *again == *p);
    for (std::size_t i = 0; i < bs::bank_size - 1U; ++i) {
      MOTIONBUS_FUZZ_CHECK(out[i] == (bp3_defined(i) ? data[i] : 0U));
    }
    MOTIONBUS_FUZZ_CHECK(p->layout().validate() == mb::errc::ok);
  } else {
    MOTIONBUS_FUZZ_CHECK(size < bs::bank_size ? p.needed() == bs::bank_size - size
                                              : p.error() == mb::errc::biss_eds);
  }
  return 0;
}
