// motionbus Python binding — motionbus.devices.sm_unit: the Tsubaki SM unit's Modbus profile
// (request builders, response decoders, units) and its emulator (served by modbus::serve_rtu).
#include <string>

#include "common.hpp"
#include "motionbus/devices/sm_unit.hpp"
#include "motionbus/devices/sm_unit_emulator.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/server.hpp"

namespace mbpy {

namespace sm = motionbus::devices::sm_unit;
namespace mb = motionbus::modbus;

namespace {

sm::channel channel_arg(const py::handle& c) {
  const auto v = as<std::uint8_t>(c, "channel");
  if (v >= sm::channel_count) {
    throw py::value_error("channel must be a Channel (0..8)");
  }
  return static_cast<sm::channel>(v);
}

template <class Build>
py::bytes adu(const char* what, Build&& b) {
  return encode_into<mb::max_rtu_size>(what, b);
}

// The response PDU of an RTU ADU the client decoded (the SM unit's FC11 layout).
mb::response response_arg(const py::handle& request_adu, const py::handle& response_adu,
                          std::string& keep) {
  const bytes_arg q(request_adu, "request");
  const bytes_arg r(response_adu, "response");
  const auto rq = mb::decode_rtu(q.view());
  check(rq, "sm_unit: request");
  const auto rr = mb::decode_rtu(r.view());
  check(rr, "sm_unit: response");
  const auto d = mb::decode_response_for(rq.value().pdu, rr.value().pdu,
                                         mb::report_id_format::two_bytes_no_count);
  check(d, "sm_unit: response");
  keep.assign(reinterpret_cast<const char*>(d.value().data.data()), d.value().data.size());
  mb::response v = d.value();
  v.data = byte_view(reinterpret_cast<const std::uint8_t*>(keep.data()), keep.size());
  return v;
}

}  // namespace

void bind_sm_unit(py::module_& root) {
  py::module_ m =
      root.def_submodule("sm_unit", "Tsubaki SM unit (Modbus RTU, 9600 8E1, slaves 1..16).");
  add_enum("Channel", {{"voltage", 0},
                       {"current", 1},
                       {"power", 2},
                       {"temperature", 3},
                       {"acceleration_x", 4},
                       {"acceleration_y", 5},
                       {"acceleration_z", 6},
                       {"frequency", 7},
                       {"torque", 8}});
  m.attr("BAUD") = sm::baud;
  m.attr("MIN_SLAVE") = sm::min_slave;
  m.attr("MAX_SLAVE") = sm::max_slave;
  m.attr("SETTING_COUNT") = sm::holding::setting_count;

  m.def(
      "read_inputs",
      [](const py::handle& s, const py::handle& f, const py::handle& c) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const auto first = as<std::uint16_t>(f, "first");
        const auto count = as<std::uint16_t>(c, "count");
        return adu("sm_unit.read_inputs",
                   [&](mutable_byte_view o) { return sm::read_inputs(slave, first, count, o); });
      },
      py::arg("slave"), py::arg("first"), py::arg("count"), "FC04 request ADU.");
  m.def(
      "read_instantaneous",
      [](const py::handle& s) {
        const auto slave = as<std::uint8_t>(s, "slave");
        return adu("sm_unit.read_instantaneous",
                   [&](mutable_byte_view o) { return sm::read_instantaneous(slave, o); });
      },
      py::arg("slave"), "FC04 100..108 request ADU.");
  m.def(
      "read_state",
      [](const py::handle& s) {
        const auto slave = as<std::uint8_t>(s, "slave");
        return adu("sm_unit.read_state",
                   [&](mutable_byte_view o) { return sm::read_state(slave, o); });
      },
      py::arg("slave"));
  m.def(
      "read_login_status",
      [](const py::handle& s) {
        const auto slave = as<std::uint8_t>(s, "slave");
        return adu("sm_unit.read_login_status",
                   [&](mutable_byte_view o) { return sm::read_login_status(slave, o); });
      },
      py::arg("slave"));
  m.def(
      "read_log",
      [](const py::handle& s, unsigned log, const py::handle& c) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const sm::channel ch = channel_arg(c);
        return adu("sm_unit.read_log",
                   [&](mutable_byte_view o) { return sm::read_log(slave, log, ch, o); });
      },
      py::arg("slave"), py::arg("log"), py::arg("channel"),
      "The 20 samples of one channel of log 1..3.");
  m.def(
      "write_setting",
      [](const py::handle& s, const py::handle& i, const py::handle& v) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const auto index = as<std::uint16_t>(i, "index");
        const auto value = as<std::uint16_t>(v, "value");
        return adu("sm_unit.write_setting",
                   [&](mutable_byte_view o) { return sm::write_setting(slave, index, value, o); });
      },
      py::arg("slave"), py::arg("index"), py::arg("value"), "FC06 one setting, range-checked.");
  m.def(
      "write_settings",
      [](const py::handle& s, const py::handle& f, const py::handle& values) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const auto first = as<std::uint16_t>(f, "first");
        const std::vector<std::uint16_t> v = registers_arg(values, "values");
        return adu("sm_unit.write_settings", [&](mutable_byte_view o) {
          return sm::write_settings(slave, first,
                                    motionbus::span<const std::uint16_t>(v.data(), v.size()), o);
        });
      },
      py::arg("slave"), py::arg("first"), py::arg("values"));
  m.def(
      "login",
      [](const py::handle& s, const py::handle& pw) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const bytes_arg p(pw, "password");
        return adu("sm_unit.login",
                   [&](mutable_byte_view o) { return sm::login(slave, p.view(), o); });
      },
      py::arg("slave"), py::arg("password"), "FC10 to 100..107: toggles login/logout.");
  m.def(
      "change_password",
      [](const py::handle& s, const py::handle& pw) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const bytes_arg p(pw, "password");
        return adu("sm_unit.change_password",
                   [&](mutable_byte_view o) { return sm::change_password(slave, p.view(), o); });
      },
      py::arg("slave"), py::arg("password"));
  m.def(
      "read_holding_block",
      [](const py::handle& s, const py::handle& f, const py::handle& c) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const auto first = as<std::uint16_t>(f, "first");
        const auto count = as<std::uint16_t>(c, "count");
        return adu("sm_unit.read_holding_block", [&](mutable_byte_view o) {
          return sm::read_holding_block(slave, first, count, o);
        });
      },
      py::arg("slave"), py::arg("first"), py::arg("count"));
  m.def(
      "set_coil",
      [](const py::handle& s, const py::handle& c) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const auto coil = as<std::uint16_t>(c, "coil");
        return adu("sm_unit.set_coil",
                   [&](mutable_byte_view o) { return sm::set_coil(slave, coil, o); });
      },
      py::arg("slave"), py::arg("coil"), "FC05 coil ON: warning reset (100) or count clear (0).");
  m.def(
      "read_version",
      [](const py::handle& s) {
        const auto slave = as<std::uint8_t>(s, "slave");
        return adu("sm_unit.read_version",
                   [&](mutable_byte_view o) { return sm::read_version(slave, o); });
      },
      py::arg("slave"), "FC11 request ADU.");

  m.def(
      "decode_instantaneous",
      [](const py::handle& q, const py::handle& r) {
        std::string keep;
        const mb::response v = response_arg(q, r, keep);
        if (sm::is_login_error(v)) {
          raise_object(decode_error(errc::modbus_mismatch, 0, 0, 4, 0,
                                    "sm_unit.decode_instantaneous: login error (exception 04)"));
        }
        const auto d = value_or_raise(sm::decode_instantaneous(v), "sm_unit.decode_instantaneous");
        py::dict out;
        for (std::size_t i = 0; i < sm::channel_count; ++i) {
          out[enum_value("Channel", static_cast<int>(i))] = d.raw[i];
        }
        return out;
      },
      py::arg("request"), py::arg("response"),
      "The instantaneous data (raw values per Channel) from the request and response ADUs.");
  m.def(
      "decode_version",
      [](const py::handle& q, const py::handle& r) {
        std::string keep;
        const mb::response v = response_arg(q, r, keep);
        const auto d = value_or_raise(sm::decode_version(v), "sm_unit.decode_version");
        return py::make_tuple(d.upper, d.lower);
      },
      py::arg("request"), py::arg("response"), "(upper, lower) software version from FC11.");
  m.def(
      "unit_of",
      [](const py::handle& c) {
        const sm::unit_info u = sm::unit_of(channel_arg(c));
        return py::make_tuple(std::string(u.unit), u.numerator, u.denominator, u.is_signed);
      },
      py::arg("channel"), "(unit, numerator, denominator, signed): value = raw * num / den.");
  m.def(
      "raw_value",
      [](const py::handle& c, const py::handle& reg) {
        return sm::raw_value(channel_arg(c), as<std::uint16_t>(reg, "register"));
      },
      py::arg("channel"), py::arg("register"));
  m.def(
      "log_address",
      [](unsigned log, const py::handle& c, unsigned sample) {
        return value_or_raise(sm::log_address(log, channel_arg(c), sample), "sm_unit.log_address");
      },
      py::arg("log"), py::arg("channel"), py::arg("sample"));
  m.def(
      "setting_limits",
      [](const py::handle& i) {
        const auto l = value_or_raise(sm::setting_limits(as<std::uint16_t>(i, "index")),
                                      "sm_unit.setting_limits");
        return py::make_tuple(l.lower, l.upper);
      },
      py::arg("index"), "(lower, upper) of setting 0..39.");
  m.def(
      "check_password",
      [](const py::handle& pw) {
        const bytes_arg p(pw, "password");
        const errc e = sm::check_password(p.view());
        if (e != errc::ok) {
          raise_encode(e, "sm_unit.check_password");
        }
      },
      py::arg("password"), "Raises EncodeError unless 8..16 characters 0x21..0x7E.");
  m.def(
      "warning_name",
      [](const py::handle& bit) -> py::object {
        const char* n = sm::warning_name(as<std::uint16_t>(bit, "bit"));
        if (n == nullptr) {
          return py::none();
        }
        return py::str(n);
      },
      py::arg("bit"));

  py::class_<sm::emulator>(m, "Emulator", "The emulated SM unit, served at a slave address.")
      .def(py::init<>())
      .def("set_time_ms", &sm::emulator::set_time_ms, py::arg("now_ms"))
      .def(
          "inject_warning",
          [](sm::emulator& e, const py::handle& bits) {
            e.inject_warning(as<std::uint16_t>(bits, "bits"));
          },
          py::arg("bits"))
      .def_property_readonly("logged_in", &sm::emulator::logged_in)
      .def(
          "setting",
          [](const sm::emulator& e, const py::handle& i) {
            const auto index = as<std::uint16_t>(i, "index");
            if (index >= sm::holding::setting_count) {
              throw py::value_error("index must be 0..39");
            }
            return e.setting(index);
          },
          py::arg("index"))
      .def_property_readonly("warning_status", &sm::emulator::warning_status)
      .def_property_readonly("warning_count", &sm::emulator::warning_count)
      .def(
          "instantaneous_register",
          [](const sm::emulator& e, const py::handle& c) {
            return e.instantaneous_register(channel_arg(c));
          },
          py::arg("channel"))
      .def(
          "serve",
          [](sm::emulator& e, const py::handle& request, const py::handle& a) {
            const auto address = as<std::uint8_t>(a, "address");
            if (address < sm::min_slave || address > sm::max_slave) {
              throw py::value_error("address must be 1..16");
            }
            const bytes_arg in(request, "request");
            std::uint8_t out[mb::max_rtu_size] = {};
            const auto n = mb::serve_rtu(e, address, in.view(), mutable_byte_view(out, sizeof out));
            return to_bytes(out, value_or_raise(n, "sm_unit.Emulator.serve"));
          },
          py::arg("request"), py::arg("address") = 1,
          "The response ADU to a request ADU (b'' when none is due).");
}

}  // namespace mbpy
