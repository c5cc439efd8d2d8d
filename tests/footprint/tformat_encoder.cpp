// Footprint probe: T-format encoder side (request decoder, response encoder). Inputs arrive as
// parameters of the entry function (no globals), so nothing folds away; the link keeps only what
// the entry reaches (--gc-sections).

#include <motionbus/tformat/codec.hpp>

namespace mb = motionbus;
namespace tf = motionbus::tformat;

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n, unsigned char* out) {
  const auto q = tf::decode_request(mb::byte_view(in, n));
  if (!q.is_complete()) {
    return static_cast<unsigned>(q.error());
  }
  tf::response r;
  r.id = q->id;
  r.cf = q->cf;
  r.abs = static_cast<std::uint32_t>(in[1]) << 8U;
  r.address = q->address;
  r.edf = q->edf;
  const auto w = tf::encode_response(r, mb::mutable_byte_view(out, tf::max_response_size));
  return w.ok() ? *w : 0U;
}
