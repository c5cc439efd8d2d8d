// The T-format receiver alone in its translation unit (alone_main.cpp says why): the same
// calls as op_tformat_receiver_* in ops.cpp.

#include <motionbus/tformat/receiver.hpp>

#include <cstdint>

namespace mb = motionbus;
namespace tf = motionbus::tformat;

#define METER_OP extern "C" __attribute__((used, noinline))

extern "C" std::uint32_t meter_out[64];

namespace {
tf::receiver rx;
}  // namespace

METER_OP void op_alone_receiver_start(unsigned code) {
  rx = tf::receiver();
  const std::uint8_t request[1] = {tf::control_field(static_cast<std::uint8_t>(code))};
  rx.sent(mb::byte_view(request, 1));
}
METER_OP bool op_alone_receiver_byte(unsigned byte) {
  return rx.put(static_cast<std::uint8_t>(byte));
}
METER_OP void op_alone_report_receiver(unsigned ready) {
  meter_out[0] = 0;
  meter_out[1] = 0;
  if (ready == 0U) {
    return;
  }
  const auto& r = rx.result();
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = r->abs;
    meter_out[3] = r->abm;
    meter_out[4] = r->almc;
    meter_out[5] = r->enid;
  }
}
