// motionbus — the library's error codes.
//
// One small enum serves every protocol so that results, tools and logs speak one language.
// Values are explicit and stable; ranges are reserved per protocol:
//   0          success
//   1..31      generic (shared by every codec)
//   32..63     T-format
//   64..127    Modbus (library errors; Modbus exception codes are wire values, kept apart)
//   128..191   BiSS-C
//   192..255   device profiles
// "Need more input" is not an error: decoders report it as its own outcome (see result.hpp).
#ifndef MOTIONBUS_CORE_ERRC_HPP
#define MOTIONBUS_CORE_ERRC_HPP

#include <cstdint>

namespace motionbus {

enum class [[nodiscard]] errc : std::uint8_t{
    ok = 0,
    /// The input ends before the field or frame does (a complete frame was required).
    truncated = 1,
    /// The caller's output buffer cannot hold what the encoder must write. Nothing was written.
    buffer_too_small = 2,
    /// An argument is outside the function's documented domain (e.g. a bit count above 64).
    invalid_argument = 3,
    /// The received check value differs from the one computed over the received data.
    crc_mismatch = 4,
    /// A value decoded from the wire, or given to an encoder, is outside its legal range.
    out_of_range = 5,
    /// A length or count field disagrees with the data actually present.
    length_mismatch = 6,
    /// Bits that the protocol reserves (must be zero or one) have the wrong value.
    reserved_bits = 7,
    /// No frame start was found within the searched input.
    no_frame = 8,
};

/// snake_case name of an error code, as printed by the tools; "unknown" for a value outside
/// the enumeration. The returned string has static storage duration.
constexpr const char* to_string(errc e) noexcept {
  switch (e) {
    case errc::ok: return "ok";
    case errc::truncated: return "truncated";
    case errc::buffer_too_small: return "buffer_too_small";
    case errc::invalid_argument: return "invalid_argument";
    case errc::crc_mismatch: return "crc_mismatch";
    case errc::out_of_range: return "out_of_range";
    case errc::length_mismatch: return "length_mismatch";
    case errc::reserved_bits: return "reserved_bits";
    case errc::no_frame: return "no_frame";
  }
  return "unknown";
}

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_ERRC_HPP
