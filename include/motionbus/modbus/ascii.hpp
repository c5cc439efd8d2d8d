// motionbus — Modbus ASCII: the ADU ':' address PDU LRC CR LF in hexadecimal characters, its LRC,
// and its stream framer (Modbus over Serial Line V1.02 §2.5.2 "The ASCII transmission mode",
// §2.5.2.1 framing, §2.5.2.2 LRC checking, §6.2.1 LRC generation; docs/modbus.md §7).
//
//   | ':' | address (2) | function (2) | data (0..2 x 252) | LRC (2) | CR | LF |
//
// Each byte is sent as two hexadecimal characters, the high nibble first; the LRC is the two's
// complement of the 8-bit sum of the address and PDU bytes. Frames are delimited by ':' and
// CR LF, not by silences: a ':' inside a frame starts the frame again (§2.5.2.1), and a gap of
// more than the inter-character timeout (1 s unless configured) inside a frame is an error,
// which the user's timer reports by idle(). Encoders write uppercase digits; decoders accept
// lowercase ones too (the specification names 0-9 and A-F; the LRC is over the byte values,
// so a lowercase digit is no ambiguity, and pymodbus's a2b_hex accepts either).
//
// The framer has the shape of rtu_framer: put(byte) from a receive interrupt, feed(bytes),
// idle(), result(), sent(request), framer_role. Its buffer holds the decoded bytes (at most
// 255: address, PDU, LRC), never the characters, and needs no rescan after a failure: the next
// ':' is the next frame's start. No heap, no I/O.
//
//   ascii_framer rx(framer_role::server, {0x11});
//   on_rx_interrupt(c):                 // one character: true when something is settled
//     if (rx.put(c) && rx.result()) handle(rx.result().value());
//   on_char_timeout():                  // no character for 1 s inside a frame
//     (void)rx.idle();                  // a frame cut short: truncated
//
// Firmware contract (Cortex-M4; sizes checked by the test command, stack and instructions by
// the meter at -Os: docs/footprint.md):
//   ascii_framer size: 300 bytes (the decoded bytes of the longest ADU, the reader's state, the
//     options and put()'s result). A default-constructed `static` framer is all zeros: .bss,
//     no start-up code, no flash copied to RAM (the delimiter is stored relative to LF).
//   put(c), a server: 34.6 instructions a character over an FC03 request, LRC included, 81 at
//     its last character (the delimiter: digits, length, LRC and address checked), 64 bytes of
//     stack.
//   Interrupts: put() or feed() may run in the UART receive interrupt, idle() in the
//     inter-character timer's; sent() (client) runs before the request's first character goes
//     out. None of them may run while another runs on the same framer. A frame handed over
//     (ascii_frame::pdu) points into the framer: use it, or copy it, before the next call.
#ifndef MOTIONBUS_MODBUS_ASCII_HPP
#define MOTIONBUS_MODBUS_ASCII_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/rtu.hpp"

namespace motionbus {
namespace modbus {

/// The longest ASCII ADU in characters: ':', 2 x (address, 253-byte PDU, LRC), CR LF (§2.5.2.1).
inline constexpr std::size_t max_ascii_size = 1U + 2U * (1U + max_pdu_size + 1U) + 2U;  // 513
/// The decoded bytes of the longest ASCII ADU: address, PDU, LRC.
inline constexpr std::size_t max_ascii_bytes = 1U + max_pdu_size + 1U;  // 255
/// The inter-character timeout's default (§2.5.2.1: "an interval greater than 1 second means
/// an error has occurred", unless the user configured a longer one).
inline constexpr std::uint32_t ascii_char_timeout_ms = 1000;

/// LRC (Longitudinal Redundancy Check, §2.5.2.2, §6.2.1): the 8-bit sum of the bytes, carries
/// discarded, two's complemented; over the address and PDU bytes (not the characters). The same
/// members as crc<Spec> (core/crc.hpp): update(), value(), compute(). A sum, not a polynomial
/// remainder: no crc_spec describes it, so it is its own small class, used by the encoder, the
/// decoder and the framer alike.
class lrc {
 public:
  constexpr void update(std::uint8_t byte) noexcept {
    sum_ = static_cast<std::uint8_t>(sum_ + byte);
  }
  constexpr void update(byte_view in) noexcept {
    for (const std::uint8_t b : in) {
      update(b);
    }
  }
  /// The LRC of the bytes so far.
  constexpr std::uint8_t value() const noexcept { return static_cast<std::uint8_t>(0U - sum_); }
  /// The 8-bit sum of the bytes so far: 0 over the bytes and their LRC.
  constexpr std::uint8_t sum() const noexcept { return sum_; }
  static constexpr std::uint8_t compute(byte_view in) noexcept {
    lrc c;
    c.update(in);
    return c.value();
  }

 private:
  std::uint8_t sum_ = 0;
};

/// An ASCII frame as decoded: the slave address and a view of the PDU in the decoded bytes.
struct ascii_frame {
  std::uint8_t slave = 0;
  byte_view pdu{};
  std::uint8_t lrc = 0;  ///< as received
  constexpr bool broadcast() const noexcept { return slave == broadcast_address; }
};

namespace detail {

inline constexpr std::uint8_t not_hex = 0xFF;

// The value of a hexadecimal digit (0-9, A-F, a-f: see the top of this file), else not_hex.
constexpr std::uint8_t hex_value(std::uint8_t c) noexcept {
  const unsigned digit = c - unsigned{'0'};
  if (digit < 10U) {
    return static_cast<std::uint8_t>(digit);
  }
  const unsigned letter = (c | 0x20U) - unsigned{'a'};  // 'A'..'F' and 'a'..'f'
  return letter < 6U ? static_cast<std::uint8_t>(letter + 10U) : not_hex;
}

constexpr std::uint8_t hex_digit(unsigned nibble) noexcept {
  return static_cast<std::uint8_t>(nibble < 10U ? '0' + nibble : 'A' + (nibble - 10U));
}

// What one character did to the frame being read.
enum class ascii_event : std::uint8_t {
  more = 0,     // taken: inside a frame, or its start
  garbage = 1,  // outside a frame, dropped
  frame = 2,    // the end of a frame whose digits, length, LRC and address are valid
  failed = 3,   // a failure (ascii_reader::failure()); a ':' that ends it starts the next frame
};

// The character-by-character reading of an ASCII ADU into its bytes, shared by decode_ascii()
// and ascii_framer: the state only; the bytes go to the caller's storage.
class ascii_reader {
 public:
  // Takes `c`, storing decoded bytes at `bytes` (room for `capacity` <= 255); the delimiter
  // after CR is LF XOR `delimiter_x` (0: LF; the framer stores it so: see ascii_framer).
  constexpr ascii_event step(std::uint8_t c, std::uint8_t* bytes, std::size_t capacity,
                             std::uint8_t delimiter_x) noexcept {
    if (phase_ == phase::digits) {
      const std::uint8_t v = hex_value(c);
      if (v != not_hex) {
        if (half_ == 0U) {
          half_ = static_cast<std::uint8_t>(0x10U | v);  // the high nibble, marked
          return ascii_event::more;
        }
        const auto byte = static_cast<std::uint8_t>((half_ << 4U) | v);
        half_ = 0;
        if (count_ >= capacity) {
          return fail(capacity < max_ascii_bytes ? errc::buffer_too_small
                                                 : errc::modbus_pdu_length);
        }
        bytes[count_] = byte;
        ++count_;
        sum_.update(byte);
        return ascii_event::more;
      }
      if (c == '\r') {
        phase_ = phase::end;
        return ascii_event::more;
      }
      return stray(
          c, is_delimiter(c, delimiter_x) ? errc::modbus_ascii_end : errc::modbus_ascii_character);
    }
    if (phase_ == phase::end) {
      if (is_delimiter(c, delimiter_x)) {
        return end(bytes);
      }
      return stray(c, errc::modbus_ascii_end);
    }
    if (c == ':') {
      start();
      return ascii_event::more;
    }
    return ascii_event::garbage;
  }
  // The inter-character timeout (or the input's end): true when a frame was cut short (it is
  // dropped: failure() is truncated).
  constexpr bool cut() noexcept {
    if (phase_ == phase::hunting) {
      return false;
    }
    (void)fail(errc::truncated);
    return true;
  }
  constexpr void reset() noexcept { *this = ascii_reader{}; }
  constexpr bool inside() const noexcept { return phase_ != phase::hunting; }
  constexpr std::size_t held() const noexcept { return inside() ? count_ : 0U; }
  constexpr decode_failure failure(std::size_t consumed) const noexcept {
    return decode_failure{error_, consumed, expected_, received_};
  }
  // The frame read (after ascii_event::frame), its PDU a view of `bytes`.
  constexpr ascii_frame frame(const std::uint8_t* bytes) const noexcept {
    return ascii_frame{bytes[0], byte_view(bytes + 1, count_ - 2U), bytes[count_ - 1U]};
  }

 private:
  enum class phase : std::uint8_t { hunting = 0, digits = 1, end = 2 };

  static constexpr bool is_delimiter(std::uint8_t c, std::uint8_t delimiter_x) noexcept {
    return static_cast<std::uint8_t>(c ^ std::uint8_t{'\n'}) == delimiter_x;
  }

  constexpr void start() noexcept {
    reset();
    phase_ = phase::digits;
  }
  constexpr ascii_event fail(errc e, std::uint32_t expected = 0,
                             std::uint32_t received = 0) noexcept {
    reset();
    error_ = e;
    expected_ = static_cast<std::uint8_t>(expected);
    received_ = static_cast<std::uint8_t>(received);
    return ascii_event::failed;
  }
  // A character that breaks the frame: a failure; a ':' also starts the next frame (§2.5.2.1).
  constexpr ascii_event stray(std::uint8_t c, errc e) noexcept {
    if (c != ':') {
      return fail(e);
    }
    start();
    error_ = errc::modbus_ascii_end;
    return ascii_event::failed;
  }
  // CR and the delimiter: the bytes held end the frame.
  constexpr ascii_event end(const std::uint8_t* bytes) noexcept {
    if (half_ != 0U) {
      return fail(errc::modbus_ascii_odd_digits);
    }
    if (count_ < 3U) {  // address, function, LRC
      return fail(errc::modbus_pdu_length);
    }
    const std::uint8_t received = bytes[count_ - 1U];
    if (sum_.sum() != 0U) {  // the LRC of the others is received - sum of all
      return fail(errc::crc_mismatch, static_cast<std::uint8_t>(received - sum_.sum()), received);
    }
    if (bytes[0] > max_unicast_address) {
      return fail(errc::modbus_slave_address);
    }
    phase_ = phase::hunting;
    return ascii_event::frame;
  }

  phase phase_ = phase::hunting;
  std::uint8_t half_ = 0;  // 0x10 | the high nibble, while a byte's second digit is awaited
  std::uint8_t count_ = 0;
  lrc sum_;
  errc error_ = errc::ok;
  std::uint8_t expected_ = 0;
  std::uint8_t received_ = 0;
};

}  // namespace detail

/// Writes the ASCII ADU of `pdu` for `slave` (0 broadcast, 1..247): ':', uppercase hex digits
/// of the address, PDU and LRC, CR LF; 2 x PDU + 7 characters. Errors: modbus_slave_address
/// (248..255), modbus_pdu_length (empty or > 253), buffer_too_small. Nothing is written on
/// error.
constexpr result<std::size_t> encode_ascii(std::uint8_t slave, byte_view pdu,
                                           mutable_byte_view out) noexcept {
  if (slave > max_unicast_address) {
    return errc::modbus_slave_address;
  }
  if (!pdu_size_ok(pdu.size())) {
    return errc::modbus_pdu_length;
  }
  const std::size_t n = 2U * pdu.size() + 7U;
  if (out.size() < n) {
    return errc::buffer_too_small;
  }
  lrc check;
  std::size_t at = 0;
  const auto put = [&](std::uint8_t b) {
    out[at] = detail::hex_digit(b >> 4U);
    out[at + 1U] = detail::hex_digit(b & 0x0FU);
    at += 2U;
    check.update(b);
  };
  out[at++] = ':';
  put(slave);
  for (const std::uint8_t b : pdu) {
    put(b);
  }
  put(check.value());
  out[at++] = '\r';
  out[at++] = '\n';
  return at;
}

/// Decodes one ASCII ADU from the start of `in` into its bytes, written to `out` (address, PDU,
/// LRC: room for 255, or for as many as the frame holds); the frame's pdu is a view into `out`.
/// Complete: consumed = the frame's characters, ':' to LF (what follows is not read). Failed,
/// each kind of bad input with its own error: no_frame (the first character is not ':'),
/// modbus_ascii_character (a character other than a hex digit, CR or LF), modbus_ascii_odd_digits
/// (an odd number of hex digits), crc_mismatch (the LRC: expected = computed, received = sent),
/// modbus_ascii_end (no CR LF: the input ends first, CR is not followed by LF, or a ':' starts
/// another frame, at which consumed stops), modbus_pdu_length (fewer than 3 or more than 255
/// bytes), modbus_slave_address (248..255), buffer_too_small (`out` too short for the frame).
/// `delimiter`: the character after CR, as ascii_options::delimiter (LF unless changed).
constexpr decode_result<ascii_frame> decode_ascii(byte_view in, mutable_byte_view out,
                                                  std::uint8_t delimiter = '\n') noexcept {
  if (in.empty() || in[0] != ':') {
    return decode_failure{errc::no_frame, in.empty() ? 0U : 1U};
  }
  const std::size_t capacity = out.size() < max_ascii_bytes ? out.size() : max_ascii_bytes;
  detail::ascii_reader reader;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const detail::ascii_event e = reader.step(
        in[i], out.data(), capacity, static_cast<std::uint8_t>(delimiter ^ std::uint8_t{'\n'}));
    if (e == detail::ascii_event::frame) {
      return decode_result<ascii_frame>::complete(reader.frame(out.data()), i + 1U);
    }
    if (e == detail::ascii_event::failed) {
      return reader.failure(in[i] == ':' ? i : i + 1U);  // a ':' is the next frame's start
    }
  }
  return decode_failure{errc::modbus_ascii_end, in.size()};
}

/// The ASCII framer's run-time choices.
struct ascii_options {
  /// A server's own address (1..247; it also takes broadcasts), or for a client the slave it
  /// talks to until the first sent() (0: accept any). Not used by a listener.
  std::uint8_t address = 0;
  /// The character after CR that ends a frame: LF, unless changed by Diagnostics sub-function
  /// 03, Change ASCII Input Delimiter (MODBUS Application Protocol V1.1b3 §6.8.1).
  std::uint8_t delimiter = '\n';
};

/// Modbus ASCII stream framing (see the top of this file), in one of three roles: server (the
/// requests for its address and broadcasts), client (the response from the slave of the last
/// sent(), any before the first, or options.address), listener (every frame of a tapped line,
/// each a request or a response: heard_response()). framer_role::either is a server: ASCII
/// frames carry their own ends, so a framer needs no length rule of either direction, which is
/// what either chooses at run time for the RTU framer.
class ascii_framer {
 public:
  /// A default-constructed framer is all zeros (its options are stored relative to the
  /// defaults, as tformat::receiver stores its own): a `static` one lands in .bss, not .data.
  constexpr explicit ascii_framer(framer_role role = framer_role::server,
                                  ascii_options options = {}) noexcept
      : address_(options.address),
        delimiter_x_(static_cast<std::uint8_t>(options.delimiter ^ std::uint8_t{'\n'})),
        slave_(options.address),
        role_(role) {}

  /// The options the framer was built with.
  constexpr ascii_options options() const noexcept {
    ascii_options o;
    o.address = address_;
    o.delimiter = static_cast<std::uint8_t>(delimiter_x_ ^ std::uint8_t{'\n'});
    return o;
  }

  /// Client: records the request just written, its ASCII ADU (':' and the address's two digits
  /// are read: the response is expected from that slave, any for 0 or an unreadable address).
  /// Drops any partial frame.
  constexpr void sent(byte_view request_ascii) noexcept {
    std::uint8_t slave = 0;
    if (request_ascii.size() >= 3U && request_ascii[0] == ':') {
      const std::uint8_t hi = detail::hex_value(request_ascii[1]);
      const std::uint8_t lo = detail::hex_value(request_ascii[2]);
      if (hi != detail::not_hex && lo != detail::not_hex) {
        slave = static_cast<std::uint8_t>((hi << 4U) | lo);
      }
    }
    slave_ = slave;
    reader_.reset();
  }

  /// Takes characters from `in` until a frame or a failure. Complete: a frame for this node
  /// (its pdu a view into the framer, valid until the next call); consumed() = characters
  /// taken. Failed: the errors of decode_ascii() (but no_frame and buffer_too_small: characters
  /// outside a frame are dropped, counted in dropped()); a ':' that ends a frame starts the
  /// next one. Incomplete: all of `in` was taken. Frames for other addresses are skipped
  /// (skipped()).
  constexpr decode_result<ascii_frame> feed(byte_view in) noexcept {
    for (std::size_t i = 0; i < in.size(); ++i) {
      if (step(in[i])) {
        decode_result<ascii_frame> r = result_;
        if (r.is_complete()) {
          return decode_result<ascii_frame>::complete(r.value(), i + 1U);
        }
        return reader_failure(i + 1U);
      }
    }
    return need_input{1};
  }

  /// The per-character step (a UART receive interrupt's call): true when `c` settles
  /// something, which result() then holds (a frame for this node, or a failure), as feed()
  /// reports it.
  constexpr bool put(std::uint8_t c) noexcept { return step(c); }
  /// What the last put() that returned true settled; incomplete before any. A frame's pdu is a
  /// view into the framer, valid until the next call.
  constexpr const decode_result<ascii_frame>& result() const noexcept { return result_; }

  /// The inter-character timeout expired (no character for ascii_char_timeout_ms, or the time
  /// configured): a frame being received is dropped, failed truncated. Incomplete: none was.
  constexpr decode_result<ascii_frame> idle() noexcept {
    if (!reader_.cut()) {
      return need_input{1};
    }
    return reader_failure(0);
  }

  /// Characters dropped outside frames, frames skipped for other addresses, bytes held.
  constexpr std::size_t dropped() const noexcept { return dropped_; }
  constexpr std::size_t skipped() const noexcept { return skipped_; }
  constexpr std::size_t pending() const noexcept { return reader_.held(); }
  /// Whether a frame is being received (':' seen, its end not yet).
  constexpr bool inside() const noexcept { return reader_.inside(); }

  /// listener: whether the last frame handed over was the response to the request before it
  /// (else it was a request). ASCII frames have no length rule to tell the directions apart,
  /// so the pairing tells: after a request other than a broadcast, a frame from its slave with
  /// its function, or that function's exception (function + 0x80), is its response; any other
  /// frame is a request. A request makes the listener expect its response; a response, a
  /// broadcast or no_response() makes it expect a request.
  constexpr bool heard_response() const noexcept { return heard_response_; }
  /// listener: the response to the last request did not come in time (the user's timer, as
  /// for the RTU listener): the next frame is a request, even one from the same slave with
  /// the same function (a master repeating its request).
  constexpr void no_response() noexcept { function_ = 0; }

 private:
  constexpr decode_result<ascii_frame> reader_failure(std::size_t consumed) const noexcept {
    return reader_.failure(consumed);
  }

  constexpr bool for_us(std::uint8_t slave) const noexcept {
    switch (role_) {
      case framer_role::listener: return true;
      case framer_role::client: return slave_ == 0U || slave == slave_;
      default: return slave == address_ || slave == broadcast_address;
    }
  }

  constexpr bool step(std::uint8_t c) noexcept {
    const detail::ascii_event e = reader_.step(c, bytes_, max_ascii_bytes, delimiter_x_);
    if (e == detail::ascii_event::more) {
      return false;
    }
    if (e == detail::ascii_event::garbage) {
      ++dropped_;
      return false;
    }
    if (e == detail::ascii_event::failed) {
      result_ = reader_.failure(1);
      return true;
    }
    const ascii_frame f = reader_.frame(bytes_);
    if (!for_us(f.slave)) {
      ++skipped_;
      return false;
    }
    if (role_ == framer_role::listener) {
      pair(f);
    }
    result_ = decode_result<ascii_frame>::complete(f, 1);
    return true;
  }

  // listener: the direction of `f` (heard_response()) and what the next frame may answer.
  constexpr void pair(const ascii_frame& f) noexcept {
    const std::uint8_t function = f.pdu[0];  // the reader hands over frames of 1 PDU byte or more
    heard_response_ = function_ != 0U && f.slave == slave_ &&
                      (function & static_cast<std::uint8_t>(~exception_flag)) == function_;
    if (heard_response_ || f.broadcast()) {
      function_ = 0;
    } else {
      slave_ = f.slave;
      function_ = function;
    }
  }

  std::uint8_t bytes_[max_ascii_bytes] = {};  // address, PDU, LRC of the frame being read
  detail::ascii_reader reader_;
  // The options, each stored so that its default is 0 (a default framer is all zeros).
  std::uint8_t address_ = 0;
  std::uint8_t delimiter_x_ = 0;  // XOR the default delimiter, LF
  std::uint8_t slave_ = 0;        // client: the slave of the request sent (0: any); listener:
                                  // the slave of the request heard
  framer_role role_ = framer_role::server;
  std::uint8_t function_ = 0;    // listener: the function of the request heard (0: none)
  bool heard_response_ = false;  // listener: heard_response()
  std::size_t dropped_ = 0;
  std::size_t skipped_ = 0;
  decode_result<ascii_frame> result_;  // put()'s
};

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_ASCII_HPP
