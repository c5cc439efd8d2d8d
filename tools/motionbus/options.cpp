// Typed options for the CLI's commands, and the serial-line group.
#include "options.hpp"

#include <iostream>

namespace cli {

std::uint64_t number_in_range(const std::string& name, const std::string& text, std::uint64_t min,
                              std::uint64_t max) {
  const auto n = parse_uint(text);
  if (!n || *n < min || *n > max) {
    throw usage_error{"--" + name + " needs a number " +
                      (min == 0 ? "up to " : "from " + std::to_string(min) + " to ") +
                      std::to_string(max)};
  }
  return *n;
}

CLI::Option* number(CLI::App& app, const std::string& name, std::uint64_t& field, std::uint64_t min,
                    std::uint64_t max) {
  return number<std::uint64_t>(app, name, field, min, max);
}

namespace {

CLI::Option* checked(CLI::Option* o, const std::string& name) {
  const option_info& i = option_help(name);
  o->type_name(i.type);
  if (!i.allowed.empty()) {
    o->check(CLI::IsMember(i.allowed));
  }
  return o;
}

}  // namespace

CLI::Option* text(CLI::App& app, const std::string& name, std::string& field) {
  CLI::Option* o = checked(app.add_option("--" + name, field, option_help(name).help), name);
  if (!field.empty()) {
    o->default_str(field);
  }
  return o;
}

CLI::Option* text(CLI::App& app, const std::string& name, std::optional<std::string>& field) {
  return checked(
      app.add_option_function<std::string>(
          "--" + name, [&field](const std::string& t) { field = t; }, option_help(name).help),
      name);
}

CLI::Option* flag(CLI::App& app, const std::string& name, bool& field) {
  return app.add_flag("--" + name, field, option_help(name).help);
}

serial_line serial_line::tformat() {
  return serial_line{};
}

serial_line serial_line::modbus() {
  serial_line l;
  l.baud = modbus_baud;
  l.parity = "E";
  l.line_kind = kind::modbus;
  return l;
}

namespace {

// The highest rate each line takes: a Modbus line's UARTs, a T-format adapter's driver.
std::uint64_t max_baud(serial_line::kind k) {
  return k == serial_line::kind::modbus ? 4000000U : 100000000U;
}

}  // namespace

serial_line serial_line::of(const options& opts, kind k) {
  serial_line l = k == kind::modbus ? modbus() : tformat();
  l.device = opts.get("device").value_or("");
  if (const auto b = opts.get("baud")) {
    l.baud = number_in_range("baud", *b, 1, max_baud(k));
  }
  if (k == kind::modbus) {
    l.parity = opts.get("parity").value_or(l.parity);
    if (const auto s = opts.get("stop-bits")) {
      l.stop_bits = static_cast<unsigned>(number_in_range("stop-bits", *s, 1, 2));
    }
  }
  return l;
}

void serial_line::bind(CLI::App& app) {
  text(app, "device", device)->required();
  bind_settings(app);
}

void serial_line::bind_settings(CLI::App& app) {
  number(app, "baud", baud, 1, max_baud(line_kind));
  if (line_kind == kind::modbus) {
    text(app, "parity", parity);
    number(app, "stop-bits", stop_bits, 1, 2);
  }
}

serial::settings serial_line::settings() const {
  serial::settings s;
  s.baud = static_cast<unsigned>(baud);
  s.parity = parity.empty() ? 'N' : parity[0];
  s.stop_bits = stop_bits;
  return s;
}

bool serial_line::open(serial::port& port) const {
  if (device.empty()) {
    throw usage_error{"--device PORT is required"};
  }
  std::string warning;
  std::string error;
  if (!port.open(device, settings(), warning, error)) {
    std::cerr << "motionbus: " << error << '\n';
    return false;
  }
  if (!warning.empty()) {
    std::cerr << "motionbus: " << device << ": " << warning << '\n';
  }
  return true;
}

}  // namespace cli
