// Compile-time suite for Modbus: the RTU ADU, a request and a response encoded and decoded by
// the compiler, where constant evaluation takes the codecs' portable paths (no memmove: the
// byte loops that targets other than x86-64 and AArch64 run) and rejects undefined behaviour.
// Compiling this file is the test.
#include <cstddef>
#include <cstdint>

#include "motionbus/modbus.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

// Modbus over Serial Line V1.02 §2.5.1.1's example: slave 0x11, FC03 from 0x006B, 3 registers,
// CRC bytes 76 87 (low byte first).
constexpr std::uint8_t example_pdu[] = {0x03, 0x00, 0x6B, 0x00, 0x03};
constexpr std::uint8_t example_adu[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87};

template <std::size_t N>
constexpr bool same(const std::uint8_t* a, const std::uint8_t (&b)[N]) {
  for (std::size_t i = 0; i < N; ++i) {
    if (a[i] != b[i]) {
      return false;
    }
  }
  return true;
}

constexpr bool rtu_encodes_the_example() {
  std::uint8_t out[16] = {};
  const auto n = mo::encode_rtu(0x11, mb::byte_view(example_pdu), mb::mutable_byte_view(out, 16));
  return n.ok() && n.value() == sizeof example_adu && same(out, example_adu) && out[8] == 0;
}
static_assert(rtu_encodes_the_example(), "encode_rtu: the Serial Line example, its CRC 76 87");

constexpr bool rtu_encodes_the_largest_pdu() {
  std::uint8_t pdu[253] = {};
  for (std::size_t i = 0; i < sizeof pdu; ++i) {
    pdu[i] = static_cast<std::uint8_t>(i + 1U);
  }
  std::uint8_t out[256] = {};
  const auto n = mo::encode_rtu(0x01, mb::byte_view(pdu), mb::mutable_byte_view(out, 256));
  if (!n.ok() || n.value() != 256U || out[0] != 0x01 || out[1] != 1U || out[253] != 253U) {
    return false;
  }
  const auto back = mo::decode_rtu(mb::byte_view(out, 256));
  return back.is_complete() && back.value().pdu.size() == 253U && back.value().pdu[252] == 253U;
}
static_assert(rtu_encodes_the_largest_pdu(), "encode_rtu and decode_rtu: a 253-byte PDU");

constexpr bool rtu_decodes_the_example() {
  const auto r = mo::decode_rtu(mb::byte_view(example_adu));
  return r.is_complete() && r.value().slave == 0x11 && r.value().crc == 0x8776 &&
         r.value().pdu.size() == 5U && r.value().pdu[0] == 0x03 && r.value().pdu[4] == 0x03;
}
static_assert(rtu_decodes_the_example(), "decode_rtu: the Serial Line example");

constexpr bool rtu_refuses_a_bad_crc() {
  std::uint8_t adu[8] = {};
  for (std::size_t i = 0; i < 8; ++i) {
    adu[i] = example_adu[i];
  }
  adu[7] = 0x88;
  const auto r = mo::decode_rtu(mb::byte_view(adu));
  return r.is_failed() && r.error() == mb::errc::crc_mismatch && r.expected() == 0x8776U &&
         r.received() == 0x8876U;
}
static_assert(rtu_refuses_a_bad_crc(), "decode_rtu: a CRC mismatch and its evidence");

constexpr bool request_round_trip() {
  std::uint8_t out[8] = {};
  const auto n = mo::encode_read(0x03, 0x006B, 3, mb::mutable_byte_view(out, 8));
  if (!n.ok() || n.value() != 5U || !same(out, example_pdu)) {
    return false;
  }
  const auto q = mo::decode_request(mb::byte_view(out, n.value()));
  return q.is_complete() && q.value().function == 0x03 && q.value().address == 0x006B &&
         q.value().quantity == 3U;
}
static_assert(request_round_trip(), "encode_read and decode_request: the example's request");

constexpr bool response_for_its_request() {
  constexpr std::uint8_t response[] = {0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64};
  const auto r = mo::decode_response_for(mb::byte_view(example_pdu), mb::byte_view(response));
  return r.is_complete() && r.value().byte_count == 6U && r.value().quantity == 3U &&
         r.value().data.size() == 6U && r.value().data[1] == 0x2B;
}
static_assert(response_for_its_request(), "decode_response_for: the Application Protocol's FC03");

// The smallest ADU (address, function, CRC: min_rtu_size) decodes; one byte less is no ADU.
constexpr bool smallest_adu() {
  constexpr std::uint8_t fc07[] = {0x07};
  std::uint8_t out[8] = {};
  const auto n = mo::encode_rtu(0x01, mb::byte_view(fc07), mb::mutable_byte_view(out, 8));
  if (!n.ok() || n.value() != mo::min_rtu_size) {
    return false;
  }
  const auto whole = mo::decode_rtu(mb::byte_view(out, mo::min_rtu_size));
  const auto cut = mo::decode_rtu(mb::byte_view(out, mo::min_rtu_size - 1U));
  return whole.is_complete() && whole.value().pdu.size() == 1U && cut.is_failed() &&
         cut.error() == mb::errc::modbus_pdu_length;
}
static_assert(smallest_adu(), "min_rtu_size: the smallest ADU, 4 bytes");
static_assert(mo::min_rtu_size == 4U && mo::max_rtu_size == 256U,
              "Serial Line §2.5.1.1: an RTU frame of 4 to 256 bytes");

// A frame made by hand starts from zeros: slave 0 (a broadcast), no PDU, CRC 0.
static_assert(mo::rtu_frame{}.slave == 0U && mo::rtu_frame{}.crc == 0U &&
                  mo::rtu_frame{}.pdu.empty() && mo::rtu_frame{}.broadcast(),
              "rtu_frame's defaults");

}  // namespace

int main() {
  return 0;
}
