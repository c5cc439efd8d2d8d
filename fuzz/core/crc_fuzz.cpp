// CRC oracle: for every named CRC, the 256-entry, 16-entry and bitwise engines agree; any split
// of the input gives the one-shot value; a CRC over an arbitrary bit range of the input equals
// the bitwise engine fed one bit at a time through the bit reader.

// fuzz-max-len: 512 (every derived parameter reaches its whole range by 256 bytes: the split
// is at most 255 bytes in, the bit range starts at most 255 bits in and is at most 1785 long)
#include <motionbus/core/crc.hpp>

#include "../fuzz_check.hpp"

namespace mb = motionbus;

namespace {

template <class Spec>
void check_spec(mb::byte_view data) {
  using byte_crc = mb::crc<Spec, mb::crc_table_size::byte>;
  using nibble_crc = mb::crc<Spec, mb::crc_table_size::nibble>;
  using bit_crc = mb::crc<Spec, mb::crc_table_size::bitwise>;
  const auto whole = byte_crc::compute(data);
  MOTIONBUS_FUZZ_CHECK(nibble_crc::compute(data) == whole);
  MOTIONBUS_FUZZ_CHECK(bit_crc::compute(data) == whole);

  if (!data.empty()) {
    const std::size_t split = data[0] % (data.size() + 1U);
    byte_crc inc;
    inc.update(data.first(split)).update(data.subspan(split));
    MOTIONBUS_FUZZ_CHECK(inc.value() == whole);
  }

  if (data.size() >= 2) {
    const std::size_t total_bits = data.size() * 8U;
    const std::size_t offset = data[1] % total_bits;
    const std::size_t count = (data[0] * 7U) % (total_bits - offset + 1U);
    for (mb::bit_order order : {mb::bit_order::msb_first, mb::bit_order::lsb_first}) {
      nibble_crc stream;
      MOTIONBUS_FUZZ_CHECK(stream.update_stream(data, order, offset, count) == mb::errc::ok);
      bit_crc serial;
      mb::bit_reader r(data, order, offset);
      for (std::size_t i = 0; i < count; ++i) {
        const auto bit = r.read_bit();
        MOTIONBUS_FUZZ_CHECK(bit.ok());
        serial.update_bits(bit.value() ? 1U : 0U, 1U);
      }
      MOTIONBUS_FUZZ_CHECK(stream.value() == serial.value());
      // one bit too many is refused and changes nothing
      nibble_crc refused;
      const auto before = refused.value();
      MOTIONBUS_FUZZ_CHECK(refused.update_stream(data, order, offset, total_bits - offset + 1U) ==
                           mb::errc::truncated);
      MOTIONBUS_FUZZ_CHECK(refused.value() == before);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const mb::byte_view view(data, size);
  check_spec<mb::crc8_tformat_spec>(view);
  check_spec<mb::crc16_modbus_spec>(view);
  check_spec<mb::crc6_biss_spec>(view);
  check_spec<mb::crc4_biss_spec>(view);
  check_spec<mb::crc_spec<12, 0x80F, 0, false, true, 0>>(view);  // refin != refout
  return 0;
}
