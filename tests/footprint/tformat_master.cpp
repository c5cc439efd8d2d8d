// Footprint probe: T-format master (request encoder, response decoder). Inputs arrive as parameters
// of the entry function (no globals), so nothing folds away; the link keeps only what the entry
// reaches (--gc-sections).

#include <motionbus/tformat/codec.hpp>

namespace mb = motionbus;
namespace tf = motionbus::tformat;

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n, unsigned char* out) {
  const auto q = tf::encode_request(static_cast<tf::data_id>(in[0] & 0xFU), in[1], in[2],
                                    mb::mutable_byte_view(out, tf::max_request_size));
  const auto r = tf::decode_response(mb::byte_view(in, n));
  return (q.ok() ? *q : 0U) +
         (r.is_complete() ? r->abs + r->abm + r->almc : static_cast<unsigned>(r.error()));
}
