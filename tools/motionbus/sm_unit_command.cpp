// The Tsubaki SM unit in the CLI:
//   serve sm-unit --device PATH [--slave N] [--baud N] [--parity E|N|O] [--stop-bits N]
//   read sm-unit --device PATH [--read instantaneous|password] [--slave N] [--password TEXT]
//                [--fc11 sm|standard] [--baud N] [--parity E|N|O] [--stop-bits N]
// Defaults: slave 1, 9600 baud 8E1 (SM unit guidelines §2), FC11 in the SM unit's layout (§11).
// Every request waits at least 0.1 s after the previous reply (§3, min_command_interval_us).
// `read sm-unit` reads the instantaneous data and the version, which need no login; only
// `--read password` needs the unit logged in (§6 note *1): it logs in when the unit is logged
// out, says so, and logs out again afterwards.
#include <motionbus/devices/sm_unit.hpp>
#include <motionbus/devices/sm_unit_emulator.hpp>
#include <motionbus/modbus.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "modbus_io.hpp"
#include "options_bind.hpp"
#include "serial.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
namespace sm = motionbus::devices::sm_unit;

namespace {

// The SM unit's addresses are 1..16 (SM unit guideline §2, "Slave addresses 1-16"): another
// is a usage error, before anything is sent.
std::uint8_t slave_of(unsigned slave) {
  if (slave < sm::min_slave || slave > sm::max_slave) {
    throw cli::usage_error{"--slave " + std::to_string(slave) +
                           ": the SM unit's addresses are 1..16 (SM unit guideline, section 2)"};
  }
  return static_cast<std::uint8_t>(slave);
}

// The password as the unit takes it (§10: 8 to 16 characters, each 0x21..0x7E); a usage error
// otherwise.
std::string password_of(std::string password) {
  const auto e = sm::check_password(
      mb::byte_view(reinterpret_cast<const std::uint8_t*>(password.data()), password.size()));
  if (e != mb::errc::ok) {
    throw cli::usage_error{
        "--password takes 8 to 16 characters, each ! (0x21) to ~ (0x7E) (SM unit guideline, "
        "section 10)"};
  }
  return password;
}

// serve and read: the line, and the unit's address (1 by default).
struct serve_options {
  cli::serial_line line = cli::serial_line::modbus();
  unsigned slave = 1;
  void bind(CLI::App& app) {
    line.bind(app);
    cli::number(app, "slave", slave, 0, 255);
  }
};

int serve_sm_unit(const serve_options& opts) {
  serial::port port;
  const std::uint8_t slave = slave_of(opts.slave);
  if (!opts.line.open(port)) {
    return 1;
  }
  serial::install_stop_handler();
  sm::emulator unit;
  mo::rtu_framer rx(mo::framer_role::server, {slave});
  const serial::settings s = opts.line.settings();
  const mo::parity p = modbus_io::parity_of(s);
  // t3.5, but at least the SM unit's own 5 ms silent interval; the OS adds its own delays
  const int silence_ms = static_cast<int>((mo::t35_us(s.baud, p, s.stop_bits) + 999U) / 1000U) + 4;
  const std::uint64_t start = serial::now_us64();  // 64-bit: no wrap after 4294 s
  std::cerr << "motionbus: SM unit emulator, slave " << static_cast<unsigned>(slave) << ", on "
            << opts.line.device << '\n';
  std::uint8_t buffer[256];
  while (!serial::stop_requested()) {
    const long n = port.read_some(buffer, sizeof buffer, rx.pending() > 0 ? silence_ms : 100);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      return 1;
    }
    unit.set_time_ms(static_cast<std::uint32_t>((serial::now_us64() - start) / 1000U));
    mb::byte_view in(buffer, static_cast<std::size_t>(n));
    for (;;) {
      auto r = n == 0 ? rx.idle() : rx.feed(in);
      if (r.is_incomplete()) {
        break;
      }
      in = in.subspan(n == 0 ? 0 : r.consumed());
      if (r.is_complete()) {
        std::uint8_t out[mo::max_rtu_size] = {};
        const auto reply = mo::serve_frame(unit, slave, r.value(), out);  // checked by the framer
        const std::size_t size = reply.value_or(0);
        if (size > 0 && !port.write_all(out, size)) {
          std::cerr << "motionbus: write error\n";
          return 1;
        }
        modbus_io::print_served(r.value(), out, size, serial::now_us64() - start);
      }
      if (n == 0) {
        break;
      }
    }
  }
  return 0;
}

// One conversation with the unit: every request at least min_command_interval_us after the
// previous reply (SM unit guideline §3: "wait at least 0.1 second before sending the next
// command"; this also keeps the 5 ms silent interval of §4).
class paced_link {
 public:
  paced_link(serial::port& port, std::uint8_t slave, mo::report_id_format fc11)
      : port_(port), slave_(slave), fc11_(fc11) {}

  // Sends the request ADU (out[0..size)) and decodes the reply against it.
  mb::decode_result<mo::response> ask(const std::uint8_t* adu, std::size_t size,
                                      std::string& error) {
    if (replied_) {
      for (;;) {
        const auto since = static_cast<std::int32_t>(serial::now_us() - last_reply_us_);
        if (since >= static_cast<std::int32_t>(sm::min_command_interval_us)) {
          break;
        }
        serial::sleep_us(static_cast<std::uint32_t>(
            static_cast<std::int32_t>(sm::min_command_interval_us) - since));
      }
    }
    const modbus_io::exchange e = modbus_io::transact(port_, slave_, adu, size, fc11_, 1000);
    last_reply_us_ = serial::now_us();
    replied_ = true;
    if (!e.error.empty()) {
      error = e.error;
      return mb::decode_failure{mb::errc::truncated, 0};
    }
    pdu_ = e.pdu;
    const auto r = mo::decode_response_for(mb::byte_view(adu + 1, size - 3U),
                                           mb::byte_view(pdu_.data(), pdu_.size()), fc11_);
    if (!r.is_complete()) {
      error = mb::to_string(r.error());
    }
    return r;
  }

 private:
  serial::port& port_;
  std::uint8_t slave_;
  mo::report_id_format fc11_;
  std::uint32_t last_reply_us_ = 0;
  bool replied_ = false;
  std::vector<std::uint8_t> pdu_;  // the last reply: the response's views point into it
};

struct read_options {
  serve_options unit;
  std::string password = "password";
  std::string read = "instantaneous";
  std::string fc11 = "sm";
  void bind(CLI::App& app) {
    unit.bind(app);
    cli::text(app, "password", password);
    cli::text(app, "read", read);
    cli::text(app, "fc11", fc11);
  }
};

int read_sm_unit(const read_options& opts) {
  serial::port port;
  const std::uint8_t slave = slave_of(opts.unit.slave);
  const std::string& what = opts.read;
  if (what != "instantaneous" && what != "password") {
    throw cli::usage_error{"--read is instantaneous (data and version) or password"};
  }
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts.fc11);
  const std::string password = password_of(opts.password);
  if (!opts.unit.line.open(port)) {
    return 1;
  }
  paced_link link(port, slave, fc11);
  std::uint8_t adu[256] = {};
  std::string error;
  auto fail = [](const std::string& code, cli::record evidence = {}) {
    cli::print(cli::outcome::failure(code, std::move(evidence)));
    return 1;
  };
  cli::record out;
  out.add("slave", slave);
  if (what == "password") {
    // Reading the password needs the login state (§6 note *1): log in only if logged out,
    // and leave the unit as it was found.
    std::size_t n = cli::built(sm::read_login_status(slave, adu), "the login status request");
    auto status = link.ask(adu, n, error);
    if (!status.is_complete() || status->exception || status->data.size() != 2) {
      return fail(status.is_complete() ? "exception" : error);
    }
    const bool was_logged_in = mo::register_at(status->data, 0) == sm::input::logged_in;
    const auto pw =
        mb::byte_view(reinterpret_cast<const std::uint8_t*>(password.data()), password.size());
    auto toggle = [&]() -> std::string {  // writing the password toggles the state (§6)
      const std::size_t k = cli::built(sm::login(slave, pw, adu), "the login request");
      const auto r = link.ask(adu, k, error);
      if (!r.is_complete()) {
        return error;
      }
      return sm::is_login_error(r.value()) ? "login_error" : (r->exception ? "exception" : "");
    };
    if (!was_logged_in) {
      const std::string e = toggle();
      if (!e.empty()) {
        return fail(e);
      }
    }
    n = cli::built(
        sm::read_holding_block(slave, sm::holding::password, sm::holding::password_registers, adu),
        "the password request");
    const auto r = link.ask(adu, n, error);
    std::string text;
    const bool read_ok = r.is_complete() && !r->exception;
    if (read_ok) {
      for (std::size_t i = 0; i < r->data.size(); ++i) {
        if (r->data[i] != 0U) {
          text += static_cast<char>(r->data[i]);
        }
      }
    }
    const std::string read_error =
        read_ok ? ""
                : (r.is_complete() ? (sm::is_login_error(r.value()) ? "login_error" : "exception")
                                   : error);
    std::string restore_error;
    if (!was_logged_in) {
      restore_error = toggle();  // log out again, whatever the read gave
    }
    if (!read_error.empty()) {
      return fail(read_error);
    }
    if (!restore_error.empty()) {  // the password was read, the unit is left logged in
      cli::record e;
      e.add("reason", restore_error);
      return fail("logout_failed", e);
    }
    out.add_bool("logged_in", was_logged_in)
        .add_bool("logged_in_by_read", !was_logged_in)
        .add_bool("login_restored", !was_logged_in)
        .add("password", text);
    if (!was_logged_in) {
      std::cerr << "motionbus: the unit was logged out: logged in to read the password, then "
                   "logged out again\n";
    }
    return cli::finish(cli::outcome::success(out));
  }
  std::size_t n = cli::built(sm::read_instantaneous(slave, adu), "the data request");
  const auto r = link.ask(adu, n, error);
  if (!r.is_complete()) {
    return fail(error);
  }
  if (r->exception) {
    return fail(sm::is_login_error(r.value()) ? "login_error" : "exception");
  }
  const auto data = sm::decode_instantaneous(r.value());
  if (!data) {
    return fail(mb::to_string(data.error()));
  }
  n = cli::built(sm::read_version(slave, adu), "the version request");
  const auto v = link.ask(adu, n, error);
  if (!v.is_complete()) {
    return fail(error);
  }
  if (v->exception) {
    return fail("exception");
  }
  if (fc11 == mo::report_id_format::two_bytes_no_count) {
    const auto ver = sm::decode_version(v.value());
    out.add("version", modbus_io::sm_version_text(ver->upper, ver->lower));
  } else {
    out.bytes("slave_id", v->data.data(), v->data.size());
  }
  static const char* const names[sm::channel_count] = {
      "voltage",        "current",        "power",     "temperature", "acceleration_x",
      "acceleration_y", "acceleration_z", "frequency", "torque"};
  for (std::size_t i = 0; i < sm::channel_count; ++i) {
    const auto c = static_cast<sm::channel>(i);
    const sm::unit_info u = sm::unit_of(c);
    const std::int32_t raw = data.value()[c];
    out.measured(names[i], static_cast<double>(raw) / u.denominator, u.unit, raw);
  }
  return cli::finish(cli::outcome::success(out));
}

}  // namespace

namespace cli {

protocol_entries sm_unit_entries() {
  protocol_entries e;
  e.typed.push_back(cli::typed("serve", "sm-unit", "",
                               "the Tsubaki SM unit emulator: a Modbus RTU server on the port; "
                               "prints each request served with the answer's bytes",
                               &serve_sm_unit));
  e.typed.push_back(cli::typed("read", "sm-unit", "",
                               "the SM unit's instantaneous data and version (or its password)",
                               &read_sm_unit));
  return e;
}

}  // namespace cli
