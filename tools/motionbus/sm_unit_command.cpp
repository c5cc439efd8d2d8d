// The Tsubaki SM unit in the CLI:
//   serve sm-unit --device PATH [--slave N] [--baud N] [--parity E|N|O] [--stop-bits N]
//   read sm-unit --device PATH [--slave N] [--password TEXT] [--baud N] [--parity E|N|O]
//                [--stop-bits N]
// Defaults: slave 1, 9600 baud 8E1 (SM unit guidelines §2).
#include <motionbus/devices/sm_unit.hpp>
#include <motionbus/devices/sm_unit_emulator.hpp>
#include <motionbus/modbus.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "modbus_io.hpp"
#include "serial.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
namespace sm = motionbus::devices::sm_unit;

namespace {

unsigned option(const cli::options& opts, const char* name, unsigned fallback, unsigned max) {
  return static_cast<unsigned>(cli::option_number(opts, name, fallback, max));
}

std::uint8_t slave_of(const cli::options& opts) {
  const unsigned slave = option(opts, "slave", 1, 247);
  if (slave == 0) {
    throw cli::usage_error{"--slave is 1..247"};
  }
  return static_cast<std::uint8_t>(slave);
}

int serve_sm_unit(const cli::options& opts) {
  serial::port port;
  const std::uint8_t slave = slave_of(opts);
  if (!modbus_io::open_port(port, opts)) {
    return 1;
  }
  serial::install_stop_handler();
  sm::emulator unit;
  mo::rtu_framer rx(mo::framer_role::server, slave);
  const serial::settings s = modbus_io::line_settings(opts);
  const mo::parity p =
      s.parity == 'N' ? mo::parity::none : (s.parity == 'O' ? mo::parity::odd : mo::parity::even);
  // t3.5, but at least the SM unit's own 5 ms silent interval; the OS adds its own delays
  const int silence_ms = static_cast<int>((mo::t35_us(s.baud, p, s.stop_bits) + 999U) / 1000U) + 4;
  const std::uint32_t start = serial::now_us();
  std::cerr << "motionbus: SM unit emulator, slave " << static_cast<unsigned>(slave) << ", on "
            << *opts.get("device") << '\n';
  std::uint8_t buffer[256];
  while (!serial::stop_requested()) {
    const long n = port.read_some(buffer, sizeof buffer, rx.pending() > 0 ? silence_ms : 100);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      return 1;
    }
    unit.set_time_ms((serial::now_us() - start) / 1000U);
    mb::byte_view in(buffer, static_cast<std::size_t>(n));
    for (;;) {
      auto r = n == 0 ? rx.end_of_frame() : rx.feed(in);
      if (r.is_incomplete()) {
        break;
      }
      in = in.subspan(n == 0 ? 0 : r.consumed());
      if (r.is_complete()) {
        std::uint8_t adu[mo::max_rtu_size] = {};
        std::uint8_t out[mo::max_rtu_size] = {};
        const auto k = mo::encode_rtu(r->slave, r->pdu, adu);
        const auto reply = mo::serve_rtu(unit, slave, mb::byte_view(adu, k.value_or(0)), out);
        if (reply.ok() && reply.value() > 0 && !port.write_all(out, reply.value())) {
          std::cerr << "motionbus: write error\n";
          return 1;
        }
      }
      if (n == 0) {
        break;
      }
    }
  }
  return 0;
}

modbus_io::exchange transact(serial::port& port, std::uint8_t slave, const std::uint8_t* adu,
                             std::size_t size) {
  return modbus_io::transact(port, slave, adu, size, mo::report_id_format::standard, 1000);
}

std::string decimal(std::int32_t raw, const sm::unit_info& u) {
  char text[32];
  if (u.denominator == 1) {
    std::snprintf(text, sizeof text, "%d", static_cast<int>(raw));
  } else {
    const int digits = u.denominator == 10 ? 1 : 2;
    std::snprintf(text, sizeof text, "%.*f", digits, static_cast<double>(raw) / u.denominator);
  }
  return text;
}

int read_sm_unit(const cli::options& opts) {
  serial::port port;
  const std::uint8_t slave = slave_of(opts);
  if (!modbus_io::open_port(port, opts)) {
    return 1;
  }
  const std::string password = opts.get("password").value_or("password");
  std::uint8_t adu[256] = {};
  auto fail = [](const std::string& code) {
    cli::print(cli::outcome::failure(code));
    return 1;
  };
  // Login status; log in if needed (writing the password toggles the state).
  std::size_t n = sm::read_login_status(slave, adu).value();
  modbus_io::exchange e = transact(port, slave, adu, n);
  if (!e.error.empty()) {
    return fail(e.error);
  }
  auto status =
      mo::decode_response(mb::byte_view(e.pdu.data(), e.pdu.size()), mb::byte_view(adu + 1, n - 3));
  if (!status.is_complete() || status->exception || status->data.size() != 2) {
    return fail(status.is_complete() ? "exception" : mb::to_string(status.error()));
  }
  bool logged_in = mo::register_at(status->data, 0) == sm::input::logged_in;
  bool logged_in_now = false;
  if (!logged_in) {
    const auto pw =
        mb::byte_view(reinterpret_cast<const std::uint8_t*>(password.data()), password.size());
    const auto k = sm::login(slave, pw, adu);
    if (!k) {
      return fail(mb::to_string(k.error()));
    }
    e = transact(port, slave, adu, k.value());
    if (!e.error.empty()) {
      return fail(e.error);
    }
    const auto r = mo::decode_response(mb::byte_view(e.pdu.data(), e.pdu.size()),
                                       mb::byte_view(adu + 1, k.value() - 3));
    if (!r.is_complete()) {
      return fail(mb::to_string(r.error()));
    }
    if (sm::is_login_error(r.value())) {
      return fail("login_error");
    }
    logged_in = logged_in_now = !r->exception;
  }
  n = sm::read_instantaneous(slave, adu).value();
  e = transact(port, slave, adu, n);
  if (!e.error.empty()) {
    return fail(e.error);
  }
  const auto r =
      mo::decode_response(mb::byte_view(e.pdu.data(), e.pdu.size()), mb::byte_view(adu + 1, n - 3));
  if (!r.is_complete()) {
    return fail(mb::to_string(r.error()));
  }
  if (r->exception) {
    return fail(sm::is_login_error(r.value()) ? "login_error" : "exception");
  }
  const auto data = sm::decode_instantaneous(r.value());
  if (!data) {
    return fail(mb::to_string(data.error()));
  }
  static const char* const names[sm::channel_count] = {
      "voltage",        "current",        "power",     "temperature", "acceleration_x",
      "acceleration_y", "acceleration_z", "frequency", "torque"};
  std::string out = "{\"ok\":true,\"slave\":" + std::to_string(slave) +
                    ",\"logged_in\":" + (logged_in ? "true" : "false") +
                    ",\"logged_in_by_read\":" + (logged_in_now ? "true" : "false");
  for (std::size_t i = 0; i < sm::channel_count; ++i) {
    const auto c = static_cast<sm::channel>(i);
    const sm::unit_info u = sm::unit_of(c);
    out += ",\"" + std::string(names[i]) + "\":{\"value\":" + decimal(data.value()[c], u) +
           ",\"unit\":" + cli::json_quote(u.unit) + ",\"raw\":" + std::to_string(data.value()[c]) +
           "}";
  }
  std::cout << out << "}\n";
  return 0;
}

}  // namespace

namespace cli {

protocol_entries sm_unit_entries() {
  protocol_entries e;
  e.emulators.push_back(
      {"sm-unit", &serve_sm_unit, {"device", "slave", "baud", "parity", "stop-bits"}, {}});
  e.devices.push_back({"sm-unit",
                       &read_sm_unit,
                       {"device", "slave", "baud", "parity", "stop-bits", "password"},
                       {}});
  return e;
}

}  // namespace cli
