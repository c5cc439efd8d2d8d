// motionbus — Modbus RTU server dispatch: the library decodes, checks, calls the user's data
// accessors and builds the response or the right exception; nothing for broadcasts (address
// 0: executed, never answered) or for other addresses (Modbus over Serial Line §2.2).
// serve_frame serves one device at one address; serve_units several units on one port, each
// by the device a lookup gives for it (docs/modbus.md §11); serve_pdu a request PDU with no
// address and CRC (Modbus TCP).
//
// The device is any type with some of these members (detected at compile time; no virtual
// calls, no heap). Each returns 0 on success or a Modbus exception code (02 illegal address,
// 03 illegal value, 04 device failure, or any other code, passed through):
//   std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
//                          motionbus::mutable_byte_view packed);        // FC01, FC02
//   std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
//                               motionbus::span<std::uint16_t> out);    // FC03, FC04 (and 16, 17)
//   std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity,
//                            motionbus::byte_view packed);              // FC05, FC0F
//   std::uint8_t write_registers(std::uint16_t address,
//                                motionbus::span<const std::uint16_t>); // FC06, FC10 (16, 17)
//   std::uint8_t report_server_id(motionbus::mutable_byte_view out, std::size_t& size); // FC11
//   std::uint8_t read_file_record(std::uint16_t file, std::uint16_t record,
//                                 motionbus::mutable_byte_view out);  // FC14: 2 x length bytes
//   std::uint8_t write_file_record(std::uint16_t file, std::uint16_t record,
//                                  motionbus::byte_view data);        // FC15: 2 x length bytes
//       // file records (Modbus App. Protocol §6.14, §6.15), as big-endian register bytes, one
//       // call per sub-request, in the request's order; optional, checked before any write:
//   std::uint8_t check_file_record(std::uint16_t file, std::uint16_t record,
//                                  std::uint16_t length) const;
//       // without it an FC15 sub-request that fails leaves the ones before it written
// Registers may instead be read and written as the big-endian bytes of the PDU, which spares
// the server a register buffer (250 bytes of stack) and a conversion (preferred when present):
//   std::uint8_t read_registers_be(std::uint8_t function, std::uint16_t address,
//                                  std::uint16_t quantity, motionbus::mutable_byte_view out);
//   std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity,
//                                   motionbus::byte_view data);   // FC06 (2 bytes), FC10
//   static constexpr motionbus::modbus::function_set functions = ...;  // optional: serve only
//                                                  // these of the functions the accessors
//                                                  // allow (e.g. not FC16/17 over registers);
//                                                  // the others are answered with 01 and cost
//                                                  // no code
//   std::uint8_t admit(motionbus::byte_view pdu) const;
//       // optional: a device-specific first check of the raw request PDU (e.g. its own order
//       // of exceptions); 0 lets it through
//   std::uint8_t check_registers(std::uint8_t function, std::uint16_t address,
//                                std::uint16_t quantity) const;
//       // optional: whether FC17's read (function 03) or write (10) range may be accessed,
//       // accessing nothing; without it the read range is checked by reading it, so that FC17
//       // reads it twice: a device whose reads have side effects (clear-on-read or FIFO
//       // registers) needs check_registers
// The contract that makes an exception mean that nothing was done: an accessor that returns an
// exception has changed nothing; read accessors, admit and check_registers change nothing and
// have no side effects (FC16 and FC17 read before they write; admit and check_registers are
// called on the const device). The server then calls a write accessor only after every
// other check of the request, and last but for FC17's read (a read that fails after FC17's
// write is answered 04, the specification's processing failure). FC17 (Modbus App. Protocol
// §6.17): both ranges checked, then the write, then the read, which sees the write.
// served_functions<Device>() says which functions a device type is served; any other is
// answered with exception 01. The request's own limits are checked first (decode_request:
// exception 01, then 03, then 02), as the spec's state diagrams order them (Modbus App.
// Protocol §6). A device type that serves no function, names in `functions` one its accessors
// cannot serve, or has a member named like an accessor that does not have the accessor's
// signature (or named like its singular, read_register, ..., with no accessor of its kind),
// fails to compile with a message that gives the expected signature.
#ifndef MOTIONBUS_MODBUS_SERVER_HPP
#define MOTIONBUS_MODBUS_SERVER_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/rtu.hpp"

namespace motionbus {
namespace modbus {

namespace detail {

// The accessors, each detected by its exact signature (the call below compiles and returns
// std::uint8_t); a member of the same name that does not match is a compile-time error
// (device_checks).
template <template <class> class Call, class D, class = void>
struct returns_code : std::false_type {};
template <template <class> class Call, class D>
struct returns_code<Call, D, std::void_t<Call<D>>> : std::is_same<Call<D>, std::uint8_t> {};

template <class D>
using read_bits_call = decltype(std::declval<D&>().read_bits(std::uint8_t{}, std::uint16_t{},
                                                             std::uint16_t{}, mutable_byte_view{}));
template <class D>
using read_registers_call = decltype(std::declval<D&>().read_registers(
    std::uint8_t{}, std::uint16_t{}, span<std::uint16_t>{}));
template <class D>
using write_coils_call =
    decltype(std::declval<D&>().write_coils(std::uint16_t{}, std::uint16_t{}, byte_view{}));
template <class D>
using write_registers_call =
    decltype(std::declval<D&>().write_registers(std::uint16_t{}, span<const std::uint16_t>{}));
template <class D>
using read_registers_be_call = decltype(std::declval<D&>().read_registers_be(
    std::uint8_t{}, std::uint16_t{}, std::uint16_t{}, mutable_byte_view{}));
template <class D>
using write_registers_be_call =
    decltype(std::declval<D&>().write_registers_be(std::uint16_t{}, std::uint16_t{}, byte_view{}));
template <class D>
using report_server_id_call = decltype(std::declval<D&>().report_server_id(
    mutable_byte_view{}, std::declval<std::size_t&>()));
template <class D>
using check_registers_call = decltype(std::declval<const D&>().check_registers(
    std::uint8_t{}, std::uint16_t{}, std::uint16_t{}));  // const: a check changes nothing
template <class D>
using admit_call = decltype(std::declval<const D&>().admit(byte_view{}));  // const, as above
// FC14/15 file records
template <class D>
using read_file_record_call = decltype(std::declval<D&>().read_file_record(
    std::uint16_t{}, std::uint16_t{}, mutable_byte_view{}));
template <class D>
using write_file_record_call =
    decltype(std::declval<D&>().write_file_record(std::uint16_t{}, std::uint16_t{}, byte_view{}));
template <class D>
using check_file_record_call = decltype(std::declval<const D&>().check_file_record(
    std::uint16_t{}, std::uint16_t{}, std::uint16_t{}));  // const: a check changes nothing

template <class D>
using has_read_bits = returns_code<read_bits_call, D>;
template <class D>
using has_read_registers = returns_code<read_registers_call, D>;
template <class D>
using has_write_coils = returns_code<write_coils_call, D>;
template <class D>
using has_write_registers = returns_code<write_registers_call, D>;
template <class D>
using has_read_registers_be = returns_code<read_registers_be_call, D>;
template <class D>
using has_write_registers_be = returns_code<write_registers_be_call, D>;
template <class D>
using has_report_server_id = returns_code<report_server_id_call, D>;
template <class D>
using has_check_registers = returns_code<check_registers_call, D>;
template <class D>
using has_admit = returns_code<admit_call, D>;
template <class D>
using has_read_file_record = returns_code<read_file_record_call, D>;
template <class D>
using has_write_file_record = returns_code<write_file_record_call, D>;
template <class D>
using has_check_file_record = returns_code<check_file_record_call, D>;

template <class D, class = void>
struct has_function_set : std::false_type {};
template <class D>
struct has_function_set<D, std::void_t<decltype(function_set{D::functions})>>
    : std::negation<std::is_member_pointer<decltype(&D::functions)>> {};  // a static member

// Members named like an accessor, whatever their signature: a member of D of one of these
// names makes the name ambiguous in name_probe<D> (the usual member-name detector; a final
// device type cannot be derived from, and is checked by signature only). The singular names
// are the near misses of the plural ones where the device has no accessor of their kind (a
// helper read_register next to read_registers_be is no mistake).
struct accessor_names {
  int read_bits, read_registers, write_coils, write_registers, read_registers_be,
      write_registers_be, report_server_id, check_registers, admit, functions;
  int read_bit, read_register, write_coil, write_register, read_register_be, write_register_be,
      report_slave_id;
  int read_file_record, write_file_record, check_file_record;  // FC14/15
};
template <class D>
struct name_probe : D, accessor_names {};
template <class D>
using probe_of = std::conditional_t<std::is_class<D>::value && !std::is_final<D>::value,
                                    name_probe<std::remove_cv_t<D>>, accessor_names>;

template <class P>
using read_bits_name = decltype(&P::read_bits);
template <class P>
using read_registers_name = decltype(&P::read_registers);
template <class P>
using write_coils_name = decltype(&P::write_coils);
template <class P>
using write_registers_name = decltype(&P::write_registers);
template <class P>
using read_registers_be_name = decltype(&P::read_registers_be);
template <class P>
using write_registers_be_name = decltype(&P::write_registers_be);
template <class P>
using report_server_id_name = decltype(&P::report_server_id);
template <class P>
using check_registers_name = decltype(&P::check_registers);
template <class P>
using admit_name = decltype(&P::admit);
template <class P>
using functions_name = decltype(&P::functions);
template <class P>
using read_bit_name = decltype(&P::read_bit);
template <class P>
using read_register_name = decltype(&P::read_register);
template <class P>
using write_coil_name = decltype(&P::write_coil);
template <class P>
using write_register_name = decltype(&P::write_register);
template <class P>
using read_register_be_name = decltype(&P::read_register_be);
template <class P>
using write_register_be_name = decltype(&P::write_register_be);
template <class P>
using report_slave_id_name = decltype(&P::report_slave_id);
template <class P>
using read_file_record_name = decltype(&P::read_file_record);
template <class P>
using write_file_record_name = decltype(&P::write_file_record);
template <class P>
using check_file_record_name = decltype(&P::check_file_record);

// Whether D has a member called as Name says (the probe's own member alone is unambiguous).
template <template <class> class Name, class D, class = void>
struct names : std::true_type {};
template <template <class> class Name, class D>
struct names<Name, D, std::void_t<Name<probe_of<D>>>> : std::false_type {};

constexpr std::uint8_t illegal_function_code =
    static_cast<std::uint8_t>(exception_code::illegal_function);

template <class Device>
constexpr bool can_read_registers =
    has_read_registers<Device>::value || has_read_registers_be<Device>::value;
template <class Device>
constexpr bool can_write_registers =
    has_write_registers<Device>::value || has_write_registers_be<Device>::value;

// The functions the device's accessors allow, before its own `functions` narrows them.
template <class Device>
constexpr function_set accessor_functions() noexcept {
  function_set set = 0;
  if constexpr (has_read_bits<Device>::value) {
    set |= functions_of(0x01, 0x02);
  }
  if constexpr (can_read_registers<Device>) {
    set |= functions_of(0x03, 0x04);
  }
  if constexpr (has_write_coils<Device>::value) {
    set |= functions_of(0x05, 0x0F);
  }
  if constexpr (can_write_registers<Device>) {
    set |= functions_of(0x06, 0x10);
  }
  if constexpr (can_read_registers<Device> && can_write_registers<Device>) {
    set |= functions_of(0x16, 0x17);
  }
  if constexpr (has_report_server_id<Device>::value) {
    set |= functions_of(0x11);
  }
  if constexpr (has_read_file_record<Device>::value) {
    set |= functions_of(0x14);
  }
  if constexpr (has_write_file_record<Device>::value) {
    set |= functions_of(0x15);
  }
  return set;
}

// The device's own `functions`, or none.
template <class Device>
constexpr function_set declared_functions() noexcept {
  if constexpr (has_function_set<Device>::value) {
    return Device::functions;
  } else {
    return 0;
  }
}

}  // namespace detail

/// The functions serve_frame and serve_rtu serve for a device type: those its accessors allow
/// (01/02 read_bits; 03/04 read_registers or read_registers_be; 05/0F write_coils; 06/10
/// write_registers or write_registers_be; 16/17 a register reader and a register writer; 11
/// report_server_id; 14 read_file_record; 15 write_file_record), narrowed by its `functions` if it
/// has one. Only these are decoded; any other function is answered with exception 01.
template <class Device>
constexpr function_set served_functions() noexcept {
  const function_set set = detail::accessor_functions<Device>();
  // the device's own choice among those
  return detail::has_function_set<Device>::value ? set & detail::declared_functions<Device>() : set;
}

namespace detail {

// The compile-time checks of a device type (instantiated by serve_frame): a member named like
// an accessor must have its signature, and the device must serve at least one function (an
// accessor, a `functions` not empty) and name in `functions` only functions its accessors
// serve: its served set is never empty.
template <class D>
struct device_checks {
  static_assert(!names<read_bits_name, D>::value || has_read_bits<D>::value,
                "modbus server device: read_bits must be std::uint8_t read_bits(std::uint8_t "
                "function, std::uint16_t address, std::uint16_t quantity, "
                "motionbus::mutable_byte_view packed)");
  static_assert(!names<read_registers_name, D>::value || has_read_registers<D>::value,
                "modbus server device: read_registers must be std::uint8_t "
                "read_registers(std::uint8_t function, std::uint16_t address, "
                "motionbus::span<std::uint16_t> out)");
  static_assert(!names<write_coils_name, D>::value || has_write_coils<D>::value,
                "modbus server device: write_coils must be std::uint8_t "
                "write_coils(std::uint16_t address, std::uint16_t quantity, motionbus::byte_view "
                "packed)");
  static_assert(!names<write_registers_name, D>::value || has_write_registers<D>::value,
                "modbus server device: write_registers must be std::uint8_t "
                "write_registers(std::uint16_t address, motionbus::span<const std::uint16_t> "
                "values)");
  static_assert(!names<read_registers_be_name, D>::value || has_read_registers_be<D>::value,
                "modbus server device: read_registers_be must be std::uint8_t "
                "read_registers_be(std::uint8_t function, std::uint16_t address, std::uint16_t "
                "quantity, motionbus::mutable_byte_view out)");
  static_assert(!names<write_registers_be_name, D>::value || has_write_registers_be<D>::value,
                "modbus server device: write_registers_be must be std::uint8_t "
                "write_registers_be(std::uint16_t address, std::uint16_t quantity, "
                "motionbus::byte_view data)");
  static_assert(!names<report_server_id_name, D>::value || has_report_server_id<D>::value,
                "modbus server device: report_server_id must be std::uint8_t "
                "report_server_id(motionbus::mutable_byte_view out, std::size_t& size)");
  static_assert(!names<check_registers_name, D>::value || has_check_registers<D>::value,
                "modbus server device: check_registers must be std::uint8_t "
                "check_registers(std::uint8_t function, std::uint16_t address, std::uint16_t "
                "quantity) const");
  static_assert(!names<admit_name, D>::value || has_admit<D>::value,
                "modbus server device: admit must be std::uint8_t admit(motionbus::byte_view pdu) "
                "const");
  static_assert(!names<functions_name, D>::value || has_function_set<D>::value,
                "modbus server device: functions must be static constexpr "
                "motionbus::modbus::function_set functions = functions_of(...)");
  static_assert(!names<read_bit_name, D>::value || has_read_bits<D>::value,
                "modbus server device: read_bit is no accessor; did you mean std::uint8_t "
                "read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity, "
                "motionbus::mutable_byte_view packed)?");
  static_assert(!names<read_register_name, D>::value || can_read_registers<D>,
                "modbus server device: read_register is no accessor; did you mean std::uint8_t "
                "read_registers(std::uint8_t function, std::uint16_t address, "
                "motionbus::span<std::uint16_t> out)?");
  static_assert(!names<write_coil_name, D>::value || has_write_coils<D>::value,
                "modbus server device: write_coil is no accessor; did you mean std::uint8_t "
                "write_coils(std::uint16_t address, std::uint16_t quantity, motionbus::byte_view "
                "packed)?");
  static_assert(!names<write_register_name, D>::value || can_write_registers<D>,
                "modbus server device: write_register is no accessor; did you mean std::uint8_t "
                "write_registers(std::uint16_t address, motionbus::span<const std::uint16_t> "
                "values)?");
  static_assert(!names<read_register_be_name, D>::value || can_read_registers<D>,
                "modbus server device: read_register_be is no accessor; did you mean "
                "std::uint8_t read_registers_be(std::uint8_t function, std::uint16_t address, "
                "std::uint16_t quantity, motionbus::mutable_byte_view out)?");
  static_assert(!names<write_register_be_name, D>::value || can_write_registers<D>,
                "modbus server device: write_register_be is no accessor; did you mean "
                "std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity, "
                "motionbus::byte_view data)?");
  static_assert(!names<report_slave_id_name, D>::value || has_report_server_id<D>::value,
                "modbus server device: report_slave_id is no accessor; did you mean std::uint8_t "
                "report_server_id(motionbus::mutable_byte_view out, std::size_t& size)?");
  static_assert(!names<read_file_record_name, D>::value || has_read_file_record<D>::value,
                "modbus server device: read_file_record must be std::uint8_t "
                "read_file_record(std::uint16_t file, std::uint16_t record, "
                "motionbus::mutable_byte_view out)");
  static_assert(!names<write_file_record_name, D>::value || has_write_file_record<D>::value,
                "modbus server device: write_file_record must be std::uint8_t "
                "write_file_record(std::uint16_t file, std::uint16_t record, motionbus::byte_view "
                "data)");
  static_assert(!names<check_file_record_name, D>::value || has_check_file_record<D>::value,
                "modbus server device: check_file_record must be std::uint8_t "
                "check_file_record(std::uint16_t file, std::uint16_t record, std::uint16_t "
                "length) const");
  static_assert(
      accessor_functions<D>() != 0U,
      "modbus server device: no accessor the server recognises; it needs one of "
      "read_bits, read_registers, read_registers_be, write_coils, write_registers, "
      "write_registers_be, report_server_id, read_file_record, write_file_record (signatures "
      "in modbus/server.hpp)");
  static_assert(!has_function_set<D>::value || declared_functions<D>() != 0U,
                "modbus server device: its functions is empty; every request would be answered "
                "with exception 01");
  static_assert((declared_functions<D>() & ~accessor_functions<D>()) == 0U,
                "modbus server device: its functions names a function its accessors cannot "
                "serve (01/02 need read_bits; 03/04 read_registers or read_registers_be; 05/0F "
                "write_coils; 06/10 write_registers or write_registers_be; 16/17 a register "
                "reader and writer; 11 report_server_id; 14 read_file_record; 15 "
                "write_file_record)");
  static constexpr bool value = true;
};

// The device's read_registers into `regs` (`quantity` of them, cleared), then, if it answers
// 0, their values into the response PDU after the function and byte count.
template <class Device>
constexpr std::uint8_t read_through(Device& dev, std::uint8_t f, std::uint16_t address,
                                    span<std::uint16_t> regs, mutable_byte_view pdu_out) noexcept {
  const std::uint8_t code = dev.read_registers(f, address, regs);
  if (code == 0U) {
    put_registers(pdu_out, 2, span<const std::uint16_t>(regs.data(), regs.size()));
  }
  return code;
}

// At run time the register buffer is cleared as far as the request reaches (a device that
// leaves a register unwritten answers 0 for it, never a stale stack value), not whole: a
// 2-register read clears 4 bytes, not 250. Not constexpr: C++17 wants every variable of a
// constexpr function initialised, which is read_registers_into's own buffer below.
// inline: in the dispatch's frame its buffer shares a slot with the write path's; out of line
// the two frames add up (meter: a buffer's worth more stack on Cortex-M0+/M4 at -O2).
template <class Device>
MOTIONBUS_INLINE std::uint8_t read_through_uncleared(Device& dev, std::uint8_t f,
                                                     std::uint16_t address, std::uint16_t quantity,
                                                     mutable_byte_view pdu_out) noexcept {
  std::uint16_t regs[max_read_registers];
#if defined(__GNUC__) || defined(__clang__)
  // (for the loop below clang's rv32 code keeps a second buffer on the stack: meter, -Os)
  __builtin_memset(regs, 0, std::size_t{2} * quantity);
#else
  for (std::size_t i = 0; i < quantity; ++i) {
    regs[i] = 0;
  }
#endif
  return read_through(dev, f, address, span<std::uint16_t>(regs, quantity), pdu_out);
}

// Reads q.quantity registers from `address` into the response PDU `pdu_out` (function, byte
// count, values), through whichever accessor the device has. Returns 0 or the exception code.
template <class Device>
constexpr std::uint8_t read_registers_into(Device& dev, std::uint8_t f, std::uint16_t address,
                                           std::uint16_t quantity,
                                           mutable_byte_view pdu_out) noexcept {
  pdu_out[0] = f;
  pdu_out[1] = static_cast<std::uint8_t>(2U * quantity);
  if constexpr (has_read_registers_be<Device>::value) {
    return dev.read_registers_be(f, address, quantity,
                                 pdu_out.subspan(2, std::size_t{2} * quantity));
  } else {
    // coverage-branch: false only in constant evaluation, which gcov does not count
    if (!MOTIONBUS_CONSTANT_EVALUATED()) {
      return read_through_uncleared(dev, f, address, quantity, pdu_out);
    }
    // coverage-begin: constant evaluation only (not counted), and compilers that cannot tell it
    std::uint16_t regs[max_read_registers] = {};
    return read_through(dev, f, address, span<std::uint16_t>(regs, quantity), pdu_out);
    // coverage-end
  }
}

// Writes the big-endian register values `data` from `address`, through whichever accessor the
// device has. Returns 0 or the exception code.
template <class Device>
constexpr std::uint8_t write_registers_from(Device& dev, std::uint16_t address,
                                            byte_view data) noexcept {
  const std::size_t n = data.size() / 2U;
  if constexpr (has_write_registers_be<Device>::value) {
    return dev.write_registers_be(address, static_cast<std::uint16_t>(n), data);
  } else {
    std::uint16_t writes[max_write_registers] = {};
    // coverage-branch: decode_request caps n at max_write_registers: the 2nd bound never ends it
    for (std::size_t i = 0; i < n && i < max_write_registers; ++i) {
      writes[i] = register_at(data, i);
    }
    return dev.write_registers(address, span<const std::uint16_t>(writes, n));
  }
}

// FC14/15 (Modbus App. Protocol §6.14, §6.15): `data` is the request after its function code
// (decode_request leaves these functions raw). The sub-requests are decoded and checked whole
// (exceptions 03, then 02, as decode_file_record_request), then served in order: FC14 reads each
// record into its place in the response; FC15 checks every sub-request with check_file_record if
// the device has it, then writes each. Returns the response's size.
template <class Device>
constexpr std::size_t serve_file_records(Device& dev, std::uint8_t f, byte_view data,
                                         mutable_byte_view pdu_out) noexcept {
  const decode_result<file_records> d = decode_file_records(f, data);
  std::uint8_t code = 0;
  if (!d.is_complete()) {
    code = static_cast<std::uint8_t>(exception_for(d.error()));
  }
  constexpr bool reads = has_read_file_record<Device>::value;
  constexpr bool writes = has_write_file_record<Device>::value;
  // coverage-branch: never true: serve_frame answers a function without its accessor (01)
  if (f == read_file_record_function ? !reads : !writes) {
    // coverage: serve_frame answers a function without its accessor with 01 before this
    code = illegal_function_code;
  }
  const file_records& q = d.value();
  std::size_t at = 2;  // FC14: where the next record's answer goes
  if constexpr (has_check_file_record<Device>::value) {
    for (std::size_t k = 0; code == 0U && f == write_file_record_function && k < q.count; ++k) {
      const file_record rec = file_record_at(q, k).value();
      code = std::as_const(dev).check_file_record(rec.file, rec.record, rec.length);
    }
  }
  for (std::size_t k = 0; code == 0U && k < q.count; ++k) {
    const file_record rec = file_record_at(q, k).value();
    if (f == read_file_record_function) {
      if constexpr (reads) {
        const std::size_t bytes = 2U * std::size_t{rec.length};
        pdu_out[at] = static_cast<std::uint8_t>(1U + bytes);
        pdu_out[at + 1U] = file_reference_type;
        code = dev.read_file_record(rec.file, rec.record, pdu_out.subspan(at + 2U, bytes));
        at += 2U + bytes;
      }
    } else {
      if constexpr (writes) {
        code = dev.write_file_record(rec.file, rec.record, rec.data);
      }
    }
  }
  if (code != 0U) {
    return encode_exception(f, code, pdu_out).value_or(0);
  }
  if (f == read_file_record_function) {
    pdu_out[0] = f;
    pdu_out[1] = static_cast<std::uint8_t>(at - 2U);  // decode_file_records: at <= 253
    return at;
  }
  return encode_write_file_record_response(q, pdu_out).value_or(0);
}

// Serves one decoded request; writes the response PDU into `pdu_out` (>= 253 bytes).
// Returns its size (an exception response is 2 bytes). No buffer is cleared per request: the
// response is built where it is sent from, registers go through a buffer only for a device
// without the big-endian accessors.
template <class Device>
constexpr std::size_t serve_pdu(Device& dev, const request& q, mutable_byte_view pdu_out) noexcept {
  const std::uint8_t f = q.function;
  std::uint8_t code = illegal_function_code;
  // only the functions served are compiled (serve_frame answers the others with 01)
  constexpr auto serves = [](unsigned c) { return ((served_functions<Device>() >> c) & 1U) != 0U; };
  auto exception = [&](std::uint8_t c) { return encode_exception(f, c, pdu_out).value_or(0); };
  if (f == 0x01 || f == 0x02) {
    if constexpr (serves(0x01) || serves(0x02)) {
      const std::size_t n = (q.quantity + 7U) / 8U;
      for (std::size_t i = 0; i < n; ++i) {
        pdu_out[2U + i] = 0;
      }
      code = dev.read_bits(f, q.address, q.quantity, pdu_out.subspan(2, n));
      if (code == 0U) {
        const std::size_t size =
            encode_read_bits_response(f, q.quantity, pdu_out.subspan(2, n), pdu_out).value_or(0);
        return size;
      }
    }
  } else if (f == 0x03 || f == 0x04) {
    if constexpr (serves(0x03) || serves(0x04)) {
      code = read_registers_into(dev, f, q.address, q.quantity, pdu_out);
      if (code == 0U) {
        return 2U + 2U * q.quantity;
      }
    }
  } else if (f == 0x05 || f == 0x0F) {
    if constexpr (serves(0x05) || serves(0x0F)) {
      const std::uint8_t one[1] = {static_cast<std::uint8_t>(q.value == coil_on ? 1U : 0U)};
      code = f == 0x05 ? dev.write_coils(q.address, 1, byte_view(one, 1))
                       : dev.write_coils(q.address, q.quantity, q.data);
      if (code == 0U) {
        return encode_write_response(q, pdu_out).value_or(0);
      }
    }
  } else if (f == 0x06 || f == 0x10) {
    if constexpr (serves(0x06) || serves(0x10)) {
      const std::uint8_t single[2] = {static_cast<std::uint8_t>(q.value >> 8U),
                                      static_cast<std::uint8_t>(q.value & 0xFFU)};
      code = write_registers_from(dev, q.address, f == 0x06 ? byte_view(single, 2) : q.data);
      if (code == 0U) {
        return encode_write_response(q, pdu_out).value_or(0);
      }
    }
  } else if (f == 0x16) {
    if constexpr (serves(0x16)) {
      // the register is read into the response area, which the echo then overwrites
      code = read_registers_into(dev, 0x03, q.address, 1, pdu_out);
      if (code == 0U) {
        const std::uint16_t now = register_at(pdu_out.subspan(2, 2), 0);
        const auto v = static_cast<std::uint16_t>(
            (now & q.and_mask) | (q.or_mask & static_cast<std::uint16_t>(~q.and_mask)));
        const std::uint8_t bytes[2] = {static_cast<std::uint8_t>(v >> 8U),
                                       static_cast<std::uint8_t>(v & 0xFFU)};
        code = write_registers_from(dev, q.address, byte_view(bytes, 2));
      }
      if (code == 0U) {
        return encode_write_response(q, pdu_out).value_or(0);
      }
    }
  } else if (f == 0x17) {
    if constexpr (serves(0x17)) {
      // Modbus App. Protocol §6.17: both ranges are checked (02) before anything is done, then
      // the write, then the read. The read range is checked by check_registers, else by reading
      // it (reads have no side effects: the contract above); the write accessor checks its own
      // range before writing.
      if constexpr (has_check_registers<Device>::value) {
        code = std::as_const(dev).check_registers(0x03, q.address, q.quantity);
        if (code == 0U) {
          code = std::as_const(dev).check_registers(0x10, q.write_address, q.write_quantity);
        }
      } else {
        code = read_registers_into(dev, 0x03, q.address, q.quantity, pdu_out);
      }
      if (code == 0U) {
        code = write_registers_from(dev, q.write_address, q.data);
        // a read that fails after the write is a processing failure (§6.17: 04), code 0 below
        if (code == 0U && read_registers_into(dev, 0x03, q.address, q.quantity, pdu_out) == 0U) {
          pdu_out[0] = f;
          return 2U + 2U * q.quantity;
        }
      }
    }
    // coverage-branch: the dispatch's last tests: serve_pdu gets only the functions served
  } else if (f == 0x14 || f == 0x15) {
    if constexpr (serves(0x14) || serves(0x15)) {
      return serve_file_records(dev, f, q.data, pdu_out);  // raw in q: decoded there
    }
    // coverage-branch: the dispatch's last test: no function served is left past FC11
  } else if (f == 0x11) {
    if constexpr (serves(0x11)) {
      std::size_t size = 0;
      code = dev.report_server_id(pdu_out.subspan(1, max_pdu_size - 1U), size);
      if (code == 0U && size < max_pdu_size) {  // no wrap-around of a huge size: 04
        pdu_out[0] = f;
        return size + 1U;
      }
    }
  }
  return exception(code == 0U ? static_cast<std::uint8_t>(exception_code::server_device_failure)
                              : code);
}

}  // namespace detail

/// Serves one request PDU (function code and data: no address, no CRC), for transports that
/// carry none (Modbus TCP: the pdu of decode_tcp; a gateway's own device). Writes the response
/// PDU to `response_pdu` (which must hold 253 bytes and must not overlap the request) and
/// returns its size: the normal response or an exception (2 bytes), as serve_frame checks and
/// dispatches. 0 for an empty request (no function code to answer).
/// errc::buffer_too_small when `response_pdu` is shorter than 253.
template <class Device>
constexpr result<std::size_t> serve_pdu(Device& dev, byte_view request_pdu,
                                        mutable_byte_view response_pdu) noexcept {
  if (response_pdu.size() < max_pdu_size) {
    return errc::buffer_too_small;
  }
  if (request_pdu.empty()) {
    return std::size_t{0};
  }
  static_assert(detail::device_checks<Device>::value, "modbus server device");
  const std::uint8_t f = request_pdu[0];
  std::uint8_t code = 0;
  if constexpr (detail::has_admit<Device>::value) {
    code = std::as_const(dev).admit(request_pdu);  // the const check, whatever D overloads
  }
  constexpr function_set served = served_functions<Device>();
  if (code == 0U && !in_function_set<served>(f)) {
    code = detail::illegal_function_code;
  }
  if (code == 0U) {
    const decode_result<request> q = decode_request<served>(request_pdu);
    if (q.is_complete()) {
      return detail::serve_pdu(dev, q.value(), response_pdu);
    }
    code = static_cast<std::uint8_t>(exception_for(q.error()));
  }
  return encode_exception(f, code, response_pdu);
}

namespace detail {

// The RTU response to `frame` from `unit` by `dev` (nullptr: none), written to `out` (>= 256
// bytes): serve_pdu, then the address and the CRC. 0: nothing to send (a broadcast, executed).
template <crc_table_size Table, class Device>
constexpr std::size_t serve_rtu_frame(Device* dev, std::uint8_t unit, const rtu_frame& frame,
                                      mutable_byte_view out) noexcept {
  if (dev == nullptr || frame.pdu.empty()) {
    return 0;
  }
  // n is 2 at least (a PDU of one byte, room for max_pdu_size); its test of 0 stays, as
  // without it the compiler gives serve_frame a larger stack frame (the meter's serve.fc03_10)
  const std::size_t n =
      modbus::serve_pdu(*dev, frame.pdu, out.subspan(1, max_pdu_size)).value_or(0);
  // coverage-branch: n == 0 never holds (n is 2 at least, above): the test kept for the stack
  if (frame.broadcast() || n == 0U) {
    return 0;
  }
  out[0] = unit;
  const std::uint16_t c = crc16_modbus<Table>::compute(byte_view(out.data(), n + 1U));
  store_le16(out, n + 1U, c);
  return n + 3U;
}

}  // namespace detail

/// Serves one RTU request frame already checked by the framer or decode_rtu (no second CRC
/// pass) for a server at `own_address` (1..247). Returns the size of the response ADU written
/// to `out` (which must hold 256 bytes and must not overlap the request), or 0 when nothing is
/// to be sent: another address, or a broadcast (executed all the same).
/// errc::buffer_too_small when `out` is shorter than 256.
template <crc_table_size Table = default_crc_table, class Device>
constexpr result<std::size_t> serve_frame(Device& dev, std::uint8_t own_address,
                                          const rtu_frame& frame, mutable_byte_view out) noexcept {
  if (out.size() < max_rtu_size) {
    return errc::buffer_too_small;
  }
  const bool ours = frame.slave == own_address || frame.broadcast();
  return detail::serve_rtu_frame<Table>(ours ? &dev : nullptr, own_address, frame, out);
}

/// Several slaves on one port: serves `frame` (checked by the framer, e.g. one built with
/// framer_options::last_address) by the device `unit_device(frame.slave)` returns, a pointer
/// (nullptr: no device for that unit, no response, as for another address). The device
/// answers as that unit (the response carries its address); a server image answers units 1-4
/// as four devices with `[&](std::uint8_t u) { return u - 1U < 4U ? &dev[u - 1U] : nullptr; }`,
/// or as one device that keeps the unit the lookup was asked for. A broadcast asks for unit 0:
/// the device returned executes it (nullptr: none), and nothing is sent. Returns as serve_frame.
template <crc_table_size Table = default_crc_table, class UnitDevice>
constexpr result<std::size_t> serve_units(UnitDevice&& unit_device, const rtu_frame& frame,
                                          mutable_byte_view out) noexcept {
  if (out.size() < max_rtu_size) {
    return errc::buffer_too_small;
  }
  return detail::serve_rtu_frame<Table>(unit_device(frame.slave), frame.slave, frame, out);
}

/// Serves one RTU request ADU (the bytes of one frame): decode_rtu, then serve_frame. Returns
/// 0 as well for a bad CRC or length (no response to a corrupted frame).
template <crc_table_size Table = default_crc_table, class Device>
constexpr result<std::size_t> serve_rtu(Device& dev, std::uint8_t own_address, byte_view adu,
                                        mutable_byte_view out) noexcept {
  if (out.size() < max_rtu_size) {
    return errc::buffer_too_small;
  }
  const decode_result<rtu_frame> f = decode_rtu<Table>(adu);
  if (!f.is_complete()) {
    return std::size_t{0};  // no response to a corrupted frame
  }
  return serve_frame<Table>(dev, own_address, f.value(), out);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_SERVER_HPP
