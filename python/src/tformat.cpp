// motionbus Python binding — motionbus.tformat: the T-format byte codec (both sides), the
// master's stream receiver (fed chunks or single bytes, as a sigrok decoder or a UART loop
// does).
#include <string>

#include "common.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/frame.hpp"
#include "motionbus/tformat/line.hpp"
#include "motionbus/tformat/listener.hpp"
#include "motionbus/tformat/receiver.hpp"

namespace mbpy {

namespace tf = motionbus::tformat;

namespace {

tf::decode_options options(unsigned single_turn_bits, unsigned multi_turn_bits,
                           bool check_unused_bits, bool resolution_from_enid) {
  if (single_turn_bits < 1U || single_turn_bits > 24U || multi_turn_bits < 1U ||
      multi_turn_bits > 24U) {
    throw py::value_error("single_turn_bits and multi_turn_bits must be 1..24");
  }
  tf::decode_options o;
  o.res.single_turn_bits = static_cast<std::uint8_t>(single_turn_bits);
  o.res.multi_turn_bits = static_cast<std::uint8_t>(multi_turn_bits);
  o.check_unused_bits = check_unused_bits;
  o.resolution_from_enid = resolution_from_enid;
  return o;
}

tf::data_id data_id_arg(const py::handle& v) {
  const auto code = as<std::uint8_t>(v, "id");
  if (code > 0x0FU) {
    throw py::value_error("id must be a 4-bit Data ID code (0..15)");
  }
  return static_cast<tf::data_id>(code);
}

py::object response_or_error(const motionbus::decode_result<tf::response>& r, const char* what) {
  if (r.is_complete()) {
    return py::cast(r.value());
  }
  return error_of(r, what);
}

// The receiver with the request frame it checks against kept as bytes.
struct receiver_box {
  tf::receiver rx;
  explicit receiver_box(const tf::receiver_options& o) : rx(o) {}
  py::list feed(byte_view in) {
    py::list events;
    (void)motionbus::feed_all(rx, in, [&](const auto& r) {
      events.append(response_or_error(r, "tformat.Receiver"));
      return true;
    });
    return events;
  }
};

// A frame the listener heard, its bytes copied out of the listener.
struct heard_box {
  bool is_response = false;
  std::string bytes;
  tf::request req{};
  errc request_error = errc::ok;
  tf::response resp{};
  bool id3_reply = false;
};

struct listener_box {
  tf::line_listener ls;
  explicit listener_box(const tf::listener_options& o) : ls(o) {}
  static py::object event(const motionbus::decode_result<tf::heard>& r) {
    if (!r.is_complete()) {
      return error_of(r, "tformat.Listener");
    }
    heard_box h;
    const tf::heard& v = r.value();
    h.is_response = v.is_response;
    h.bytes.assign(reinterpret_cast<const char*>(v.bytes.data()), v.bytes.size());
    h.req = v.req;
    h.request_error = v.request_error;
    h.resp = v.resp;
    h.id3_reply = v.id3_reply;
    return py::cast(std::move(h));
  }
};

// A frame found in line samples: the decoded frame, its start bit, the bit after it.
struct line_box {
  py::object frame;
  std::size_t start_bit = 0;
  std::size_t end = 0;
};

template <class T>
line_box line_of(const motionbus::decode_result<tf::line_frame<T>, motionbus::input_unit::bits>& r,
                 const char* what) {
  check(r, what);
  return line_box{py::cast(r.value().frame), r.value().start_bit, r.consumed_bits()};
}

}  // namespace

void bind_tformat(py::module_& root) {
  py::module_ m = root.def_submodule("tformat", "T-format (Tamagawa Smart-Abs) codec.");
  add_enum("DataId", {{"read_abs", 0x0},
                      {"read_abm", 0x1},
                      {"read_enid", 0x2},
                      {"read_all", 0x3},
                      {"eeprom_write", 0x6},
                      {"reset_errors", 0x7},
                      {"reset_single_turn", 0x8},
                      {"reset_multi_turn", 0xC},
                      {"eeprom_read", 0xD}});
  add_enum("AlmcBit", {{"os", 0x01},
                       {"fs", 0x02},
                       {"ce", 0x04},
                       {"of", 0x08},
                       {"oh", 0x10},
                       {"me", 0x20},
                       {"be", 0x40},
                       {"ba", 0x80}});
  add_enum("Echo", {{"none", 0}, {"expected", 1}});
  m.attr("MAX_REQUEST_SIZE") = tf::max_request_size;
  m.attr("MAX_RESPONSE_SIZE") = tf::max_response_size;

  py::class_<tf::request> req(m, "Request", "A request as the encoder decoded it.");
  req.def(py::init<>())
      .def_property_readonly(
          "id", [](const tf::request& q) { return enum_value("DataId", static_cast<int>(q.id)); })
      .def_readonly("cf", &tf::request::cf)
      .def_readonly("address", &tf::request::address, "EEPROM address (ID6, IDD).")
      .def_readonly("edf", &tf::request::edf, "Data to write (ID6).")
      .def_readonly("crc", &tf::request::crc, "The CRC received (ID6, IDD).")
      .def_property_readonly("size", [](const tf::request& q) { return tf::request_size(q.id); });
  add_repr(req, {"id", "cf", "address", "edf", "crc"});

  py::class_<tf::response> rsp(
      m, "Response",
      "A T-format response: the fields its Data ID's layout carries (others 0). Build one "
      "with keywords to encode it.");
  rsp.def(py::init([](const py::handle& id, const py::handle& sf, const py::handle& abs,
                      const py::handle& abm, const py::handle& enid, const py::handle& almc,
                      const py::handle& address, bool busy, const py::handle& edf) {
            tf::response r;
            r.id = data_id_arg(id);
            r.cf = tf::control_field(r.id);
            r.sf = as<std::uint8_t>(sf, "sf");
            r.abs = as<std::uint32_t>(abs, "abs");
            r.abm = as<std::uint32_t>(abm, "abm");
            r.enid = as<std::uint8_t>(enid, "enid");
            r.almc = as<std::uint8_t>(almc, "almc");
            r.address = as<std::uint8_t>(address, "address");
            r.busy = busy;
            r.edf = as<std::uint8_t>(edf, "edf");
            return r;
          }),
          py::arg("id") = 0, py::kw_only(), py::arg("sf") = 0, py::arg("abs") = 0,
          py::arg("abm") = 0, py::arg("enid") = 0, py::arg("almc") = 0, py::arg("address") = 0,
          py::arg("busy") = false, py::arg("edf") = 0)
      .def_property_readonly(
          "id", [](const tf::response& r) { return enum_value("DataId", static_cast<int>(r.id)); })
      .def_readonly("cf", &tf::response::cf)
      .def_readonly("sf", &tf::response::sf, "Status field (absent, 0, for ID6/IDD).")
      .def_readonly("abs", &tf::response::abs, "Single-turn position.")
      .def_readonly("abm", &tf::response::abm, "Multi-turn count.")
      .def_readonly("enid", &tf::response::enid, "Encoder ID.")
      .def_readonly("almc", &tf::response::almc, "Alarm bits (AlmcBit).")
      .def_readonly("address", &tf::response::address, "EEPROM address (ID6/IDD).")
      .def_readonly("busy", &tf::response::busy, "EEPROM busy (ID6/IDD): EDF is then 0.")
      .def_readonly("edf", &tf::response::edf, "EEPROM data (ID6/IDD).")
      .def_readonly("crc", &tf::response::crc, "The CRC as received.")
      .def_property_readonly("ea0", &tf::response::ea0, "SF counting error.")
      .def_property_readonly("ea1", &tf::response::ea1, "SF OR of OH, ME, BE, BA.")
      .def_property_readonly("ca0", &tf::response::ca0,
                             "SF: the encoder saw a request parity error.")
      .def_property_readonly("ca1", &tf::response::ca1,
                             "SF: the encoder saw a request delimiter error.")
      .def_property_readonly(
          "size", [](const tf::response& r) { return r.layout().size; },
          "Bytes of the frame (CF to CRC).")
      .def_property_readonly(
          "alarms",
          [](const tf::response& r) {
            py::list out;
            for (const tf::almc_bit a : tf::all_alarms) {
              if (tf::has_alarm(r.almc, a)) {
                out.append(enum_value("AlmcBit", static_cast<int>(a)));
              }
            }
            return out;
          },
          "The ALMC alarms set, as AlmcBit members.");
  add_repr(rsp, {"id", "cf", "sf", "abs", "abm", "enid", "almc", "address", "busy", "edf", "crc"});

  m.def(
      "control_field", [](const py::handle& id) { return tf::control_field(data_id_arg(id)); },
      py::arg("id"), "The CF byte of a Data ID (sync code, code bits, parity).");
  m.def(
      "request_size", [](const py::handle& id) { return tf::request_size(data_id_arg(id)); },
      py::arg("id"), "Bytes of the request for `id` (1, 3 or 4).");
  m.def(
      "response_size", [](const py::handle& id) { return tf::layout_of(data_id_arg(id)).size; },
      py::arg("id"), "Bytes of the response to `id` (4, 6 or 11).");
  m.def("status_field", &tf::status_field, py::arg("almc"), py::arg("ca0") = false,
        py::arg("ca1") = false, "The SF an encoder reports for alarm bits `almc`.");
  m.def("absolute_position", &tf::absolute_position, py::arg("abs"), py::arg("abm"),
        py::arg("single_turn_bits") = 17, "Turns above the single-turn bits.");
  m.def(
      "resolution_for_enid",
      [](std::uint8_t enid) -> py::object {
        const tf::resolution none{0, 0};
        const tf::resolution r = tf::resolution_for_enid(enid, none);
        if (r.single_turn_bits == 0U) {
          return py::none();
        }
        return py::make_tuple(r.single_turn_bits, r.multi_turn_bits);
      },
      py::arg("enid"),
      "(single_turn_bits, multi_turn_bits) a known ENID announces (0x11, 0x17, 0x0B), else None.");

  m.def(
      "encode_request",
      [](const py::handle& id, const py::handle& address, const py::handle& data) {
        const tf::data_id d = data_id_arg(id);
        const auto a = as<std::uint8_t>(address, "address");
        const auto e = as<std::uint8_t>(data, "data");
        return encode_into<tf::max_request_size>(
            "tformat.encode_request",
            [&](mutable_byte_view out) { return tf::encode_request(d, a, e, out); });
      },
      py::arg("id"), py::arg("address") = 0, py::arg("data") = 0,
      "The request frame for Data ID `id`: CF, or CF ADF [EDF] CRC for the EEPROM IDs "
      "(address 0..127).");
  m.def(
      "decode_response",
      [](const py::handle& data, unsigned st, unsigned mt, bool check_unused, bool from_enid,
         bool exact) {
        const bytes_arg in(data);
        const tf::decode_options o = options(st, mt, check_unused, from_enid);
        const auto r =
            exact ? tf::decode_response_frame(in.view(), o) : tf::decode_response(in.view(), o);
        check(r, "tformat.decode_response");
        return r.value();
      },
      py::arg("data"), py::kw_only(), py::arg("single_turn_bits") = 17,
      py::arg("multi_turn_bits") = 16, py::arg("check_unused_bits") = true,
      py::arg("resolution_from_enid") = false, py::arg("exact") = false,
      "Decodes the response at the start of `data` (its CF picks the layout; extra bytes are "
      "left: Response.size says how many were used). exact=True: `data` must be exactly one "
      "frame. Raises DecodeError (IncompleteError when `data` is short).");
  m.def(
      "decode_response_for",
      [](const py::handle& request, const py::handle& data, unsigned st, unsigned mt,
         bool check_unused, bool from_enid) {
        const bytes_arg q(request, "request");
        const bytes_arg in(data);
        const auto r =
            tf::decode_response_for(q.view(), in.view(), options(st, mt, check_unused, from_enid));
        check(r, "tformat.decode_response_for");
        return r.value();
      },
      py::arg("request"), py::arg("data"), py::kw_only(), py::arg("single_turn_bits") = 17,
      py::arg("multi_turn_bits") = 16, py::arg("check_unused_bits") = true,
      py::arg("resolution_from_enid") = false,
      "decode_response checked against the request frame that was sent (CF, EEPROM address "
      "and data echo, ca0/ca1: communication_alarm).");
  m.def(
      "decode_request",
      [](const py::handle& data) {
        const bytes_arg in(data);
        const auto r = tf::decode_request(in.view());
        check(r, "tformat.decode_request");
        return r.value();
      },
      py::arg("data"), "Decodes a request as an encoder receives it.");
  m.def(
      "encode_response",
      [](const tf::response& r) {
        return encode_into<tf::max_response_size>(
            "tformat.encode_response",
            [&](mutable_byte_view out) { return tf::encode_response(r, out); });
      },
      py::arg("response"),
      "The response frame for `response`'s id and fields (CF and CRC computed).");

  py::class_<receiver_box>(m, "Receiver",
                           "The master's stream receiver: feed it the bytes the UART delivers "
                           "(chunks, or one byte at a time with put); it frames, decodes and "
                           "checks each response against the last request given to sent().")
      .def(py::init([](const py::handle& echo, bool check_against_request, unsigned st, unsigned mt,
                       bool check_unused, bool from_enid) {
             tf::receiver_options o;
             const auto e = as<std::uint8_t>(echo, "echo");
             if (e > 1U) {
               throw py::value_error("echo must be Echo.none or Echo.expected");
             }
             o.echo_mode = static_cast<tf::echo>(e);
             o.check_against_request = check_against_request;
             o.decode = options(st, mt, check_unused, from_enid);
             return new receiver_box(
                 o);  // NOLINT(cppcoreguidelines-owning-memory): pybind11 owns it
           }),
           py::arg("echo") = 0, py::kw_only(), py::arg("check_against_request") = true,
           py::arg("single_turn_bits") = 17, py::arg("multi_turn_bits") = 16,
           py::arg("check_unused_bits") = true, py::arg("resolution_from_enid") = false)
      .def(
          "sent",
          [](receiver_box& b, const py::handle& request) {
            const bytes_arg q(request, "request");
            b.rx.sent(q.view());
          },
          py::arg("request"),
          "Records the request frame just sent (its echo is skipped; responses are checked against "
          "it).")
      .def(
          "feed",
          [](receiver_box& b, const py::handle& data) {
            const bytes_arg in(data);
            return b.feed(in.view());
          },
          py::arg("data"),
          "Takes bytes; returns the events they complete, in order: Response objects and "
          "DecodeError objects (not raised: a rejected frame, after which the stream goes on).")
      .def(
          "put",
          [](receiver_box& b, int byte) {
            if (byte < 0 || byte > 255) {
              throw py::value_error("byte must be 0..255");
            }
            py::list events;
            motionbus::put_each(b.rx, static_cast<std::uint8_t>(byte), [&](const auto& r) {
              events.append(response_or_error(r, "tformat.Receiver"));
              return true;
            });
            return events;
          },
          py::arg("byte"),
          "The per-byte step: returns the events this byte completes (usually none).")
      .def(
          "idle",
          [](receiver_box& b) -> py::object {
            const auto r = b.rx.idle();
            if (r.is_incomplete()) {
              return py::none();
            }
            return error_of(r, "tformat.Receiver.idle");
          },
          "The line went idle: drops a partial frame and returns its DecodeError (truncated), or "
          "None.")
      .def_property_readonly("dropped", [](const receiver_box& b) { return b.rx.dropped(); })
      .def_property_readonly("echoes_skipped",
                             [](const receiver_box& b) { return b.rx.echoes_skipped(); })
      .def_property_readonly("echo_missed",
                             [](const receiver_box& b) { return b.rx.echo_missed(); })
      .def_property_readonly("pending", [](const receiver_box& b) { return b.rx.pending(); });

  py::class_<heard_box> heard(m, "Heard",
                              "A frame the Listener heard: a request (is_response False) or a "
                              "response paired with the request before it.");
  heard.def_readonly("is_response", &heard_box::is_response)
      .def_property_readonly("bytes", [](const heard_box& h) { return py::bytes(h.bytes); })
      .def_property_readonly(
          "request",
          [](const heard_box& h) -> py::object {
            if (h.is_response) {
              return py::none();
            }
            return py::cast(h.req);
          },
          "The request's fields (id and cf always), or None for a response.")
      .def_property_readonly(
          "request_error",
          [](const heard_box& h) -> py::object {
            if (h.is_response || h.request_error == errc::ok) {
              return py::none();
            }
            return py::reinterpret_borrow<py::object>(lookup("motionbus._enums", "Errc"))(
                static_cast<int>(h.request_error));
          },
          "Why the encoder answers this request with ID3 data (Errc), else None.")
      .def_property_readonly("response",
                             [](const heard_box& h) -> py::object {
                               if (!h.is_response) {
                                 return py::none();
                               }
                               return py::cast(h.resp);
                             })
      .def_readonly("id3_reply", &heard_box::id3_reply,
                    "The response is ID3 data answering a request that is not ID3 (abnormal).");
  add_repr(heard, {"is_response", "bytes", "request", "request_error", "response", "id3_reply"});

  py::class_<listener_box>(m, "Listener",
                           "Both directions of a tapped half-duplex line (a bus monitor, a "
                           "capture decoder): requests and responses framed and paired. Feed "
                           "it bytes (feed, or put one at a time); idle() at a silence.")
      .def(py::init([](unsigned st, unsigned mt, bool check_unused, bool from_enid) {
             tf::listener_options o;
             o.decode = options(st, mt, check_unused, from_enid);
             return new listener_box(o);  // NOLINT(cppcoreguidelines-owning-memory)
           }),
           py::kw_only(), py::arg("single_turn_bits") = 17, py::arg("multi_turn_bits") = 16,
           py::arg("check_unused_bits") = true, py::arg("resolution_from_enid") = false)
      .def(
          "feed",
          [](listener_box& b, const py::handle& data) {
            const bytes_arg in(data);
            py::list events;
            (void)motionbus::feed_all(b.ls, in.view(), [&](const auto& r) {
              events.append(listener_box::event(r));
              return true;
            });
            return events;
          },
          py::arg("data"),
          "Takes bytes; returns the events: Heard objects and DecodeError objects.")
      .def(
          "put",
          [](listener_box& b, int byte) {
            if (byte < 0 || byte > 255) {
              throw py::value_error("byte must be 0..255");
            }
            py::list events;
            motionbus::put_each(b.ls, static_cast<std::uint8_t>(byte), [&](const auto& r) {
              events.append(listener_box::event(r));
              return true;
            });
            return events;
          },
          py::arg("byte"), "The per-byte step: the events this byte completes.")
      .def(
          "idle",
          [](listener_box& b) {
            py::list events;
            for (;;) {  // one result a call, each dropping what it settles
              const auto r = b.ls.idle();
              if (r.is_incomplete()) {
                return events;
              }
              events.append(listener_box::event(r));
            }
          },
          "The line went idle: the events the bytes held settle in (frames, cut-short frames).")
      .def_property_readonly("dropped", [](const listener_box& b) { return b.ls.dropped(); })
      .def_property_readonly("pending", [](const listener_box& b) { return b.ls.pending(); })
      .def_property_readonly("expecting_response",
                             [](const listener_box& b) { return b.ls.expecting_response(); });

  // --- the line: 10 samples a field (start 0, b0..b7, delimiter 1), for captures of SD/RD ---
  py::class_<line_box> line(m, "LineFrame", "A frame found in line samples.");
  line.def_readonly("frame", &line_box::frame, "The Response or Request decoded.")
      .def_readonly("start_bit", &line_box::start_bit, "Index of its first start bit.")
      .def_readonly("end", &line_box::end, "Index just past its last delimiter.");
  add_repr(line, {"frame", "start_bit", "end"});
  m.def(
      "encode_line",
      [](const py::handle& frame, std::size_t idle_bits) {
        const bytes_arg in(frame, "frame");
        if (idle_bits > (1U << 20U) || in.view().size() > 4096U) {
          throw py::value_error("idle_bits must be at most 2**20 and frame at most 4096 bytes");
        }
        const std::size_t n = idle_bits + in.view().size() * tf::field_bits;
        std::vector<std::uint8_t> out(n / 8U + 1U, 0);
        const auto r =
            tf::encode_line(in.view(), motionbus::span<std::uint8_t>(out.data(), out.size()),
                            motionbus::bit_order::msb_first, 0, idle_bits);
        return unpack_samples(out.data(), value_or_raise(r, "tformat.encode_line"));
      },
      py::arg("frame"), py::arg("idle_bits") = 0,
      "The line samples (0/1) of a frame's bytes, after `idle_bits` idle 1s.");
  m.def(
      "decode_response_line",
      [](const py::handle& bits, std::size_t from_bit, unsigned st, unsigned mt, bool check_unused,
         bool from_enid) {
        const std::vector<std::uint8_t> packed = pack_samples(bits);
        const auto r = tf::decode_response_line(
            motionbus::span<const std::uint8_t>(packed.data(), packed.size()),
            motionbus::bit_order::msb_first, static_cast<std::size_t>(py::len(bits)), from_bit,
            options(st, mt, check_unused, from_enid));
        return line_of(r, "tformat.decode_response_line");
      },
      py::arg("bits"), py::arg("from_bit") = 0, py::kw_only(), py::arg("single_turn_bits") = 17,
      py::arg("multi_turn_bits") = 16, py::arg("check_unused_bits") = true,
      py::arg("resolution_from_enid") = false,
      "Finds and decodes the response in line samples from `from_bit` on (start_bit, delimiter "
      "errors as DecodeError, offset in bits).");
  m.def(
      "decode_request_line",
      [](const py::handle& bits, std::size_t from_bit) {
        const std::vector<std::uint8_t> packed = pack_samples(bits);
        const auto r = tf::decode_request_line(
            motionbus::span<const std::uint8_t>(packed.data(), packed.size()),
            motionbus::bit_order::msb_first, static_cast<std::size_t>(py::len(bits)), from_bit);
        return line_of(r, "tformat.decode_request_line");
      },
      py::arg("bits"), py::arg("from_bit") = 0, "Finds and decodes a request in line samples.");
}

}  // namespace mbpy
