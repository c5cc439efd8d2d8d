// Modbus request decoder (server side). Oracles: never out of bounds; a complete request
// re-encodes with the client encoders to exactly the input bytes; a rejected one maps to an
// exception code 01, 02 or 03.
#include <motionbus/modbus/pdu_client.hpp>
#include <motionbus/modbus/pdu_server.hpp>

#include <cstring>
#include <vector>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const mb::byte_view pdu(data, size);
  const auto d = mo::decode_request(pdu);
  if (d.is_failed()) {
    const auto code = static_cast<unsigned>(mo::exception_for(d.error()));
    MOTIONBUS_FUZZ_CHECK(code >= 1 && code <= 3);
    MOTIONBUS_FUZZ_CHECK(d.consumed() == size);
    return 0;
  }
  MOTIONBUS_FUZZ_CHECK(d.is_complete() && d.consumed() == size);
  const mo::request& q = d.value();
  std::uint8_t out[mo::max_pdu_size] = {};
  mb::result<std::size_t> n = mb::errc::invalid_argument;
  std::vector<std::uint16_t> regs;
  for (std::size_t i = 0; i + 1 < q.data.size(); i += 2) {
    regs.push_back(mo::register_at(q.data, i / 2));
  }
  const mb::span<const std::uint16_t> values(regs.data(), regs.size());
  switch (q.function) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04: n = mo::encode_read(q.function, q.address, q.quantity, out); break;
    case 0x05: n = mo::encode_write_single_coil(q.address, q.value == mo::coil_on, out); break;
    case 0x06: n = mo::encode_write_single_register(q.address, q.value, out); break;
    case 0x0F: n = mo::encode_write_multiple_coils(q.address, q.quantity, q.data, out); break;
    case 0x10: n = mo::encode_write_multiple_registers(q.address, values, out); break;
    case 0x16: n = mo::encode_mask_write_register(q.address, q.and_mask, q.or_mask, out); break;
    case 0x17:
      n = mo::encode_read_write_multiple_registers(q.address, q.quantity, q.write_address, values,
                                                   out);
      break;
    case 0x08: n = mo::encode_diagnostics(q.sub_function, q.data, out); break;
    case 0x18: n = mo::encode_read_fifo_queue(q.address, out); break;
    case 0x2B:
      if (q.mei_type == mo::mei_read_device_identification) {
        n = mo::encode_read_device_identification(q.read_code, q.object_id, out);
      } else {
        std::uint8_t mei_data[mo::max_pdu_size] = {q.mei_type};
        std::memcpy(mei_data + 1, q.data.data(), q.data.size());
        n = mo::encode_raw(q.function, mb::byte_view(mei_data, q.data.size() + 1U), out);
      }
      break;
    default: n = mo::encode_raw(q.function, q.data, out); break;
  }
  MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == size);
  // FC0F: the encoder clears unused high bits of the last byte; the decoder accepts them set.
  const std::size_t compare = q.function == 0x0F ? size - 1 : size;
  MOTIONBUS_FUZZ_CHECK(std::memcmp(out, data, compare) == 0);
  return 0;
}
