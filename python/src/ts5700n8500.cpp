// motionbus Python binding — motionbus.devices.ts5700n8500: the Tamagawa TS5700N8500 profile
// (request plans, EEPROM and temperature helpers, the alarm table) and its emulator.
#include "motionbus/devices/ts5700n8500.hpp"
#include "common.hpp"
#include "motionbus/devices/ts5700n8500_emulator.hpp"

namespace mbpy {

namespace ts = motionbus::devices::ts5700n8500;
namespace tf = motionbus::tformat;

namespace {

template <std::size_t N>
std::vector<ts::plan_step> steps(const motionbus::result<ts::plan<N>>& p, const char* what) {
  const ts::plan<N> v = value_or_raise(p, what);
  return std::vector<ts::plan_step>(v.begin(), v.end());
}

}  // namespace

void bind_ts5700n8500(py::module_& root) {
  py::module_ m = root.def_submodule("ts5700n8500", "Tamagawa TS5700N8500 (T-format encoder).");
  add_enum("LatchRule", {{"none", 0}, {"latched", 1}, {"by_speed", 2}});
  m.attr("ENID") = ts::enid;
  m.attr("SINGLE_TURN_BITS") = ts::resolution.single_turn_bits;
  m.attr("MULTI_TURN_BITS") = ts::resolution.multi_turn_bits;
  m.attr("COUNTS_PER_TURN") = ts::counts_per_turn;
  m.attr("STANDARD_BIT_RATE") = ts::standard_bit_rate;
  m.attr("OVERHEAT_FACTORY") = ts::overheat_factory;
  m.attr("TEMPERATURE_PAGE") = ts::temperature_page;
  m.attr("OVERHEAT_ADDRESS") = ts::overheat_address;
  m.attr("TEMPERATURE_ADDRESS") = ts::temperature_address;

  py::class_<ts::plan_step> step(m, "PlanStep", "One request to send, then a pause.");
  step.def_property_readonly("request", [](const ts::plan_step& s) { return to_bytes(s.view()); })
      .def_readonly("wait_after_us", &ts::plan_step::wait_after_us)
      .def_readonly("verify", &ts::plan_step::verify, "An EEPROM read that checks a write.")
      .def_readonly("expected_edf", &ts::plan_step::expected_edf);
  add_repr(step, {"request", "wait_after_us", "verify", "expected_edf"});

  m.def(
      "reset_plan",
      [](const py::handle& id) {
        return steps(ts::reset_plan(static_cast<tf::data_id>(as<std::uint8_t>(id, "id") & 0x0FU)),
                     "ts5700n8500.reset_plan");
      },
      py::arg("id"), "ID7/ID8/IDC ten times, 40 us apart; the last step waits for completion.");
  m.def(
      "page_change_plan",
      [](const py::handle& page) {
        return steps(ts::page_change_plan(as<std::uint8_t>(page, "page")),
                     "ts5700n8500.page_change_plan");
      },
      py::arg("page"), "Selects EEPROM page 0..5 or 7.");
  m.def(
      "write_verify_plan",
      [](const py::handle& page, const py::handle& address, const py::handle& data) {
        return steps(ts::write_verify_plan(as<std::uint8_t>(page, "page"),
                                           as<std::uint8_t>(address, "address"),
                                           as<std::uint8_t>(data, "data")),
                     "ts5700n8500.write_verify_plan");
      },
      py::arg("page"), py::arg("address"), py::arg("data"),
      "Page change, write, re-select, read back.");
  m.def(
      "writable",
      [](const py::handle& page, const py::handle& address) {
        return ts::writable(as<std::uint8_t>(page, "page"), as<std::uint8_t>(address, "address"));
      },
      py::arg("page"), py::arg("address"));
  m.def(
      "encode_overheat_threshold",
      [](int celsius) {
        return value_or_raise(ts::encode_overheat_threshold(celsius),
                              "ts5700n8500.encode_overheat_threshold");
      },
      py::arg("celsius"), "The threshold byte for 1..127 degC (degC + 128).");
  m.def(
      "decode_overheat_threshold",
      [](const py::handle& v) -> py::object {
        const ts::overheat_setting s = ts::decode_overheat_threshold(as<std::uint8_t>(v, "value"));
        if (!s.enabled) {
          return py::none();
        }
        return py::int_(s.celsius);
      },
      py::arg("value"), "The threshold in degC, or None when the check is disabled.");
  m.def(
      "decode_temperature",
      [](const py::handle& v) { return ts::decode_temperature(as<std::uint8_t>(v, "value")); },
      py::arg("value"), "Substrate temperature, two's complement degC.");

  py::class_<ts::alarm_info> alarm(m, "AlarmInfo",
                                   "One ALMC flag: symbol, name, what to do, how it latches.");
  alarm
      .def_property_readonly("symbol",
                             [](const ts::alarm_info& a) { return std::string(a.symbol); })
      .def_property_readonly("name", [](const ts::alarm_info& a) { return std::string(a.name); })
      .def_property_readonly("action",
                             [](const ts::alarm_info& a) { return std::string(a.action); })
      .def_property_readonly(
          "flag",
          [](const ts::alarm_info& a) { return enum_value("AlmcBit", static_cast<int>(a.flag)); })
      .def_property_readonly("latch",
                             [](const ts::alarm_info& a) {
                               return enum_value("LatchRule", static_cast<int>(a.latch));
                             })
      .def("latched_at", &ts::alarm_info::latched_at, py::arg("rpm"));
  add_repr(alarm, {"symbol", "name", "flag", "latch"});
  m.def(
      "alarm_table",
      []() {
        return std::vector<ts::alarm_info>(std::begin(ts::alarm_table), std::end(ts::alarm_table));
      },
      "The eight ALMC flags (spec 6.5).");

  py::class_<ts::emulator>(m, "Emulator",
                           "The emulated encoder: set its shaft and conditions, hand it each "
                           "request frame with the time, send back what respond() returns.")
      .def(py::init([](unsigned st, unsigned mt, const py::handle& enid, const py::handle& th) {
             if (st < 1U || st > 24U || mt < 1U || mt > 24U) {
               throw py::value_error("single_turn_bits and multi_turn_bits must be 1..24");
             }
             ts::emulator_config c;
             c.res.single_turn_bits = static_cast<std::uint8_t>(st);
             c.res.multi_turn_bits = static_cast<std::uint8_t>(mt);
             c.enid = as<std::uint8_t>(enid, "enid");
             c.overheat_threshold = as<std::uint8_t>(th, "overheat_threshold");
             return ts::emulator(c);
           }),
           py::kw_only(), py::arg("single_turn_bits") = 17, py::arg("multi_turn_bits") = 16,
           py::arg("enid") = ts::enid, py::arg("overheat_threshold") = ts::overheat_factory)
      .def("set_position", &ts::emulator::set_position, py::arg("raw_single_turn"),
           py::arg("turns"))
      .def("rotate", &ts::emulator::rotate, py::arg("counts"))
      .def(
          "set_condition",
          [](ts::emulator& e, const py::handle& a, bool present) {
            e.set_condition(static_cast<tf::almc_bit>(as<std::uint8_t>(a, "alarm")), present);
          },
          py::arg("alarm"), py::arg("present"))
      .def("set_speed_rpm", &ts::emulator::set_speed_rpm, py::arg("rpm"))
      .def("set_temperature", &ts::emulator::set_temperature, py::arg("celsius"))
      .def_property_readonly("abs", &ts::emulator::abs)
      .def_property_readonly("abm", &ts::emulator::abm)
      .def_property_readonly("almc", &ts::emulator::almc)
      .def_property_readonly("page", &ts::emulator::page)
      .def_property_readonly("overheat_threshold", &ts::emulator::overheat_threshold)
      .def(
          "eeprom",
          [](const ts::emulator& e, const py::handle& page, const py::handle& a) {
            return e.eeprom(as<std::uint8_t>(page, "page"), as<std::uint8_t>(a, "address"));
          },
          py::arg("page"), py::arg("address"))
      .def("busy", &ts::emulator::busy, py::arg("now_us"))
      .def(
          "respond",
          [](ts::emulator& e, const py::handle& frame, std::uint32_t now_us, bool delimiter_error) {
            const bytes_arg in(frame, "frame");
            const ts::reply r = e.respond(
                in.view(), now_us,
                delimiter_error ? ts::request_line::delimiter_error : ts::request_line::ok);
            return to_bytes(r.view());
          },
          py::arg("frame"), py::arg("now_us") = 0, py::kw_only(),
          py::arg("delimiter_error") = false,
          "The reply to a request frame at `now_us` (b'' when the encoder stays silent).");
}

}  // namespace mbpy
