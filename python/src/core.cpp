// motionbus Python binding — the shared machinery (common.hpp) and motionbus.crc.
#include <map>

#include "common.hpp"
#include "motionbus/core/crc.hpp"

namespace mbpy {

namespace {
// The errc values with their C++ names (the Python enum's member names); to_string() gives
// the tools' names. The test suite checks that every value to_string() knows is listed.
// clang-format off
#define MOTIONBUS_PY_ERRC(X) \
  X(ok) X(truncated) X(buffer_too_small) X(invalid_argument) X(crc_mismatch) X(out_of_range) \
  X(length_mismatch) X(reserved_bits) X(no_frame) X(tformat_sync_code) X(tformat_parity) \
  X(tformat_unknown_data_id) X(tformat_length) X(tformat_cf_mismatch) \
  X(tformat_address_mismatch) X(tformat_communication_alarm) X(tformat_start_bit) \
  X(tformat_delimiter) X(tformat_data_mismatch) X(modbus_illegal_function) X(modbus_quantity) \
  X(modbus_byte_count) X(modbus_address_overflow) X(modbus_coil_value) X(modbus_mismatch) \
  X(modbus_slave_address) X(modbus_pdu_length) X(modbus_ascii_character) \
  X(modbus_ascii_odd_digits) X(modbus_ascii_end) X(modbus_reference_type) X(modbus_file_number) \
  X(modbus_record_number) X(biss_no_ack) X(biss_no_start) \
  X(biss_not_acknowledged) X(biss_access_denied) X(biss_echo_mismatch) X(biss_timeout) \
  X(biss_write_not_confirmed) X(biss_aborted) X(biss_busy) X(biss_layout) X(biss_eds)
// clang-format on

std::map<std::string, std::vector<std::pair<const char*, int>>>& enums() {
  static auto* table = new std::map<std::string, std::vector<std::pair<const char*, int>>>();
  return *table;
}
}  // namespace

py::handle lookup(const char* module, const char* name) {
  py::object o = py::module_::import(module).attr(name);
  return o.release();
}

py::object enum_value(const char* cls_name, int value) {
  // One cache per class name (a handful of enums).
  static auto* cache = new std::map<std::string, py::handle>();
  auto it = cache->find(cls_name);
  if (it == cache->end()) {
    it = cache->emplace(cls_name, lookup("motionbus._enums", cls_name)).first;
  }
  py::object member =
      py::reinterpret_borrow<py::object>(it->second).attr("_value2member_map_").attr("get")(value);
  if (member.is_none()) {
    return py::int_(value);  // a wire value outside the enum (e.g. an unknown exception code)
  }
  return member;
}

void add_enum(const char* name, std::vector<std::pair<const char*, int>> members) {
  enums()[name] = std::move(members);
}

py::object decode_error(errc e, std::size_t consumed, std::uint32_t expected,
                        std::uint32_t received, std::size_t needed, const char* context,
                        const char* unit) {
  static const py::handle decode = lookup("motionbus._errors", "DecodeError");
  static const py::handle incomplete = lookup("motionbus._errors", "IncompleteError");
  const py::handle cls = needed != 0U ? incomplete : decode;
  return cls(static_cast<int>(e), context, py::arg("offset") = consumed,
             py::arg("expected") = expected, py::arg("received") = received,
             py::arg("needed") = needed, py::arg("unit") = unit);
}

void raise_object(const py::object& err) {
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(err.ptr())), err.ptr());
  throw py::error_already_set();
}

void raise_encode(errc e, const char* context) {
  static const py::handle encode = lookup("motionbus._errors", "EncodeError");
  raise_object(encode(static_cast<int>(e), context));
}

void raise_invalid(const char* context, const std::string& what) {
  static const py::handle encode = lookup("motionbus._errors", "EncodeError");
  raise_object(encode(static_cast<int>(errc::invalid_argument), context, py::arg("detail") = what));
}

std::uint64_t ranged(const py::handle& v, std::uint64_t hi, const char* name) {
  if (PyBool_Check(v.ptr()) == 0 && PyIndex_Check(v.ptr()) == 0) {
    throw py::type_error(std::string(name) + " must be an int, not " +
                         std::string(py::str(py::type::handle_of(v).attr("__name__"))));
  }
  const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(v.ptr()));
  if (!i) {
    throw py::error_already_set();
  }
  int overflow = 0;
  const long long s = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow < 0 || (overflow == 0 && s < 0)) {
    throw py::value_error(std::string(name) + " must be 0.." + std::to_string(hi) + ", got " +
                          std::string(py::str(static_cast<const py::handle&>(i))));
  }
  const unsigned long long u = PyLong_AsUnsignedLongLong(i.ptr());
  if (PyErr_Occurred() != nullptr || u > hi) {
    PyErr_Clear();
    throw py::value_error(std::string(name) + " must be 0.." + std::to_string(hi) + ", got " +
                          std::string(py::str(static_cast<const py::handle&>(i))));
  }
  return u;
}

std::vector<std::uint16_t> registers_arg(const py::handle& seq, const char* name) {
  if (PySequence_Check(seq.ptr()) == 0 || PyUnicode_Check(seq.ptr()) != 0 ||
      PyBytes_Check(seq.ptr()) != 0) {
    throw py::type_error(std::string(name) + " must be a sequence of ints (registers)");
  }
  const py::sequence s = py::reinterpret_borrow<py::sequence>(seq);
  if (s.size() > 0xFFFFU) {
    throw py::value_error(std::string(name) + ": too many registers");
  }
  std::vector<std::uint16_t> out;
  out.reserve(s.size());
  for (const py::handle v : s) {
    out.push_back(as<std::uint16_t>(v, name));
  }
  return out;
}

std::vector<std::uint8_t> packed_bits(const py::handle& seq, const char* name) {
  if (PySequence_Check(seq.ptr()) == 0 || PyUnicode_Check(seq.ptr()) != 0) {
    throw py::type_error(std::string(name) + " must be a sequence of bools");
  }
  const py::sequence s = py::reinterpret_borrow<py::sequence>(seq);
  if (s.size() > 0xFFFFU) {
    throw py::value_error(std::string(name) + ": too many bits");
  }
  std::vector<std::uint8_t> out((s.size() + 7U) / 8U, 0);
  std::size_t i = 0;
  for (const py::handle v : s) {
    if (PyObject_IsTrue(v.ptr()) == 1) {
      out[i / 8U] = static_cast<std::uint8_t>(out[i / 8U] | (1U << (i % 8U)));
    }
    ++i;
  }
  return out;
}

py::list unpack_bits(byte_view packed, std::size_t count) {
  py::list out;
  for (std::size_t i = 0; i < count && i / 8U < packed.size(); ++i) {
    out.append(py::bool_(((packed[i / 8U] >> (i % 8U)) & 1U) != 0U));
  }
  return out;
}

std::vector<std::uint8_t> pack_samples(const py::handle& seq) {
  if (PySequence_Check(seq.ptr()) == 0 || PyUnicode_Check(seq.ptr()) != 0 ||
      PyObject_CheckBuffer(seq.ptr()) != 0) {
    throw py::type_error("bits must be a sequence of 0/1 samples (the *_bytes forms take bytes)");
  }
  const py::sequence s = py::reinterpret_borrow<py::sequence>(seq);
  std::vector<std::uint8_t> packed((s.size() + 7U) / 8U, 0);
  std::size_t i = 0;
  for (const py::handle b : s) {
    if (PyObject_IsTrue(b.ptr()) == 1) {
      packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (0x80U >> (i % 8U)));
    }
    ++i;
  }
  return packed;
}

py::list unpack_samples(const std::uint8_t* packed, std::size_t count) {
  py::list out;
  for (std::size_t i = 0; i < count; ++i) {
    out.append(static_cast<int>((packed[i / 8U] >> (7U - i % 8U)) & 1U));
  }
  return out;
}

void add_repr(py::handle cls, std::vector<const char*> fields) {
  py::tuple names(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    names[i] = py::str(fields[i]);
  }
  cls.attr("_fields") = names;
  result_classes().append(cls);
}

py::list& result_classes() {
  static auto* classes = new py::list();
  return *classes;
}

namespace {

template <class Crc>
typename Crc::value_type crc_bytes(const py::handle& data) {
  const bytes_arg in(data);
  return Crc::compute(in.view());
}

template <class Crc>
typename Crc::value_type crc_of_bits(std::uint64_t bits, unsigned count) {
  if (count > 64U) {
    throw py::value_error("count must be 0..64");
  }
  return Crc::compute_bits(bits, count);
}

}  // namespace

void bind_core(py::module_& m) {
  py::list table;
  // NOLINTNEXTLINE(cppcoreguidelines-macro-usage)
#define MOTIONBUS_PY_ERRC_ROW(name) \
  table.append(py::make_tuple(#name, static_cast<int>(errc::name), to_string(errc::name)));
  MOTIONBUS_PY_ERRC(MOTIONBUS_PY_ERRC_ROW)
#undef MOTIONBUS_PY_ERRC_ROW
  m.attr("_errc_table") = table;
  m.def(
      "_errc_name", [](int v) { return motionbus::to_string(static_cast<errc>(v)); },
      "The tools' name of an error code value (\"unknown\" outside the enumeration).");
  m.def("_enum_table", []() {
    py::dict d;
    for (const auto& e : enums()) {
      py::list members;
      for (const auto& kv : e.second) {
        members.append(py::make_tuple(kv.first, kv.second));
      }
      d[py::str(e.first)] = members;
    }
    return d;
  });

  py::module_ crc = m.def_submodule("crc", "The protocols' CRCs, from the library's CRC engine.");
  crc.def("crc8_tformat", &crc_bytes<motionbus::crc8_tformat<>>, py::arg("data"),
          "T-format CRC (G = x^8 + 1: the XOR of the bytes) of bytes-like `data`.");
  crc.def("crc16_modbus", &crc_bytes<motionbus::crc16_modbus<>>, py::arg("data"),
          "Modbus RTU CRC-16 (poly 0x8005 reflected, init 0xFFFF) of bytes-like `data`; sent "
          "low byte first.");
  crc.def("crc6_biss", &crc_of_bits<motionbus::crc6_biss<>>, py::arg("bits"), py::arg("count"),
          "BiSS CRC6 (x^6 + x + 1, start 0, inverted) of the low `count` bits of `bits`, MSB "
          "first.");
  crc.def("crc4_biss", &crc_of_bits<motionbus::crc4_biss<>>, py::arg("bits"), py::arg("count"),
          "BiSS control CRC4 (x^4 + x + 1, start 0, inverted) of the low `count` bits, MSB first.");

  py::class_<motionbus::dynamic_crc>(crc, "Crc",
                                     "A CRC from run-time Williams-model parameters (poly "
                                     "without its x^width term), computed bit by bit.")
      .def(py::init([](unsigned width, std::uint32_t poly, std::uint32_t init, bool refin,
                       bool refout, std::uint32_t xorout) {
             const motionbus::crc_parameters p{width, poly, init, refin, refout, xorout};
             if (!p.valid()) {
               raise_invalid("Crc", "width must be 1..32 and poly, init, xorout fit it");
             }
             return motionbus::dynamic_crc(p);
           }),
           py::arg("width"), py::arg("poly"), py::arg("init") = 0, py::arg("refin") = false,
           py::arg("refout") = false, py::arg("xorout") = 0)
      .def(
          "update",
          [](motionbus::dynamic_crc& c, const py::handle& data) -> motionbus::dynamic_crc& {
            const bytes_arg in(data);
            return c.update(in.view());
          },
          py::arg("data"), py::return_value_policy::reference_internal,
          "Feeds bytes-like `data`; returns self.")
      .def(
          "update_bits",
          [](motionbus::dynamic_crc& c, std::uint64_t bits,
             unsigned count) -> motionbus::dynamic_crc& {
            if (count > 64U) {
              throw py::value_error("count must be 0..64");
            }
            return c.update_bits(bits, count);
          },
          py::arg("bits"), py::arg("count"), py::return_value_policy::reference_internal,
          "Feeds the low `count` bits of `bits` in the CRC's bit order; returns self.")
      .def_property_readonly("value", &motionbus::dynamic_crc::value, "The CRC so far.")
      .def_property_readonly("width",
                             [](const motionbus::dynamic_crc& c) { return c.parameters().width; })
      .def("__repr__", [](const motionbus::dynamic_crc& c) {
        const auto& p = c.parameters();
        return "Crc(width=" + std::to_string(p.width) + ", poly=" + std::to_string(p.poly) +
               ", init=" + std::to_string(p.init) + ", refin=" + (p.refin ? "True" : "False") +
               ", refout=" + (p.refout ? "True" : "False") +
               ", xorout=" + std::to_string(p.xorout) + ", value=" + std::to_string(c.value()) +
               ")";
      });
}

}  // namespace mbpy
