// Footprint probe: Modbus RTU client (FC03 and FC10 requests, their responses decoded by the
// per-function decoders, as a client that knows what it asked decodes them). Inputs arrive as
// parameters of the entry function (no globals), so nothing folds away; the link keeps only what
// the entry reaches (--gc-sections).

#include <motionbus/modbus/pdu_client.hpp>
#include <motionbus/modbus/rtu.hpp>

namespace mb = motionbus;
namespace md = motionbus::modbus;

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n, unsigned char* out) {
  unsigned char pdu[md::max_pdu_size];
  const std::uint16_t values[2] = {in[0], in[1]};
  const bool read = (in[2] & 1U) != 0U;
  const auto p =
      read ? md::encode_read(md::function_code::read_holding_registers, in[3], in[4],
                             mb::mutable_byte_view(pdu, sizeof pdu))
           : md::encode_write_multiple_registers(in[3], mb::span<const std::uint16_t>(values, 2),
                                                 mb::mutable_byte_view(pdu, sizeof pdu));
  if (!p.ok()) {
    return 0;
  }
  const auto a = md::encode_rtu(in[5], mb::byte_view(pdu, *p), mb::mutable_byte_view(out, 256));
  const auto f = md::decode_rtu(mb::byte_view(in, n));
  if (!a.ok() || !f.is_complete()) {
    return 1;
  }
  const auto r =
      read ? md::decode_read_response(md::function_code::read_holding_registers, in[4], f->pdu)
           : md::decode_write_response(md::function_code::write_multiple_registers, in[3], 2,
                                       f->pdu);
  return r.is_complete() ? static_cast<unsigned>(r->data.size()) + r->quantity
                         : static_cast<unsigned>(r.error());
}
