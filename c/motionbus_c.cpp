// motionbus — the C API (c/include/motionbus/c.h) on the C++ headers: each function converts
// its arguments, calls the library and converts the result; nothing is re-implemented. Built
// without exceptions and RTTI (no exception can cross into C), no heap: the stream objects are
// constructed in the caller's storage, whose size and alignment are checked below against the
// C++ types on the ABI being compiled for.
#include "include/motionbus/c.h"  // beside this file: no include path needed

#include <cstddef>
#include <cstdint>
#include <new>

#include "motionbus/biss/codec.hpp"
#include "motionbus/biss/control.hpp"
#include "motionbus/core/crc.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/server.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/receiver.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;
namespace md = motionbus::modbus;
namespace bs = motionbus::biss;

namespace {

// --- the storage: sizes and alignment as the header says, for the ABI compiled for ------------
template <class Storage, class T, std::size_t Size>
constexpr bool fits() {
  return sizeof(Storage) >= sizeof(T) && alignof(Storage) >= alignof(T) && Size == sizeof(T);
}
static_assert(fits<mb_tformat_receiver, tf::receiver, MB_TFORMAT_RECEIVER_SIZE>(),
              "MB_TFORMAT_RECEIVER_SIZE is not sizeof(tformat::receiver) on this ABI");
static_assert(fits<mb_modbus_server_framer, md::rtu_server_framer, MB_MODBUS_SERVER_FRAMER_SIZE>(),
              "MB_MODBUS_SERVER_FRAMER_SIZE is not sizeof(modbus::rtu_server_framer) on this ABI");
static_assert(fits<mb_biss_control_master, bs::control_master, MB_BISS_CONTROL_MASTER_SIZE>(),
              "MB_BISS_CONTROL_MASTER_SIZE is not sizeof(biss::control_master) on this ABI");
static_assert(alignof(mb_tformat_receiver) == MB_STORAGE_ALIGN &&
                  alignof(mb_modbus_server_framer) == MB_STORAGE_ALIGN &&
                  alignof(mb_biss_control_master) == MB_STORAGE_ALIGN,
              "MB_STORAGE_ALIGN is not the storage unions' alignment on this ABI");

// The object living in `s` (constructed there by its _init function).
template <class T, class Storage>
T& object(Storage* s) {
  return *std::launder(static_cast<T*>(static_cast<void*>(s->bytes)));
}
template <class T, class Storage>
const T& object(const Storage* s) {
  return *std::launder(static_cast<const T*>(static_cast<const void*>(s->bytes)));
}

// --- errors: the C enumeration is errc, value for value -----------------------------------
#define MB_SAME(c, cpp) \
  static_assert(static_cast<int>(c) == static_cast<int>(mb::errc::cpp), #c " is not errc::" #cpp)
MB_SAME(MB_OK, ok);
MB_SAME(MB_TRUNCATED, truncated);
MB_SAME(MB_BUFFER_TOO_SMALL, buffer_too_small);
MB_SAME(MB_INVALID_ARGUMENT, invalid_argument);
MB_SAME(MB_CRC_MISMATCH, crc_mismatch);
MB_SAME(MB_OUT_OF_RANGE, out_of_range);
MB_SAME(MB_LENGTH_MISMATCH, length_mismatch);
MB_SAME(MB_RESERVED_BITS, reserved_bits);
MB_SAME(MB_NO_FRAME, no_frame);
MB_SAME(MB_TFORMAT_SYNC_CODE, tformat_sync_code);
MB_SAME(MB_TFORMAT_PARITY, tformat_parity);
MB_SAME(MB_TFORMAT_UNKNOWN_DATA_ID, tformat_unknown_data_id);
MB_SAME(MB_TFORMAT_LENGTH, tformat_length);
MB_SAME(MB_TFORMAT_CF_MISMATCH, tformat_cf_mismatch);
MB_SAME(MB_TFORMAT_ADDRESS_MISMATCH, tformat_address_mismatch);
MB_SAME(MB_TFORMAT_COMMUNICATION_ALARM, tformat_communication_alarm);
MB_SAME(MB_TFORMAT_START_BIT, tformat_start_bit);
MB_SAME(MB_TFORMAT_DELIMITER, tformat_delimiter);
MB_SAME(MB_TFORMAT_DATA_MISMATCH, tformat_data_mismatch);
MB_SAME(MB_MODBUS_ILLEGAL_FUNCTION, modbus_illegal_function);
MB_SAME(MB_MODBUS_QUANTITY, modbus_quantity);
MB_SAME(MB_MODBUS_BYTE_COUNT, modbus_byte_count);
MB_SAME(MB_MODBUS_ADDRESS_OVERFLOW, modbus_address_overflow);
MB_SAME(MB_MODBUS_COIL_VALUE, modbus_coil_value);
MB_SAME(MB_MODBUS_MISMATCH, modbus_mismatch);
MB_SAME(MB_MODBUS_SLAVE_ADDRESS, modbus_slave_address);
MB_SAME(MB_MODBUS_PDU_LENGTH, modbus_pdu_length);
MB_SAME(MB_MODBUS_ASCII_CHARACTER, modbus_ascii_character);
MB_SAME(MB_MODBUS_ASCII_ODD_DIGITS, modbus_ascii_odd_digits);
MB_SAME(MB_MODBUS_ASCII_END, modbus_ascii_end);
MB_SAME(MB_MODBUS_REFERENCE_TYPE, modbus_reference_type);
MB_SAME(MB_MODBUS_FILE_NUMBER, modbus_file_number);
MB_SAME(MB_MODBUS_RECORD_NUMBER, modbus_record_number);
MB_SAME(MB_BISS_NO_ACK, biss_no_ack);
MB_SAME(MB_BISS_NO_START, biss_no_start);
MB_SAME(MB_BISS_NOT_ACKNOWLEDGED, biss_not_acknowledged);
MB_SAME(MB_BISS_ACCESS_DENIED, biss_access_denied);
MB_SAME(MB_BISS_ECHO_MISMATCH, biss_echo_mismatch);
MB_SAME(MB_BISS_TIMEOUT, biss_timeout);
MB_SAME(MB_BISS_WRITE_NOT_CONFIRMED, biss_write_not_confirmed);
MB_SAME(MB_BISS_ABORTED, biss_aborted);
MB_SAME(MB_BISS_BUSY, biss_busy);
MB_SAME(MB_BISS_LAYOUT, biss_layout);
MB_SAME(MB_BISS_EDS, biss_eds);
#undef MB_SAME
static_assert(static_cast<int>(MB_INCOMPLETE) == static_cast<int>(mb::decode_status::incomplete) &&
                  static_cast<int>(MB_COMPLETE) == static_cast<int>(mb::decode_status::complete) &&
                  static_cast<int>(MB_FAILED) == static_cast<int>(mb::decode_status::failed),
              "mb_status is decode_status");
static_assert(MB_TFORMAT_MAX_REQUEST_SIZE == tf::max_request_size &&
                  MB_TFORMAT_MAX_RESPONSE_SIZE == tf::max_response_size &&
                  MB_MODBUS_MAX_ADU_SIZE == md::max_rtu_size &&
                  MB_MODBUS_MAX_PDU_SIZE == md::max_pdu_size && MB_BISS_MAX_CHAIN == bs::max_chain,
              "the header's limits are the library's");

mb_errc to_c(mb::errc e) {
  return static_cast<mb_errc>(e);
}

mb::byte_view bytes(const std::uint8_t* p, std::size_t n) {
  return p == nullptr ? mb::byte_view() : mb::byte_view(p, n);
}
mb::mutable_byte_view out_bytes(std::uint8_t* p, std::size_t n) {
  return p == nullptr ? mb::mutable_byte_view() : mb::mutable_byte_view(p, n);
}

// An encoder's result<size_t>: the error, or MB_OK with the size in `written` (if given).
mb_errc encoded(const mb::result<std::size_t>& r, std::size_t* written) {
  if (written != nullptr) {
    *written = r.ok() ? r.value() : 0U;
  }
  return to_c(r.error());
}

// A decode_result's outcome; `set(value)` writes the value when complete.
template <class T, mb::input_unit Unit, class Set>
mb_result outcome(const mb::decode_result<T, Unit>& r, Set&& set) {
  mb_result c{};
  c.status = static_cast<std::uint8_t>(r.status());
  c.error = static_cast<std::uint8_t>(r.error());
  c.expected = r.expected();
  c.received = r.received();
  if constexpr (Unit == mb::input_unit::bytes) {
    c.count = r.is_incomplete() ? r.needed() : r.consumed();
  } else {
    c.count = r.is_incomplete() ? r.needed_bits() : r.consumed_bits();
  }
  if (r.is_complete()) {
    set(r.value());
  }
  return c;
}

// --- T-format -------------------------------------------------------------------------------
tf::decode_options tformat_options(const mb_tformat_options* o) {
  tf::decode_options d;
  if (o != nullptr) {
    d.res.single_turn_bits = o->single_turn_bits;
    d.res.multi_turn_bits = o->multi_turn_bits;
    d.check_unused_bits = o->check_unused_bits;
    d.resolution_from_enid = o->resolution_from_enid;
  }
  return d;
}

mb_result tformat_outcome(const mb::decode_result<tf::response>& r, mb_tformat_response* out) {
  return outcome(r, [out](const tf::response& v) {
    if (out != nullptr) {
      *out = mb_tformat_response{static_cast<std::uint8_t>(v.id),
                                 v.cf,
                                 v.sf,
                                 v.enid,
                                 v.almc,
                                 v.address,
                                 v.busy,
                                 v.edf,
                                 v.crc,
                                 v.abs,
                                 v.abm};
    }
  });
}

// --- Modbus ---------------------------------------------------------------------------------
mb_result frame_outcome(const mb::decode_result<md::rtu_frame>& r, mb_modbus_frame* out) {
  return outcome(r, [out](const md::rtu_frame& f) {
    if (out != nullptr) {
      *out = mb_modbus_frame{f.slave, f.pdu.data(), f.pdu.size(), f.crc};
    }
  });
}

md::rtu_frame rtu_frame_of(const mb_modbus_frame& f) {
  md::rtu_frame r;
  r.slave = f.slave;
  r.pdu = bytes(f.pdu, f.pdu_size);
  r.crc = f.crc;
  return r;
}

constexpr std::uint8_t illegal_function = 0x01;

// The device the server dispatches to: the C callback table. Every accessor is present (all
// functions compiled); admit() answers 01 for a function whose callback is NULL before
// anything else is checked, as a function the device does not serve.
class callback_device {
 public:
  explicit callback_device(const mb_modbus_callbacks& cb) noexcept : cb_(cb) {}

  std::uint8_t admit(mb::byte_view pdu) const {
    function_ = pdu[0];  // serve_pdu calls admit with a request of one byte at least
    bool served = false;
    switch (function_) {
      case 0x01: served = cb_.read_coils != nullptr; break;
      case 0x02: served = cb_.read_discrete_inputs != nullptr; break;
      case 0x03: served = cb_.read_holding_registers != nullptr; break;
      case 0x04: served = cb_.read_input_registers != nullptr; break;
      case 0x05: served = cb_.write_single_coil != nullptr; break;
      case 0x06: served = cb_.write_single_register != nullptr; break;
      case 0x0F: served = cb_.write_multiple_coils != nullptr; break;
      case 0x10: served = cb_.write_multiple_registers != nullptr; break;
      case 0x11: served = cb_.report_server_id != nullptr; break;
      case 0x16:
        served = cb_.read_holding_registers != nullptr &&
                 (cb_.write_single_register != nullptr || cb_.write_multiple_registers != nullptr);
        break;
      case 0x17:
        served = cb_.read_holding_registers != nullptr && cb_.write_multiple_registers != nullptr;
        break;
      default: break;
    }
    return served ? 0U : illegal_function;
  }

  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) {
    const auto call = function == 0x01 ? cb_.read_coils : cb_.read_discrete_inputs;
    return call(address, quantity, packed.data(), cb_.context);
  }
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              mb::span<std::uint16_t> out) {
    // FC16 and FC17 read holding registers (function 03)
    const auto call = function == 0x04 ? cb_.read_input_registers : cb_.read_holding_registers;
    return call(address, static_cast<std::uint16_t>(out.size()), out.data(), cb_.context);
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, mb::byte_view packed) {
    if (function_ == 0x05) {
      return cb_.write_single_coil(address, (packed[0] & 1U) != 0U, cb_.context);
    }
    return cb_.write_multiple_coils(address, quantity, packed.data(), cb_.context);
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    // FC06, and FC16 where there is a single-register writer: one register
    const bool single =
        function_ == 0x06 || (function_ == 0x16 && cb_.write_single_register != nullptr);
    if (single) {
      return cb_.write_single_register(address, values[0], cb_.context);
    }
    return cb_.write_multiple_registers(address, static_cast<std::uint16_t>(values.size()),
                                        values.data(), cb_.context);
  }
  std::uint8_t report_server_id(mb::mutable_byte_view out, std::size_t& size) {
    return cb_.report_server_id(out.data(), out.size(), &size, cb_.context);
  }

 private:
  const mb_modbus_callbacks& cb_;
  mutable std::uint8_t function_ = 0;  // the request's, set by admit()
};

static_assert(md::served_functions<callback_device>() == md::functions_of(0x01, 0x02, 0x03, 0x04,
                                                                          0x05, 0x06, 0x0F, 0x10,
                                                                          0x11, 0x16, 0x17),
              "the callback table's functions");

mb_result response_outcome(const mb::decode_result<md::response>& r, mb_modbus_response* out) {
  return outcome(r, [out](const md::response& v) {
    if (out != nullptr) {
      mb_modbus_response c{};
      c.data = v.data.data();
      c.data_size = v.data.size();
      c.function = v.function;
      c.exception = v.exception;
      c.exception_code = v.exception_code;
      c.byte_count = v.byte_count;
      c.address = v.address;
      c.quantity = v.quantity;
      c.value = v.value;
      c.and_mask = v.and_mask;
      c.or_mask = v.or_mask;
      c.sub_function = v.sub_function;
      c.status = v.status;
      c.event_count = v.event_count;
      c.message_count = v.message_count;
      c.fifo_count = v.fifo_count;
      *out = c;
    }
  });
}

// --- BiSS-C ---------------------------------------------------------------------------------
bs::slave_layout layout_of(const mb_biss_layout& l) {
  bs::slave_layout s;
  s.multi_turn_bits = l.multi_turn_bits;
  s.single_turn_bits = l.single_turn_bits;
  s.alignment_bits = l.alignment_bits;
  s.has_error = l.has_error;
  s.has_warning = l.has_warning;
  s.crc = bs::crc_format{l.crc_width, l.crc_poly, l.crc_start, l.crc_inverted};
  return s;
}

mb_biss_slave_data slave_data_of(const bs::slave_data& d) {
  return mb_biss_slave_data{d.data, d.multi_turn, d.single_turn, d.ne, d.nw, d.crc, d.crc_computed};
}

using capture_view = mb::span<const std::uint32_t>;

// A chain of 2..8 slaves (out of line: its layouts and frame stay off the single-slave path's
// stack).
__attribute__((noinline)) mb_result decode_chain(capture_view capture, std::size_t bit_count,
                                                 const mb_biss_layout* chain,
                                                 std::size_t chain_size,
                                                 const bs::decode_options& opt, mb::bit_order order,
                                                 mb_biss_frame* out) {
  bs::slave_layout layouts[bs::max_chain];
  for (std::size_t i = 0; i < chain_size; ++i) {
    layouts[i] = layout_of(chain[i]);
  }
  const mb::span<const bs::slave_layout> lay(layouts, chain_size);
  return outcome(bs::decode_frame(capture, bit_count, lay, opt, order),
                 [out](const bs::chain_frame<bs::max_chain>& f) {
                   if (out != nullptr) {
                     out->line_delay = f.line_delay;
                     out->start = f.start;
                     out->cds = f.cds;
                     out->count = f.count;
                     for (std::size_t i = 0; i < f.count; ++i) {
                       out->slaves[i] = slave_data_of(f.slaves[i]);
                     }
                   }
                 });
}

}  // namespace

extern "C" {

const char* mb_errc_name(int error) {
  return mb::to_string(static_cast<mb::errc>(static_cast<std::uint8_t>(error)));
}

// --- CRCs -----------------------------------------------------------------------------------
uint16_t mb_crc16_modbus(const uint8_t* data, size_t size) {
  return mb::crc16_modbus<>::compute(bytes(data, size));
}
uint8_t mb_crc8_tformat(const uint8_t* data, size_t size) {
  return mb::crc8_tformat<>::compute(bytes(data, size));
}
uint8_t mb_crc6_biss(uint64_t bits, unsigned count) {
  return mb::crc6_biss<>::compute_bits(bits, count > 64U ? 64U : count);
}
uint8_t mb_crc4_biss(uint64_t bits, unsigned count) {
  return mb::crc4_biss<>::compute_bits(bits, count > 64U ? 64U : count);
}

// --- T-format -------------------------------------------------------------------------------
mb_tformat_options mb_tformat_default_options(void) {
  const tf::decode_options d;
  return mb_tformat_options{d.res.single_turn_bits, d.res.multi_turn_bits, d.check_unused_bits,
                            d.resolution_from_enid};
}

mb_errc mb_tformat_encode_request(uint8_t id, uint8_t address, uint8_t data, uint8_t* out,
                                  size_t out_size, size_t* written) {
  return encoded(
      tf::encode_request(static_cast<tf::data_id>(id), address, data, out_bytes(out, out_size)),
      written);
}

mb_result mb_tformat_decode_response(const uint8_t* in, size_t size,
                                     const mb_tformat_options* options, mb_tformat_response* out) {
  return tformat_outcome(tf::decode_response(bytes(in, size), tformat_options(options)), out);
}

mb_result mb_tformat_decode_response_for(const uint8_t* request, size_t request_size,
                                         const uint8_t* in, size_t size,
                                         const mb_tformat_options* options,
                                         mb_tformat_response* out) {
  return tformat_outcome(tf::decode_response_for(bytes(request, request_size), bytes(in, size),
                                                 tformat_options(options)),
                         out);
}

mb_result mb_tformat_decode_request(const uint8_t* in, size_t size, mb_tformat_request* out) {
  return outcome(tf::decode_request(bytes(in, size)), [out](const tf::request& q) {
    if (out != nullptr) {
      *out = mb_tformat_request{static_cast<std::uint8_t>(q.id), q.cf, q.address, q.edf, q.crc};
    }
  });
}

mb_errc mb_tformat_encode_response(const mb_tformat_response* r, uint8_t* out, size_t out_size,
                                   size_t* written) {
  if (r == nullptr) {
    return encoded(mb::errc::invalid_argument, written);
  }
  tf::response v;
  v.id = static_cast<tf::data_id>(r->id);
  v.sf = r->sf;
  v.enid = r->enid;
  v.almc = r->almc;
  v.address = r->address;
  v.busy = r->busy;
  v.edf = r->edf;
  v.abs = r->abs;
  v.abm = r->abm;
  return encoded(tf::encode_response(v, out_bytes(out, out_size)), written);
}

mb_tformat_receiver_options mb_tformat_receiver_default_options(void) {
  const tf::receiver_options o;
  return mb_tformat_receiver_options{o.echo_mode == tf::echo::expected, o.check_against_request,
                                     mb_tformat_default_options()};
}

void mb_tformat_receiver_init(mb_tformat_receiver* rx, const mb_tformat_receiver_options* options) {
  tf::receiver_options o;
  if (options != nullptr) {
    o.echo_mode = options->echo_expected ? tf::echo::expected : tf::echo::none;
    o.check_against_request = options->check_against_request;
    o.decode = tformat_options(&options->decode);
  }
  ::new (static_cast<void*>(rx->bytes)) tf::receiver(o);
}

void mb_tformat_receiver_sent(mb_tformat_receiver* rx, const uint8_t* request, size_t size) {
  object<tf::receiver>(rx).sent(bytes(request, size));
}

bool mb_tformat_receiver_put(mb_tformat_receiver* rx, uint8_t byte) {
  return object<tf::receiver>(rx).put(byte);
}

mb_result mb_tformat_receiver_result(const mb_tformat_receiver* rx, mb_tformat_response* out) {
  return tformat_outcome(object<tf::receiver>(rx).result(), out);
}

mb_result mb_tformat_receiver_feed(mb_tformat_receiver* rx, const uint8_t* in, size_t size,
                                   mb_tformat_response* out) {
  return tformat_outcome(object<tf::receiver>(rx).feed(bytes(in, size)), out);
}

mb_result mb_tformat_receiver_idle(mb_tformat_receiver* rx) {
  return tformat_outcome(object<tf::receiver>(rx).idle(), nullptr);
}

size_t mb_tformat_receiver_dropped(const mb_tformat_receiver* rx) {
  return object<tf::receiver>(rx).dropped();
}
size_t mb_tformat_receiver_echoes_skipped(const mb_tformat_receiver* rx) {
  return object<tf::receiver>(rx).echoes_skipped();
}
size_t mb_tformat_receiver_pending(const mb_tformat_receiver* rx) {
  return object<tf::receiver>(rx).pending();
}
bool mb_tformat_receiver_echo_missed(const mb_tformat_receiver* rx) {
  return object<tf::receiver>(rx).echo_missed();
}

// --- Modbus RTU -----------------------------------------------------------------------------
mb_errc mb_modbus_encode_rtu(uint8_t slave, const uint8_t* pdu, size_t pdu_size, uint8_t* out,
                             size_t out_size, size_t* written) {
  return encoded(md::encode_rtu(slave, bytes(pdu, pdu_size), out_bytes(out, out_size)), written);
}

mb_result mb_modbus_decode_rtu(const uint8_t* adu, size_t size, mb_modbus_frame* out) {
  return frame_outcome(md::decode_rtu(bytes(adu, size)), out);
}

void mb_modbus_server_framer_init(mb_modbus_server_framer* framer,
                                  const mb_modbus_framer_options* options) {
  md::framer_options o;
  if (options != nullptr) {
    o.address = options->address;
    o.last_address = options->last_address;
    o.ends = options->length_only ? md::frame_end::length : md::frame_end::silence;
  }
  ::new (static_cast<void*>(framer->bytes)) md::rtu_server_framer(o);
}

bool mb_modbus_server_framer_put(mb_modbus_server_framer* framer, uint8_t byte) {
  return object<md::rtu_server_framer>(framer).put(byte);
}

mb_result mb_modbus_server_framer_result(const mb_modbus_server_framer* framer,
                                         mb_modbus_frame* out) {
  return frame_outcome(object<md::rtu_server_framer>(framer).result(), out);
}

mb_result mb_modbus_server_framer_feed(mb_modbus_server_framer* framer, const uint8_t* in,
                                       size_t size, mb_modbus_frame* out) {
  return frame_outcome(object<md::rtu_server_framer>(framer).feed(bytes(in, size)), out);
}

mb_result mb_modbus_server_framer_idle(mb_modbus_server_framer* framer, mb_modbus_frame* out) {
  return frame_outcome(object<md::rtu_server_framer>(framer).idle(), out);
}

size_t mb_modbus_server_framer_pending(const mb_modbus_server_framer* framer) {
  return object<md::rtu_server_framer>(framer).pending();
}
size_t mb_modbus_server_framer_dropped(const mb_modbus_server_framer* framer) {
  return object<md::rtu_server_framer>(framer).dropped();
}
size_t mb_modbus_server_framer_skipped(const mb_modbus_server_framer* framer) {
  return object<md::rtu_server_framer>(framer).skipped();
}

mb_errc mb_modbus_serve_frame(const mb_modbus_callbacks* callbacks, uint8_t own_address,
                              const mb_modbus_frame* frame, uint8_t* out, size_t out_size,
                              size_t* written) {
  if (callbacks == nullptr || frame == nullptr) {
    return encoded(mb::errc::invalid_argument, written);
  }
  callback_device dev(*callbacks);
  return encoded(md::serve_frame(dev, own_address, rtu_frame_of(*frame), out_bytes(out, out_size)),
                 written);
}

mb_errc mb_modbus_serve_pdu(const mb_modbus_callbacks* callbacks, const uint8_t* pdu,
                            size_t pdu_size, uint8_t* out, size_t out_size, size_t* written) {
  if (callbacks == nullptr) {
    return encoded(mb::errc::invalid_argument, written);
  }
  callback_device dev(*callbacks);
  return encoded(md::serve_pdu(dev, bytes(pdu, pdu_size), out_bytes(out, out_size)), written);
}

mb_errc mb_modbus_encode_read(uint8_t function, uint16_t address, uint16_t quantity, uint8_t* out,
                              size_t out_size, size_t* written) {
  return encoded(md::encode_read(function, address, quantity, out_bytes(out, out_size)), written);
}

mb_errc mb_modbus_encode_write_single_coil(uint16_t address, bool on, uint8_t* out, size_t out_size,
                                           size_t* written) {
  return encoded(md::encode_write_single_coil(address, on, out_bytes(out, out_size)), written);
}

mb_errc mb_modbus_encode_write_single_register(uint16_t address, uint16_t value, uint8_t* out,
                                               size_t out_size, size_t* written) {
  return encoded(md::encode_write_single_register(address, value, out_bytes(out, out_size)),
                 written);
}

mb_errc mb_modbus_encode_write_multiple_coils(uint16_t address, uint16_t quantity,
                                              const uint8_t* packed, size_t packed_size,
                                              uint8_t* out, size_t out_size, size_t* written) {
  return encoded(md::encode_write_multiple_coils(address, quantity, bytes(packed, packed_size),
                                                 out_bytes(out, out_size)),
                 written);
}

mb_errc mb_modbus_encode_write_multiple_registers(uint16_t address, const uint16_t* values,
                                                  size_t count, uint8_t* out, size_t out_size,
                                                  size_t* written) {
  const mb::span<const std::uint16_t> v = values == nullptr
                                              ? mb::span<const std::uint16_t>()
                                              : mb::span<const std::uint16_t>(values, count);
  return encoded(md::encode_write_multiple_registers(address, v, out_bytes(out, out_size)),
                 written);
}

mb_errc mb_modbus_encode_mask_write_register(uint16_t address, uint16_t and_mask, uint16_t or_mask,
                                             uint8_t* out, size_t out_size, size_t* written) {
  return encoded(
      md::encode_mask_write_register(address, and_mask, or_mask, out_bytes(out, out_size)),
      written);
}

mb_errc mb_modbus_encode_read_write_multiple_registers(
    uint16_t read_address, uint16_t read_quantity, uint16_t write_address, const uint16_t* values,
    size_t count, uint8_t* out, size_t out_size, size_t* written) {
  const mb::span<const std::uint16_t> v = values == nullptr
                                              ? mb::span<const std::uint16_t>()
                                              : mb::span<const std::uint16_t>(values, count);
  return encoded(md::encode_read_write_multiple_registers(
                     read_address, read_quantity, write_address, v, out_bytes(out, out_size)),
                 written);
}

mb_errc mb_modbus_encode_raw(uint8_t function, const uint8_t* data, size_t data_size, uint8_t* out,
                             size_t out_size, size_t* written) {
  return encoded(md::encode_raw(function, bytes(data, data_size), out_bytes(out, out_size)),
                 written);
}

mb_result mb_modbus_decode_response_for(const uint8_t* sent, size_t sent_size, const uint8_t* pdu,
                                        size_t pdu_size, mb_modbus_response* out) {
  return response_outcome(md::decode_response_for(bytes(sent, sent_size), bytes(pdu, pdu_size)),
                          out);
}

mb_result mb_modbus_decode_response_unpaired(const uint8_t* pdu, size_t pdu_size,
                                             mb_modbus_response* out) {
  return response_outcome(md::decode_response_unpaired(bytes(pdu, pdu_size)), out);
}

uint16_t mb_modbus_register_at(const uint8_t* data, size_t index) {
  return md::register_at(mb::byte_view(data, 2U * index + 2U), index);
}

bool mb_modbus_bit_at(const uint8_t* packed, size_t index) {
  return md::bit_at(mb::byte_view(packed, index / 8U + 1U), index);
}

// --- BiSS-C ---------------------------------------------------------------------------------
mb_biss_layout mb_biss_absys_layout(void) {
  const bs::slave_layout& l = bs::absys_layout;
  return mb_biss_layout{static_cast<std::uint8_t>(l.multi_turn_bits),
                        static_cast<std::uint8_t>(l.single_turn_bits),
                        static_cast<std::uint8_t>(l.alignment_bits),
                        l.has_error,
                        l.has_warning,
                        static_cast<std::uint8_t>(l.crc.width),
                        l.crc.poly,
                        l.crc.start,
                        l.crc.inverted};
}

mb_result mb_biss_decode_frame(const uint32_t* words, size_t word_count, size_t bit_count,
                               const mb_biss_layout* chain, size_t chain_size,
                               size_t max_line_delay, size_t max_ack_bits, bool lsb_first,
                               mb_biss_frame* out) {
  if (chain == nullptr || chain_size == 0U || chain_size > bs::max_chain) {
    mb_result bad{};
    bad.status = MB_FAILED;
    bad.error = MB_INVALID_ARGUMENT;
    return bad;
  }
  bs::decode_options opt;
  if (max_line_delay != 0U) {
    opt.max_line_delay = max_line_delay;
  }
  if (max_ack_bits != 0U) {
    opt.max_ack_bits = max_ack_bits;
  }
  const capture_view capture = words == nullptr ? capture_view() : capture_view(words, word_count);
  const mb::bit_order order = lsb_first ? mb::bit_order::lsb_first : mb::bit_order::msb_first;
  if (chain_size > 1U) {
    return decode_chain(capture, bit_count, chain, chain_size, opt, order, out);
  }
  // one slave: the single-slave decoder, one slave copied
  return outcome(bs::decode_frame(capture, bit_count, layout_of(chain[0]), opt, order),
                 [out](const bs::single_frame& f) {
                   if (out != nullptr) {
                     out->line_delay = f.line_delay;
                     out->start = f.start;
                     out->cds = f.cds;
                     out->count = 1;
                     out->slaves[0] = slave_data_of(f.slaves[0]);
                   }
                 });
}

mb_errc mb_biss_encode_frame(const mb_biss_layout* layout, const mb_biss_slave_values* values,
                             size_t line_delay, size_t ack_bits, bool cds, uint32_t* words,
                             size_t word_count, size_t* bits) {
  if (layout == nullptr || values == nullptr) {
    return encoded(mb::errc::invalid_argument, bits);
  }
  bs::slave_values v;
  v.multi_turn = values->multi_turn;
  v.single_turn = values->single_turn;
  v.ne = values->ne;
  v.nw = values->nw;
  bs::line_options line;
  line.line_delay = line_delay;
  line.ack_bits = ack_bits;
  line.cds = cds;
  const mb::span<std::uint32_t> out =
      words == nullptr ? mb::span<std::uint32_t>() : mb::span<std::uint32_t>(words, word_count);
  return encoded(bs::encode_frame(layout_of(*layout), v, out, line), bits);
}

void mb_biss_control_master_init(mb_biss_control_master* master, size_t max_wait_frames) {
  bs::control_options o;
  if (max_wait_frames != 0U) {
    o.max_wait_frames = max_wait_frames;
  }
  ::new (static_cast<void*>(master->bytes)) bs::control_master(o);
}

mb_errc mb_biss_control_master_start_read(mb_biss_control_master* master, uint8_t slave_id,
                                          uint8_t address, uint8_t* out, size_t size) {
  return to_c(
      object<bs::control_master>(master).start_read(slave_id, address, out_bytes(out, size)));
}

mb_errc mb_biss_control_master_start_write(mb_biss_control_master* master, uint8_t slave_id,
                                           uint8_t address, const uint8_t* data, size_t size) {
  return to_c(object<bs::control_master>(master).start_write(slave_id, address, bytes(data, size)));
}

void mb_biss_control_master_abort(mb_biss_control_master* master) {
  object<bs::control_master>(master).abort();
}

bool mb_biss_control_master_step(mb_biss_control_master* master, bool cds) {
  return object<bs::control_master>(master).step(cds);
}

mb_biss_control_state mb_biss_control_master_state(const mb_biss_control_master* master) {
  return static_cast<mb_biss_control_state>(object<bs::control_master>(master).state());
}

mb_errc mb_biss_control_master_error(const mb_biss_control_master* master) {
  return to_c(object<bs::control_master>(master).error());
}

size_t mb_biss_control_master_transferred(const mb_biss_control_master* master) {
  return object<bs::control_master>(master).transferred();
}

size_t mb_biss_control_master_frames(const mb_biss_control_master* master) {
  return object<bs::control_master>(master).frames();
}

size_t mb_biss_control_frames_for(size_t bytes) {
  return bs::control_master::frames_for(bytes);
}

}  // extern "C"

static_assert(
    static_cast<int>(MB_BISS_CONTROL_IDLE) == static_cast<int>(bs::control_state::idle) &&
        static_cast<int>(MB_BISS_CONTROL_BUSY) == static_cast<int>(bs::control_state::busy) &&
        static_cast<int>(MB_BISS_CONTROL_DONE) == static_cast<int>(bs::control_state::done) &&
        static_cast<int>(MB_BISS_CONTROL_FAILED) == static_cast<int>(bs::control_state::failed),
    "mb_biss_control_state is control_state");
