// motionbus Python binding — motionbus.devices.absys: the AMO ABSYS BiSS-C encoder profile
// (registers, status, serial number, positions, default EDS) and its emulator.
#include <string>

#include "common.hpp"
#include "motionbus/devices/absys.hpp"
#include "motionbus/devices/absys_emulator.hpp"

namespace mbpy {

namespace ab = motionbus::devices::absys;
namespace bs = motionbus::biss;

void bind_absys(py::module_& root) {
  py::module_ m = root.def_submodule("absys", "AMO ABSYS (BiSS-C encoder).");
  add_enum("Command",
           {{"set_offset_to_position", 0x02}, {"reset_offset", 0x03}, {"reset_errors", 0x06}});
  add_enum("PresetMode", {{"with_offset", 0x00}, {"actual", 0x01}});
  add_enum("SensorError", {{"none", 0}, {"in_operation", 1}, {"at_power_on", 2}});
  m.attr("LAYOUT") = ab::layout;
  py::dict regs;
  regs["bank_select"] = ab::reg::bank_select;
  regs["eds_bank"] = ab::reg::eds_bank;
  regs["profile_id"] = ab::reg::profile_id;
  regs["serial_number"] = ab::reg::serial_number;
  regs["offset"] = ab::reg::offset;
  regs["command"] = ab::reg::command;
  regs["position"] = ab::reg::position;
  regs["preset_mode"] = ab::reg::preset_mode;
  regs["error_status"] = ab::reg::error_status;
  regs["functional_reserve"] = ab::reg::functional_reserve;
  regs["device_id"] = ab::reg::device_id;
  regs["revision"] = ab::reg::revision;
  regs["manufacturer_id"] = ab::reg::manufacturer_id;
  m.attr("REGISTERS") = regs;
  m.attr("STATUS_HEALTHY") = ab::status_healthy;

  m.def(
      "decode_error_status",
      [](const py::handle& v) {
        const ab::error_status s = ab::decode_error_status(as<std::uint8_t>(v, "value"));
        py::dict d;
        d["error"] = s.error;
        d["warning"] = s.warning;
        d["undefined"] = s.undefined;
        return d;
      },
      py::arg("value"), "Register 0x6B: {'error', 'warning', 'undefined'} (active low bits).");
  m.def("status_of", &ab::status_of, py::arg("ne"), py::arg("nw"));
  m.def(
      "decode_serial_number",
      [](const py::handle& regs_in) {
        const bytes_arg in(regs_in, "registers");
        const auto r = ab::decode_serial_number(in.view());
        check(r, "absys.decode_serial_number");
        return py::make_tuple(std::string(r.value().prefix, 3), r.value().number,
                              std::string(1, r.value().suffix));
      },
      py::arg("registers"), "(prefix, number, suffix) from registers 0x44..0x4B.");
  m.def(
      "decode_device_id",
      [](const py::handle& regs_in) {
        const bytes_arg in(regs_in, "registers");
        const auto r = ab::decode_device_id(in.view());
        check(r, "absys.decode_device_id");
        return py::make_tuple(std::string(r.value().prefix, 2), r.value().number,
                              std::string(r.value().suffix, 2));
      },
      py::arg("registers"), "(prefix, number, suffix) from registers 0x75..0x7C.");
  m.def(
      "write_time_us",
      [](const py::handle& a, const py::handle& v) {
        return ab::write_time_us(as<std::uint8_t>(a, "address"), as<std::uint8_t>(v, "value"));
      },
      py::arg("address"), py::arg("value"));
  m.def("linear_position", &ab::linear_position, py::arg("absolute"), py::arg("offset"));
  m.def("rotary_position", &ab::rotary_position, py::arg("absolute"), py::arg("offset"),
        py::arg("pulses"));
  m.def(
      "default_bp3",
      [](const py::handle& t, std::uint32_t c, std::uint32_t r) {
        return ab::default_bp3(static_cast<bs::encoder_type>(as<std::uint8_t>(t, "type")), c, r);
      },
      py::arg("type"), py::arg("sip_count"), py::arg("sip_resolution"));

  py::class_<ab::emulator>(
      m, "Emulator",
      "The emulated ABSYS: frame() gives each frame's SL samples; control(cdm) "
      "takes the master's CDM bit (register access through biss.ControlMaster).")
      .def(
          py::init([](const py::handle& type, std::uint32_t sip_count, std::uint32_t sip_resolution,
                      const py::handle& slave_id, std::uint32_t period) {
            ab::emulator_config c;
            c.type = static_cast<bs::encoder_type>(as<std::uint8_t>(type, "type") & 1U);
            c.sip_count = sip_count;
            c.sip_resolution = sip_resolution;
            c.slave_id = as<std::uint8_t>(slave_id, "slave_id");
            if (c.slave_id > bs::max_slave_id) {
              throw py::value_error("slave_id must be 0..7");
            }
            c.frame_period_us = period;
            return new ab::emulator(c);  // NOLINT: pybind11 owns it (the emulator is not copyable)
          }),
          py::kw_only(), py::arg("type") = 0, py::arg("sip_count") = 512,
          py::arg("sip_resolution") = 10, py::arg("slave_id") = 0, py::arg("frame_period_us") = 100)
      .def("set_position", &ab::emulator::set_position, py::arg("position"))
      .def_property_readonly("absolute_position", &ab::emulator::absolute_position)
      .def_property_readonly("reported_position", &ab::emulator::reported_position)
      .def(
          "set_error",
          [](ab::emulator& e, const py::handle& s) {
            const auto v = as<std::uint8_t>(s, "error");
            if (v > 2U) {
              throw py::value_error("error must be a SensorError");
            }
            e.set_error(static_cast<ab::sensor_error>(v));
          },
          py::arg("error"))
      .def("set_functional_reserve", &ab::emulator::set_functional_reserve, py::arg("value"),
           py::arg("indicator"))
      .def_property_readonly("pulses_per_revolution", &ab::emulator::pulses_per_revolution)
      .def("values", &ab::emulator::values, "This frame's sensor data values (biss.SlaveValues).")
      .def(
          "frame",
          [](const ab::emulator& e, std::size_t line_delay, std::size_t ack_bits) {
            if (line_delay > 4096U || ack_bits > 4096U) {
              throw py::value_error("line_delay and ack_bits must be at most 4096");
            }
            std::vector<std::uint8_t> out(
                (line_delay + ack_bits + 2U + ab::layout.frame_bits() + 7U) / 8U + 1U, 0);
            const auto r = e.frame(motionbus::span<std::uint8_t>(out.data(), out.size()),
                                   line_delay, ack_bits);
            const std::size_t n = value_or_raise(r, "absys.Emulator.frame");
            return unpack_samples(out.data(), n);
          },
          py::arg("line_delay") = 1, py::arg("ack_bits") = 1,
          "This frame's SL samples as a list of 0/1.")
      .def_property_readonly("cds", &ab::emulator::cds, "The CDS bit the next frame carries.")
      .def("control", &ab::emulator::control, py::arg("cdm"),
           "The master's CDM bit of this frame; advances one frame period.")
      .def_property_readonly("offset", &ab::emulator::offset)
      .def_property_readonly("error_status", &ab::emulator::error_status)
      .def_property_readonly("selected_bank", &ab::emulator::selected_bank)
      .def_property_readonly("busy", &ab::emulator::busy)
      .def_property_readonly("register_accesses", &ab::emulator::register_accesses)
      .def_property_readonly("refused_while_busy", &ab::emulator::refused_while_busy);
}

}  // namespace mbpy
