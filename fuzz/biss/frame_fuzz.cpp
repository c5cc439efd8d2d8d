// BiSS-C sensor data decoder on arbitrary captures. Oracles: no out-of-bounds access (ASan);
// consumed within the capture; a decoded frame re-encodes (encode_frame with the found idle,
// Ack length, CDS and values) to exactly the capture bits it was read from; a CRC failure
// names a slave whose CRC is wrong; an incomplete result never asks for zero bits.
#include <motionbus/biss/codec.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

const bs::slave_layout layouts[] = {
    bs::absys_layout,
    {12, 13, 2, true, false, bs::crc_from_biss_notation(0x25)},
    {0, 18, 0, false, false, bs::crc_from_biss_notation(0x97, 0x15, bs::crc_output::plain)},
    {24, 40, 0, true, true, bs::crc_from_biss_notation(0x1021 | 0x10000, 0x1D0F)},
};

template <class Word>
void run(const std::uint8_t* data, std::size_t size, std::size_t chain_len, std::size_t pick,
         const bs::decode_options& opt) {
  std::vector<Word> words((size + sizeof(Word) - 1) / sizeof(Word), 0);
  for (std::size_t i = 0; i < size; ++i) {
    const unsigned shift = 8U * static_cast<unsigned>(sizeof(Word) - 1U - i % sizeof(Word));
    words[i / sizeof(Word)] =
        static_cast<Word>(words[i / sizeof(Word)] | (static_cast<Word>(data[i]) << shift));
  }
  std::vector<bs::slave_layout> chain;
  for (std::size_t k = 0; k < chain_len; ++k) {
    chain.push_back(layouts[(pick >> (2U * k)) % 4U]);
  }
  const std::size_t total = words.size() * sizeof(Word) * 8U;
  const auto r =
      bs::decode_frame(mb::span<const Word>(words.data(), words.size()), total,
                       mb::span<const bs::slave_layout>(chain.data(), chain.size()), opt);
  if (r.is_incomplete()) {
    MOTIONBUS_FUZZ_CHECK(r.needed_bits() > 0U);
    return;
  }
  MOTIONBUS_FUZZ_CHECK(r.consumed_bits() <= total);
  if (r.is_failed()) {
    if (r.error() == mb::errc::crc_mismatch) {
      MOTIONBUS_FUZZ_CHECK(r.expected() != r.received());
    } else {
      MOTIONBUS_FUZZ_CHECK(r.error() == mb::errc::biss_no_ack ||
                           r.error() == mb::errc::biss_no_start);
    }
    return;
  }
  const auto& f = r.value();
  MOTIONBUS_FUZZ_CHECK(f.size() == chain.size());
  MOTIONBUS_FUZZ_CHECK(f.line_delay <= opt.max_line_delay && f.ack_bits() >= 1U &&
                       f.ack_bits() <= opt.max_ack_bits);
  std::vector<bs::slave_values> values;
  bool filler_set = false;  // alignment bits are filler: the encoder writes them as 0
  for (std::size_t k = 0; k < f.size(); ++k) {
    const auto& d = f[k];
    MOTIONBUS_FUZZ_CHECK(d.crc_ok());
    values.push_back({d.multi_turn, d.single_turn, d.ne, d.nw});
    const unsigned a = chain[k].alignment_bits;
    filler_set = filler_set || (d.data & ((std::uint64_t{1} << a) - 1U)) != 0U;
  }
  bs::line_options line;
  line.line_delay = f.line_delay;
  line.ack_bits = f.ack_bits();
  line.cds = f.cds;
  std::vector<Word> copy(words);
  const auto w = bs::encode_frame(mb::span<const bs::slave_layout>(chain.data(), chain.size()),
                                  mb::span<const bs::slave_values>(values.data(), values.size()),
                                  mb::span<Word>(copy.data(), copy.size()), line);
  MOTIONBUS_FUZZ_CHECK(w.ok() && w.value() == r.consumed_bits());
  MOTIONBUS_FUZZ_CHECK(filler_set || copy == words);  // the same bits were there already
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) {
    return 0;
  }
  const std::size_t chain_len = 1U + data[0] % 3U;
  const std::size_t pick = data[1];
  bs::decode_options opt;
  opt.max_line_delay = 1U + (data[2] & 0x3FU);
  opt.max_ack_bits = 1U + (data[2] >> 6U) * 40U;
  switch ((data[0] >> 2U) % 3U) {
    case 0: run<std::uint8_t>(data + 3, size - 3, chain_len, pick, opt); break;
    case 1: run<std::uint16_t>(data + 3, size - 3, chain_len, pick, opt); break;
    default: run<std::uint32_t>(data + 3, size - 3, chain_len, pick, opt); break;
  }
  return 0;
}
