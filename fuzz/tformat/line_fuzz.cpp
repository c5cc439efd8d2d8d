// T-format bit-stream decoders (master and encoder side). Oracles: no out-of-bounds access;
// consumed counts within the stream; a decoded frame re-encodes (encode_line) to exactly the
// stream bits it was read from.
#include <motionbus/core/bits.hpp>
#include <motionbus/tformat/codec.hpp>
#include <motionbus/tformat/line.hpp>

#include <vector>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

template <class Word, class Frame>
void check_round_trip(const std::vector<Word>& words, mb::bit_order order, std::size_t start,
                      std::size_t end, const std::uint8_t* bytes, std::size_t n) {
  MOTIONBUS_FUZZ_CHECK(end == start + n * tf::field_bits);
  std::vector<Word> copy(words);
  const auto w = tf::encode_line(mb::byte_view(bytes, n), mb::span<Word>(copy.data(), copy.size()),
                                 order, start);
  MOTIONBUS_FUZZ_CHECK(w.ok() && w.value() == n * tf::field_bits);
  MOTIONBUS_FUZZ_CHECK(copy == words);  // the same bits were there already
}

template <class Word>
void run(const std::uint8_t* data, std::size_t size, mb::bit_order order) {
  std::vector<Word> words((size + sizeof(Word) - 1) / sizeof(Word), 0);
  for (std::size_t i = 0; i < size; ++i) {
    words[i / sizeof(Word)] = static_cast<Word>(
        words[i / sizeof(Word)] | (static_cast<Word>(data[i]) << (8U * (i % sizeof(Word)))));
  }
  const mb::span<const Word> view(words.data(), words.size());
  const std::size_t total = words.size() * sizeof(Word) * 8U;
  std::size_t from = 0;
  for (int k = 0; k < 8 && from < total; ++k) {
    const auto r = tf::decode_response_line(view, order, total, from);
    if (r.is_incomplete()) {
      break;
    }
    MOTIONBUS_FUZZ_CHECK(r.consumed_bits() <= total && r.consumed_bits() > from);
    if (r.is_complete()) {
      std::uint8_t bytes[tf::max_response_size] = {};
      const auto n = tf::encode_response(r.value().frame, bytes);
      MOTIONBUS_FUZZ_CHECK(n.ok());
      if (!(r.value().frame.layout().eeprom() && r.value().frame.busy)) {
        check_round_trip<Word, tf::response>(words, order, r.value().start_bit, r.consumed_bits(),
                                             bytes, n.value());
      }
    }
    from = r.consumed_bits();
  }
  const auto q = tf::decode_request_line(view, order, total, 0);
  if (q.is_complete()) {
    std::uint8_t bytes[tf::max_request_size] = {};
    const auto n =
        tf::encode_request(q.value().frame.id, q.value().frame.address, q.value().frame.edf, bytes);
    MOTIONBUS_FUZZ_CHECK(n.ok());
    check_round_trip<Word, tf::request>(words, order, q.value().start_bit, q.consumed_bits(), bytes,
                                        n.value());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) {
    return 0;
  }
  const mb::bit_order order =
      (data[0] & 1U) != 0 ? mb::bit_order::lsb_first : mb::bit_order::msb_first;
  switch ((data[0] >> 1U) % 3U) {
    case 0: run<std::uint8_t>(data + 1, size - 1, order); break;
    case 1: run<std::uint16_t>(data + 1, size - 1, order); break;
    default: run<std::uint32_t>(data + 1, size - 1, order); break;
  }
  return 0;
}
