// motionbus Python binding — motionbus.biss: BiSS-C layouts, the sensor-data frame decoder over
// a capture given as bits, bytes or words, the frame encoder, register access (control master
// and slave over a Python register file) and the electronic data sheet.
#include <string>
#include <vector>

#include "common.hpp"
#include "motionbus/biss/codec.hpp"
#include "motionbus/biss/control.hpp"
#include "motionbus/biss/eds.hpp"
#include "motionbus/biss/frame.hpp"

namespace mbpy {

namespace bs = motionbus::biss;
using motionbus::bit_order;

namespace {

struct frame_box {
  std::size_t line_delay = 0;
  std::size_t start = 0;
  bool cds = false;
  std::vector<bs::slave_data> slaves;
  std::size_t end = 0;
};

std::vector<bs::slave_layout> chain_arg(const py::handle& layout) {
  std::vector<bs::slave_layout> chain;
  if (py::isinstance<bs::slave_layout>(layout)) {
    chain.push_back(layout.cast<bs::slave_layout>());
    return chain;
  }
  if (PySequence_Check(layout.ptr()) == 0) {
    throw py::type_error("layout must be a SlaveLayout or a sequence of them (a chain)");
  }
  for (const py::handle l : py::reinterpret_borrow<py::sequence>(layout)) {
    if (!py::isinstance<bs::slave_layout>(l)) {
      throw py::type_error("a chain must hold SlaveLayout objects");
    }
    chain.push_back(l.cast<bs::slave_layout>());
  }
  return chain;
}

bit_order order_arg(const py::handle& o) {
  const auto v = as<std::uint8_t>(o, "order");
  if (v > 1U) {
    throw py::value_error("order must be BitOrder.msb_first or BitOrder.lsb_first");
  }
  return static_cast<bit_order>(v);
}

template <class Word>
frame_box decode_words(motionbus::span<const Word> words, std::size_t bit_count,
                       const std::vector<bs::slave_layout>& chain, const bs::decode_options& opt,
                       bit_order order, bool single) {
  frame_box f;
  if (single && chain.size() == 1U) {
    const auto r = bs::decode_frame(words, bit_count, chain[0], opt, order);
    check(r, "biss.decode_frame");
    f.line_delay = r.value().line_delay;
    f.start = r.value().start;
    f.cds = r.value().cds;
    f.slaves.push_back(r.value().slaves[0]);
    f.end = r.consumed_bits();
    return f;
  }
  const auto r = bs::decode_frame(
      words, bit_count, motionbus::span<const bs::slave_layout>(chain.data(), chain.size()), opt,
      order);
  check(r, "biss.decode_frame");
  f.line_delay = r.value().line_delay;
  f.start = r.value().start;
  f.cds = r.value().cds;
  f.slaves.assign(r.value().begin(), r.value().end());
  f.end = r.consumed_bits();
  return f;
}

bs::decode_options decode_opts(std::size_t max_line_delay, std::size_t max_ack_bits) {
  bs::decode_options o;
  o.max_line_delay = max_line_delay;
  o.max_ack_bits = max_ack_bits;
  return o;
}

std::size_t count_arg(const py::object& bit_count, std::size_t available) {
  if (bit_count.is_none()) {
    return available;
  }
  return static_cast<std::size_t>(ranged(bit_count, available, "bit_count"));
}

std::vector<bs::slave_values> values_arg(const py::handle& values, std::size_t n) {
  std::vector<bs::slave_values> out;
  if (py::isinstance<bs::slave_values>(values)) {
    out.push_back(values.cast<bs::slave_values>());
  } else if (PySequence_Check(values.ptr()) != 0) {
    for (const py::handle v : py::reinterpret_borrow<py::sequence>(values)) {
      if (!py::isinstance<bs::slave_values>(v)) {
        throw py::type_error("values must be SlaveValues objects");
      }
      out.push_back(v.cast<bs::slave_values>());
    }
  } else {
    throw py::type_error("values must be a SlaveValues or a sequence of them");
  }
  if (out.size() != n) {
    raise_invalid("biss.encode_frame", "one SlaveValues per layout of the chain");
  }
  return out;
}

// The frame's samples, one byte per 8 samples (msb_first or lsb_first), and their count.
std::vector<std::uint8_t> encode_samples(const py::handle& layout, const py::handle& values,
                                         const bs::line_options& line, bit_order order,
                                         std::size_t& bits) {
  const std::vector<bs::slave_layout> chain = chain_arg(layout);
  const std::vector<bs::slave_values> v = values_arg(values, chain.size());
  const motionbus::span<const bs::slave_layout> c(chain.data(), chain.size());
  const std::size_t n = bs::encoded_bits(c, line);
  if (line.line_delay > (1U << 24U) || line.ack_bits > (1U << 24U) ||
      line.timeout_bits > (1U << 24U)) {
    raise_invalid("biss.encode_frame", "line_delay, ack_bits and timeout_bits must be below 2**24");
  }
  std::vector<std::uint8_t> out((n + 7U) / 8U + 1U, 0);
  const auto r =
      bs::encode_frame(c, motionbus::span<const bs::slave_values>(v.data(), v.size()),
                       motionbus::span<std::uint8_t>(out.data(), out.size()), line, order);
  bits = value_or_raise(r, "biss.encode_frame");
  out.resize((bits + 7U) / 8U);
  return out;
}

bs::line_options line_arg(std::size_t line_delay, std::size_t ack_bits, bool cds,
                          std::size_t timeout_bits) {
  bs::line_options l;
  l.line_delay = line_delay;
  l.ack_bits = ack_bits;
  l.cds = cds;
  l.timeout_bits = timeout_bits;
  return l;
}

// The control master with the buffer of its access.
struct master_box {
  bs::control_master master;
  std::vector<std::uint8_t> buffer;
  explicit master_box(const bs::control_options& o) : master(o) {}
};

// A Python register file: readable(a), writable(a), ready(), read(a) -> int, write(a, v); each
// optional (readable/writable/ready default to True, a missing read gives 0). An exception in
// one is kept (the access refused) and raised after the step.
struct py_registers {
  py::object obj;
  mutable py::object pending = py::none();
  explicit py_registers(py::object o) : obj(std::move(o)) {}

  template <class T, class Call>
  T guarded(const char* method, T fallback, Call&& call) const {
    if (!pending.is_none()) {
      return fallback;
    }
    try {
      if (!py::hasattr(obj, method)) {
        return fallback;
      }
      return call(obj.attr(method));
    } catch (py::error_already_set& e) {
      pending = e.value();
    } catch (std::exception& e) {
      pending = py::reinterpret_borrow<py::object>(PyExc_ValueError)(std::string(method) + ": " +
                                                                     e.what());
    }
    return fallback;
  }
  bool readable(std::uint8_t a) const {
    return guarded("readable", pending.is_none(),
                   [&](py::object m) { return py::bool_(m(a)).cast<bool>(); });
  }
  bool writable(std::uint8_t a) const {
    return guarded("writable", pending.is_none(),
                   [&](py::object m) { return py::bool_(m(a)).cast<bool>(); });
  }
  bool ready() const {
    return guarded("ready", true, [&](py::object m) { return py::bool_(m()).cast<bool>(); });
  }
  std::uint8_t read(std::uint8_t a) {
    return guarded("read", std::uint8_t{0},
                   [&](py::object m) { return as<std::uint8_t>(m(a), "read() result"); });
  }
  void write(std::uint8_t a, std::uint8_t v) {
    (void)guarded("write", 0, [&](py::object m) {
      m(a, v);
      return 0;
    });
  }
};

struct slave_box {
  py_registers regs;
  bs::control_slave<py_registers> slave;
  slave_box(py::object o, const bs::control_slave_options& opt)
      : regs(std::move(o)), slave(regs, opt) {}
};

template <class T>
py::bytes bank_of(const T& v, errc (*encode)(const T&, mutable_byte_view), const char* what) {
  std::uint8_t bank[bs::bank_size] = {};
  const errc e = encode(v, mutable_byte_view(bank, sizeof bank));
  if (e != errc::ok) {
    raise_encode(e, what);
  }
  return to_bytes(bank, sizeof bank);
}

}  // namespace

void bind_biss(py::module_& root) {
  py::module_ m = root.def_submodule("biss", "BiSS-C sensor data, register access and EDS.");
  add_enum("BitOrder", {{"msb_first", 0}, {"lsb_first", 1}});
  add_enum("CrcOutput", {{"inverted", 0}, {"plain", 1}});
  add_enum("ControlState", {{"idle", 0}, {"busy", 1}, {"done", 2}, {"failed", 3}});
  add_enum("EncoderType", {{"rotary", 0}, {"linear", 1}});
  m.attr("MAX_CHAIN") = bs::max_chain;
  m.attr("PREAMBLE_FRAMES") = bs::preamble_frames;

  py::class_<bs::crc_format> crc(m, "CrcFormat",
                                 "A slave's CRC: width, poly without its x^width term, start "
                                 "value, inverted on the wire (BiSS default). Width 0: no CRC.");
  crc.def(py::init([](unsigned width, std::uint32_t poly, std::uint32_t start, bool inverted) {
            return bs::crc_format{width, poly, start, inverted};
          }),
          py::arg("width") = 6, py::arg("poly") = 0x03, py::arg("start") = 0,
          py::arg("inverted") = true)
      .def_readwrite("width", &bs::crc_format::width)
      .def_readwrite("poly", &bs::crc_format::poly)
      .def_readwrite("start", &bs::crc_format::start)
      .def_readwrite("inverted", &bs::crc_format::inverted);
  add_repr(crc, {"width", "poly", "start", "inverted"});
  m.def(
      "crc_from_biss_notation",
      [](std::uint32_t poly, std::uint32_t start, int output) {
        return bs::crc_from_biss_notation(poly, start, static_cast<bs::crc_output>(output & 1));
      },
      py::arg("poly"), py::arg("start") = 0, py::arg("output") = 0,
      "A CrcFormat from the BiSS notation, which includes the x^width term (0x43 = x^6 + x + 1).");
  m.def("crc_from_eds", &bs::crc_from_eds, py::arg("cpoly"), py::arg("start") = 0,
        "A CrcFormat from an EDS CPOLY value (bits n:1, x^0 implied).");

  py::class_<bs::slave_layout> layout(m, "SlaveLayout",
                                      "The fields one slave sends (default: AMO ABSYS, 32-bit "
                                      "position, nE, nW, CRC6 0x43 inverted).");
  layout
      .def(py::init([](unsigned mt, unsigned st, unsigned al, bool ne, bool nw,
                       const bs::crc_format& c) {
             bs::slave_layout l;
             l.multi_turn_bits = mt;
             l.single_turn_bits = st;
             l.alignment_bits = al;
             l.has_error = ne;
             l.has_warning = nw;
             l.crc = c;
             return l;
           }),
           py::kw_only(), py::arg("multi_turn_bits") = 0, py::arg("single_turn_bits") = 32,
           py::arg("alignment_bits") = 0, py::arg("has_error") = true,
           py::arg("has_warning") = true, py::arg("crc") = bs::crc6_43)
      .def_readwrite("multi_turn_bits", &bs::slave_layout::multi_turn_bits)
      .def_readwrite("single_turn_bits", &bs::slave_layout::single_turn_bits)
      .def_readwrite("alignment_bits", &bs::slave_layout::alignment_bits)
      .def_readwrite("has_error", &bs::slave_layout::has_error)
      .def_readwrite("has_warning", &bs::slave_layout::has_warning)
      .def_readwrite("crc", &bs::slave_layout::crc)
      .def_property_readonly("data_bits", &bs::slave_layout::data_bits)
      .def_property_readonly("frame_bits", &bs::slave_layout::frame_bits, "Bits after the CDS bit.")
      .def(
          "validate",
          [](const bs::slave_layout& l) {
            const errc e = l.validate();
            if (e != errc::ok) {
              raise_encode(e, "biss.SlaveLayout.validate");
            }
          },
          "Raises EncodeError (invalid_layout) for an inconsistent layout.");
  add_repr(layout, {"multi_turn_bits", "single_turn_bits", "alignment_bits", "has_error",
                    "has_warning", "crc"});
  m.attr("ABSYS_LAYOUT") = bs::absys_layout;

  py::class_<bs::slave_data> data(m, "SlaveData", "One slave's decoded sensor data.");
  data.def_readonly("data", &bs::slave_data::data, "The whole data field as sent.")
      .def_readonly("multi_turn", &bs::slave_data::multi_turn)
      .def_readonly("single_turn", &bs::slave_data::single_turn)
      .def_readonly("ne", &bs::slave_data::ne, "nE line level (False: error active).")
      .def_readonly("nw", &bs::slave_data::nw, "nW line level (False: warning active).")
      .def_readonly("crc", &bs::slave_data::crc, "The CRC as received.")
      .def_readonly("crc_computed", &bs::slave_data::crc_computed, "The CRC the data calls for.")
      .def_property_readonly("crc_ok", &bs::slave_data::crc_ok)
      .def_property_readonly("error", &bs::slave_data::error)
      .def_property_readonly("warning", &bs::slave_data::warning);
  add_repr(data, {"multi_turn", "single_turn", "ne", "nw", "crc"});

  py::class_<frame_box> frame(m, "Frame",
                              "A decoded sensor-data frame (bit indices into the capture).");
  frame
      .def_readonly("line_delay", &frame_box::line_delay,
                    "Idle samples before the Ack (the line delay, in bits).")
      .def_readonly("start", &frame_box::start, "Index of the Start bit.")
      .def_readonly("cds", &frame_box::cds, "The CDS bit.")
      .def_readonly("slaves", &frame_box::slaves, "Each slave's data, chain order.")
      .def_readonly("end", &frame_box::end, "Index just past the last CRC bit.")
      .def_property_readonly("ack_bits", [](const frame_box& f) { return f.start - f.line_delay; });
  add_repr(frame, {"line_delay", "start", "cds", "slaves", "end"});

  py::class_<bs::slave_values> values(m, "SlaveValues", "What a slave reports in one frame.");
  values
      .def(py::init([](std::uint64_t mt, std::uint64_t st, bool ne, bool nw) {
             bs::slave_values v;
             v.multi_turn = mt;
             v.single_turn = st;
             v.ne = ne;
             v.nw = nw;
             return v;
           }),
           py::kw_only(), py::arg("multi_turn") = 0, py::arg("single_turn") = 0,
           py::arg("ne") = true, py::arg("nw") = true)
      .def_readwrite("multi_turn", &bs::slave_values::multi_turn)
      .def_readwrite("single_turn", &bs::slave_values::single_turn)
      .def_readwrite("ne", &bs::slave_values::ne)
      .def_readwrite("nw", &bs::slave_values::nw);
  add_repr(values, {"multi_turn", "single_turn", "ne", "nw"});

  const char* decode_doc_tail =
      " `layout`: a SlaveLayout, or a sequence of them (a chain, slave 1 first). Raises "
      "DecodeError (crc_mismatch with expected/received, no_ack, no_start; offset in bits) or "
      "IncompleteError (the capture ends inside the frame).";
  m.def(
      "decode_frame",
      [](const py::handle& bits, const py::handle& layout, std::size_t mld, std::size_t mab) {
        const std::vector<std::uint8_t> packed = pack_samples(bits);
        const std::size_t count = static_cast<std::size_t>(py::len(bits));
        const auto chain = chain_arg(layout);
        return decode_words(motionbus::span<const std::uint8_t>(packed.data(), packed.size()),
                            count, chain, decode_opts(mld, mab), bit_order::msb_first,
                            py::isinstance<bs::slave_layout>(layout));
      },
      py::arg("bits"), py::arg("layout"), py::kw_only(), py::arg("max_line_delay") = 64,
      py::arg("max_ack_bits") = 256,
      (std::string(
           "Decodes the frame in SL samples `bits` (a sequence of 0/1, from the first clock).") +
       decode_doc_tail)
          .c_str());
  m.def(
      "decode_frame_bytes",
      [](const py::handle& data, const py::handle& layout, const py::object& bit_count,
         const py::handle& order, std::size_t mld, std::size_t mab) {
        const bytes_arg in(data);
        const auto chain = chain_arg(layout);
        return decode_words(in.view(), count_arg(bit_count, in.view().size() * 8U), chain,
                            decode_opts(mld, mab), order_arg(order),
                            py::isinstance<bs::slave_layout>(layout));
      },
      py::arg("data"), py::arg("layout"), py::kw_only(), py::arg("bit_count") = py::none(),
      py::arg("order") = 0, py::arg("max_line_delay") = 64, py::arg("max_ack_bits") = 256,
      (std::string("Decodes the frame in a capture packed 8 samples a byte (`order`: the first "
                   "sample in the MSB or the LSB), the first `bit_count` samples valid.") +
       decode_doc_tail)
          .c_str());
  m.def(
      "decode_frame_words",
      [](const py::handle& words, const py::handle& layout, unsigned word_bits,
         const py::object& bit_count, const py::handle& order, std::size_t mld, std::size_t mab) {
        if (PySequence_Check(words.ptr()) == 0 || PyUnicode_Check(words.ptr()) != 0) {
          throw py::type_error("words must be a sequence of ints");
        }
        if (word_bits != 8U && word_bits != 16U && word_bits != 32U && word_bits != 64U) {
          throw py::value_error("word_bits must be 8, 16, 32 or 64");
        }
        const py::sequence s = py::reinterpret_borrow<py::sequence>(words);
        std::vector<std::uint64_t> w;
        w.reserve(s.size());
        const std::uint64_t hi =
            word_bits == 64U ? ~std::uint64_t{0} : ((std::uint64_t{1} << word_bits) - 1U);
        for (const py::handle x : s) {
          w.push_back(ranged(x, hi, "word"));
        }
        const auto chain = chain_arg(layout);
        const std::size_t n = count_arg(bit_count, w.size() * word_bits);
        const bool single = py::isinstance<bs::slave_layout>(layout);
        const bs::decode_options o = decode_opts(mld, mab);
        const bit_order ord = order_arg(order);
        const auto narrow = [&](auto tag) {
          using W = decltype(tag);
          std::vector<W> v(w.begin(), w.end());
          return decode_words(motionbus::span<const W>(v.data(), v.size()), n, chain, o, ord,
                              single);
        };
        switch (word_bits) {
          case 8: return narrow(std::uint8_t{});
          case 16: return narrow(std::uint16_t{});
          case 32: return narrow(std::uint32_t{});
          default:
            return decode_words(motionbus::span<const std::uint64_t>(w.data(), w.size()), n, chain,
                                o, ord, single);
        }
      },
      py::arg("words"), py::arg("layout"), py::kw_only(), py::arg("word_bits"),
      py::arg("bit_count") = py::none(), py::arg("order") = 0, py::arg("max_line_delay") = 64,
      py::arg("max_ack_bits") = 256,
      (std::string("Decodes the frame in a capture of `word_bits`-bit words (an SPI/DMA capture), "
                   "one sample a bit.") +
       decode_doc_tail)
          .c_str());

  m.def(
      "encoded_bits",
      [](const py::handle& layout, std::size_t line_delay, std::size_t ack_bits,
         std::size_t timeout_bits) {
        const auto chain = chain_arg(layout);
        return bs::encoded_bits(motionbus::span<const bs::slave_layout>(chain.data(), chain.size()),
                                line_arg(line_delay, ack_bits, false, timeout_bits));
      },
      py::arg("layout"), py::kw_only(), py::arg("line_delay") = 0, py::arg("ack_bits") = 1,
      py::arg("timeout_bits") = 0, "Samples encode_frame writes (0 for an invalid layout).");
  m.def(
      "encode_frame",
      [](const py::handle& layout, const py::handle& values, std::size_t line_delay,
         std::size_t ack_bits, bool cds, std::size_t timeout_bits) {
        std::size_t bits = 0;
        const auto bytes =
            encode_samples(layout, values, line_arg(line_delay, ack_bits, cds, timeout_bits),
                           bit_order::msb_first, bits);
        return unpack_samples(bytes.data(), bits);
      },
      py::arg("layout"), py::arg("values"), py::kw_only(), py::arg("line_delay") = 0,
      py::arg("ack_bits") = 1, py::arg("cds") = false, py::arg("timeout_bits") = 0,
      "The SL samples of one frame as a list of 0/1: line delay (1s), Ack, Start, CDS, each "
      "slave's data, nE, nW, CRC, then the timeout (0s). Raises EncodeError.");
  m.def(
      "encode_frame_bytes",
      [](const py::handle& layout, const py::handle& values, std::size_t line_delay,
         std::size_t ack_bits, bool cds, std::size_t timeout_bits, const py::handle& order) {
        std::size_t bits = 0;
        const auto bytes =
            encode_samples(layout, values, line_arg(line_delay, ack_bits, cds, timeout_bits),
                           order_arg(order), bits);
        return py::make_tuple(to_bytes(bytes.data(), bytes.size()), bits);
      },
      py::arg("layout"), py::arg("values"), py::kw_only(), py::arg("line_delay") = 0,
      py::arg("ack_bits") = 1, py::arg("cds") = false, py::arg("timeout_bits") = 0,
      py::arg("order") = 0,
      "encode_frame packed 8 samples a byte: (bytes, sample count); the last byte padded with 0s.");

  // --- register access ----------------------------------------------------------------------
  m.def(
      "header_crc",
      [](const py::handle& id, const py::handle& a, bool cts) {
        return bs::header_crc(as<std::uint8_t>(id, "slave_id"), as<std::uint8_t>(a, "address"),
                              cts);
      },
      py::arg("slave_id"), py::arg("address"), py::arg("cts") = true,
      "CRC4 of a register access header.");
  m.def(
      "data_crc", [](const py::handle& d) { return bs::data_crc(as<std::uint8_t>(d, "data")); },
      py::arg("data"), "CRC4 of a register data byte.");
  m.def(
      "header_bits",
      [](const py::handle& id, const py::handle& a, bool write) {
        return bs::header_bits(as<std::uint8_t>(id, "slave_id"), as<std::uint8_t>(a, "address"),
                               write);
      },
      py::arg("slave_id"), py::arg("address"), py::arg("write"),
      "The 18 CDM bits of an access header, first in bit 17.");

  py::class_<master_box>(m, "ControlMaster",
                         "Register access, master side: start an access, then call step(cds) "
                         "once per frame with the frame's CDS bit; it returns the CDM bit to send.")
      .def(py::init([](std::size_t max_wait_frames) {
             bs::control_options o;
             o.max_wait_frames = max_wait_frames;
             return new master_box(o);  // NOLINT: pybind11 owns it
           }),
           py::kw_only(), py::arg("max_wait_frames") = 4096)
      .def(
          "start_read",
          [](master_box& b, const py::handle& id, const py::handle& a, const py::handle& count) {
            if (b.master.busy()) {
              raise_encode(errc::biss_busy, "biss.ControlMaster.start_read");
            }
            const auto n = ranged(count, 128, "count");
            b.buffer.assign(static_cast<std::size_t>(n), 0);
            const errc e = b.master.start_read(as<std::uint8_t>(id, "slave_id"),
                                               as<std::uint8_t>(a, "address"),
                                               mutable_byte_view(b.buffer.data(), b.buffer.size()));
            if (e != errc::ok) {
              raise_encode(e, "biss.ControlMaster.start_read");
            }
          },
          py::arg("slave_id"), py::arg("address"), py::arg("count") = 1,
          "Starts reading `count` registers from `address`.")
      .def(
          "start_write",
          [](master_box& b, const py::handle& id, const py::handle& a, const py::handle& data) {
            if (b.master.busy()) {
              raise_encode(errc::biss_busy, "biss.ControlMaster.start_write");
            }
            const bytes_arg in(data);
            b.buffer.assign(in.view().begin(), in.view().end());
            const errc e = b.master.start_write(as<std::uint8_t>(id, "slave_id"),
                                                as<std::uint8_t>(a, "address"),
                                                byte_view(b.buffer.data(), b.buffer.size()));
            if (e != errc::ok) {
              raise_encode(e, "biss.ControlMaster.start_write");
            }
          },
          py::arg("slave_id"), py::arg("address"), py::arg("data"),
          "Starts writing bytes `data` from `address`.")
      .def("abort", [](master_box& b) { b.master.abort(); })
      .def(
          "step", [](master_box& b, bool cds) { return b.master.step(cds); }, py::arg("cds"),
          "One frame: the CDS bit read; returns the CDM bit to send with the next frame.")
      .def_property_readonly("state",
                             [](const master_box& b) {
                               return enum_value("ControlState",
                                                 static_cast<int>(b.master.state()));
                             })
      .def_property_readonly("busy", [](const master_box& b) { return b.master.busy(); })
      .def_property_readonly(
          "error",
          [](const master_box& b) -> py::object {
            if (b.master.error() == errc::ok) {
              return py::none();
            }
            return py::reinterpret_borrow<py::object>(lookup("motionbus._enums", "Errc"))(
                static_cast<int>(b.master.error()));
          },
          "The failed access's Errc, else None.")
      .def_property_readonly("transferred",
                             [](const master_box& b) { return b.master.transferred(); })
      .def_property_readonly("frames", [](const master_box& b) { return b.master.frames(); })
      .def_property_readonly(
          "data", [](const master_box& b) { return to_bytes(b.buffer.data(), b.buffer.size()); },
          "The registers read (after a read completes) or the bytes being written.")
      .def_static("frames_for", &bs::control_master::frames_for, py::arg("bytes"),
                  "Frames an access of `bytes` bytes takes without wait states.");

  py::class_<slave_box>(m, "ControlSlave",
                        "Register access, slave side, over a Python register file with "
                        "readable(a), writable(a), ready(), read(a) -> int, write(a, v) (each "
                        "optional). step(cdm) once per frame returns the CDS bit for the next.")
      .def(py::init([](py::object regs, const py::handle& id, bool refuse) {
             bs::control_slave_options o;
             o.slave_id = as<std::uint8_t>(id, "slave_id");
             if (o.slave_id > bs::max_slave_id) {
               throw py::value_error("slave_id must be 0..7");
             }
             o.refuse_while_busy = refuse;
             return new slave_box(std::move(regs), o);  // NOLINT: pybind11 owns it
           }),
           py::arg("registers"), py::kw_only(), py::arg("slave_id") = 0,
           py::arg("refuse_while_busy") = false, py::keep_alive<1, 2>())
      .def(
          "step",
          [](slave_box& b, bool cdm) {
            const bool cds = b.slave.step(cdm);
            if (!b.regs.pending.is_none()) {
              const py::object e = b.regs.pending;
              b.regs.pending = py::none();
              raise_object(e);
            }
            return cds;
          },
          py::arg("cdm"))
      .def_property_readonly("accesses", [](const slave_box& b) { return b.slave.accesses(); })
      .def_property_readonly("rejected_writes",
                             [](const slave_box& b) { return b.slave.rejected_writes(); })
      .def_property_readonly("refused_busy",
                             [](const slave_box& b) { return b.slave.refused_busy(); });

  // A passive observer's events: kind "header" or "byte" (None for frames completing nothing).
  py::class_<bs::observed_access> seen(
      m, "ObservedAccess",
      "A register access part the observer saw complete: kind 'header' (slave_id, address, "
      "write, cts, crc, crc_ok, echo: the slave's R/W answer, R in bit 1) or 'byte' (address, "
      "write, data, crc and crc_ok of the sending side, answer and answer_crc: the slave's, "
      "stop: its P answer, waits: its wait states).");
  seen.def_property_readonly("kind",
                             [](const bs::observed_access& a) {
                               return a.kind == bs::observed_kind::header ? "header" : "byte";
                             })
      .def_readonly("slave_id", &bs::observed_access::slave_id)
      .def_readonly("address", &bs::observed_access::address)
      .def_readonly("write", &bs::observed_access::write)
      .def_readonly("cts", &bs::observed_access::cts)
      .def_readonly("crc", &bs::observed_access::crc)
      .def_readonly("crc_ok", &bs::observed_access::crc_ok)
      .def_readonly("echo", &bs::observed_access::echo)
      .def_readonly("data", &bs::observed_access::data)
      .def_readonly("answer", &bs::observed_access::answer)
      .def_readonly("answer_crc", &bs::observed_access::answer_crc)
      .def_readonly("stop", &bs::observed_access::stop)
      .def_readonly("waits", &bs::observed_access::waits);
  add_repr(seen, {"kind", "slave_id", "address", "write", "crc", "crc_ok", "echo", "data", "answer",
                  "stop", "waits"});
  py::class_<bs::control_observer>(
      m, "ControlObserver",
      "Register access as a bus monitor sees it: step(cds, cdm) once per frame with the frame's "
      "CDS bit and the CDM bit sent after it; returns an ObservedAccess when a header or a byte "
      "completes (the answer to a slot comes one frame later), else None.")
      .def(py::init<>())
      .def(
          "step",
          [](bs::control_observer& o, bool cds, bool cdm) -> py::object {
            const bs::observed_access a = o.step(cds, cdm);
            if (a.kind == bs::observed_kind::none) {
              return py::none();
            }
            return py::cast(a);
          },
          py::arg("cds"), py::arg("cdm"))
      .def("reset", &bs::control_observer::reset, "Forgets a half-seen access (a capture gap).");

  // --- EDS ----------------------------------------------------------------------------------
  py::class_<bs::eds_common> common(m, "EdsCommon", "EDS common part (one 64-byte bank).");
  common.def(py::init<>())
      .def_readwrite("version", &bs::eds_common::version)
      .def_readwrite("length", &bs::eds_common::length)
      .def_readwrite("user_bank_start", &bs::eds_common::user_bank_start)
      .def_readwrite("user_bank_end", &bs::eds_common::user_bank_end)
      .def_readwrite("channels", &bs::eds_common::channels)
      .def_readwrite("validity", &bs::eds_common::validity)
      .def_readwrite("location", &bs::eds_common::location)
      .def_readwrite("profile_bank", &bs::eds_common::profile_bank)
      .def_readwrite("data_length", &bs::eds_common::data_length)
      .def_readwrite("data_format", &bs::eds_common::data_format)
      .def_readwrite("crc_poly", &bs::eds_common::crc_poly);
  add_repr(common, {"version", "length", "user_bank_start", "user_bank_end", "channels", "validity",
                    "location", "profile_bank", "data_length", "data_format", "crc_poly"});
  py::class_<bs::bp3_profile> bp3(m, "Bp3Profile", "EDS standard encoder profile BP3 (one bank).");
  bp3.def(py::init<>())
      .def_readwrite("version", &bs::bp3_profile::version)
      .def_readwrite("length", &bs::bp3_profile::length)
      .def_readwrite("profile_id", &bs::bp3_profile::profile_id)
      .def_readwrite("feedback1", &bs::bp3_profile::feedback1)
      .def_readwrite("feedback2", &bs::bp3_profile::feedback2)
      .def_readwrite("power_on_delay_ms", &bs::bp3_profile::power_on_delay_ms)
      .def_property(
          "type",
          [](const bs::bp3_profile& p) {
            return enum_value("EncoderType", static_cast<int>(p.type));
          },
          [](bs::bp3_profile& p, const py::handle& t) {
            p.type = static_cast<bs::encoder_type>(as<std::uint8_t>(t, "type"));
          })
      .def_readwrite("positions", &bs::bp3_profile::positions)
      .def_readwrite("mt_length", &bs::bp3_profile::mt_length)
      .def_readwrite("mt_format", &bs::bp3_profile::mt_format)
      .def_readwrite("coarse_length", &bs::bp3_profile::coarse_length)
      .def_readwrite("coarse_format", &bs::bp3_profile::coarse_format)
      .def_readwrite("fine_length", &bs::bp3_profile::fine_length)
      .def_readwrite("fine_format", &bs::bp3_profile::fine_format)
      .def_readwrite("mt_count", &bs::bp3_profile::mt_count)
      .def_readwrite("sip_count", &bs::bp3_profile::sip_count)
      .def_readwrite("sip_resolution", &bs::bp3_profile::sip_resolution)
      .def_readwrite("crc_poly", &bs::bp3_profile::crc_poly)
      .def_readwrite("crc_start", &bs::bp3_profile::crc_start)
      .def_property_readonly("pulses_per_revolution", &bs::bp3_profile::pulses_per_revolution)
      .def_property_readonly("lsb_nm", &bs::bp3_profile::lsb_nm)
      .def("layout", &bs::bp3_profile::layout, "The sensor-data layout the profile announces.");
  add_repr(bp3, {"version", "profile_id", "type", "mt_length", "coarse_length", "fine_length",
                 "sip_count", "sip_resolution", "crc_poly", "crc_start"});
  m.def(
      "bank_checksum",
      [](const py::handle& bank) {
        const bytes_arg in(bank, "bank");
        if (in.view().size() < bs::bank_size) {
          raise_object(decode_error(errc::truncated, 0, 0, 0, bs::bank_size - in.view().size(),
                                    "biss.bank_checksum"));
        }
        return bs::bank_checksum(in.view());
      },
      py::arg("bank"), "The low byte of the sum of bytes 0x00..0x3E of a 64-byte bank.");
  m.def(
      "decode_eds_common",
      [](const py::handle& bank, bool verify) {
        const bytes_arg in(bank, "bank");
        const auto r = bs::decode_eds_common(in.view(), bs::eds_options{verify});
        check(r, "biss.decode_eds_common");
        return r.value();
      },
      py::arg("bank"), py::kw_only(), py::arg("verify_checksum") = false,
      "Parses the EDS common part.");
  m.def(
      "decode_bp3",
      [](const py::handle& bank, bool verify) {
        const bytes_arg in(bank, "bank");
        const auto r = bs::decode_bp3(in.view(), bs::eds_options{verify});
        check(r, "biss.decode_bp3");
        return r.value();
      },
      py::arg("bank"), py::kw_only(), py::arg("verify_checksum") = false,
      "Parses the BP3 profile.");
  m.def(
      "encode_eds_common",
      [](const bs::eds_common& e) {
        return bank_of(e, &bs::encode_eds_common, "biss.encode_eds_common");
      },
      py::arg("common"), "The 64-byte bank of the common part (checksum in 0x3F).");
  m.def(
      "encode_bp3",
      [](const bs::bp3_profile& p) { return bank_of(p, &bs::encode_bp3, "biss.encode_bp3"); },
      py::arg("profile"), "The 64-byte bank of the BP3 profile (checksum in 0x3F).");
}

}  // namespace mbpy
