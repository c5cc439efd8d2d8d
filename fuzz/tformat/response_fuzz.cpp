// T-format response decoder (master side). Oracles: never reads out of bounds (ASan); a
// complete response re-encodes to exactly the bytes consumed (a busy EEPROM response with a
// non-zero EDF excepted: the encoder always sends 00 then); consumed counts stay within the input;
// the exact-frame form agrees with the prefix form; the size and speed forms of the decoder
// (MOTIONBUS_SMALL_CODE) agree on every input.
#include <motionbus/tformat/codec.hpp>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const mb::byte_view in(data, size);
  tf::decode_options opt;
  if (size > 0 && (data[size - 1] & 0x80U) != 0) {
    opt.resolution_from_enid = true;
  }
  const auto r = tf::decode_response(in, opt);
  const auto small = tf::detail::decode_response_small(in, opt);
  const auto fast = tf::detail::decode_response_fast(in, opt);
  MOTIONBUS_FUZZ_CHECK(small.status() == fast.status() && small.error() == fast.error() &&
                       small.consumed() == fast.consumed() && small.needed() == fast.needed() &&
                       small.expected() == fast.expected() && small.received() == fast.received());
  MOTIONBUS_FUZZ_CHECK(small->abs == fast->abs && small->abm == fast->abm &&
                       small->enid == fast->enid && small->almc == fast->almc &&
                       small->sf == fast->sf && small->edf == fast->edf &&
                       small->address == fast->address && small->busy == fast->busy &&
                       small->id == fast->id && small->cf == fast->cf && small->crc == fast->crc);
  if (r.is_failed()) {
    MOTIONBUS_FUZZ_CHECK(r.consumed() <= size && r.consumed() >= 1);
    return 0;
  }
  if (r.is_incomplete()) {
    MOTIONBUS_FUZZ_CHECK(r.needed() >= 1 && size + r.needed() <= tf::max_response_size);
    return 0;
  }
  MOTIONBUS_FUZZ_CHECK(r.consumed() <= size && r.consumed() == r.value().layout().size);
  std::uint8_t out[tf::max_response_size] = {};
  const auto n = tf::encode_response(r.value(), out);
  MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == r.consumed());
  // A busy EEPROM response is re-encoded with EDF 00 (spec Table 5), hence another CRC: only
  // CF and ADF must match then. Everything else re-encodes byte for byte.
  const bool normalised = r.value().layout().eeprom() && r.value().busy && data[2] != 0;
  const std::size_t compare = normalised ? 2U : n.value();
  for (std::size_t i = 0; i < compare; ++i) {
    MOTIONBUS_FUZZ_CHECK(out[i] == data[i]);
  }
  if (normalised) {
    MOTIONBUS_FUZZ_CHECK(out[2] == 0);
  }
  const auto exact = tf::decode_response_frame(in.first(r.consumed()), opt);
  MOTIONBUS_FUZZ_CHECK(exact.is_complete() && exact.value().abs == r.value().abs);
  if (size > r.consumed()) {
    MOTIONBUS_FUZZ_CHECK(tf::decode_response_frame(in, opt).error() == mb::errc::tformat_length);
  }
  return 0;
}
