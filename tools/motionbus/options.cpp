// Typed options for the CLI's commands, and the serial-line group.
#include "options_bind.hpp"

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

std::string help_with_range(const std::string& name, std::uint64_t min, std::uint64_t max) {
  const std::string& help = option_help(name).help;
  if (max >= 0xFFFFFFFFU) {
    return help;
  }
  return help + " (" + std::to_string(min) + ".." + std::to_string(max) + ")";
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

monitored_line monitored_line::tformat() {
  return monitored_line{};
}

monitored_line monitored_line::modbus() {
  monitored_line m;
  m.line = serial_line::modbus();
  return m;
}

void monitored_line::bind(CLI::App& app, bool device) {
  if (device) {
    line.bind(app);
  } else {
    line.bind_settings(app);
  }
  if (line.line_kind == serial_line::kind::modbus) {
    text(app, "fc11", fc11);
  }
  number(app, "gap-us", gap_us, 1, 60000000);
}

monitor_options monitor_options::modbus() {
  monitor_options o;
  o.watched = monitored_line::modbus();
  return o;
}

void monitor_options::bind(CLI::App& app) {
  watched.bind(app, true);
  number(app, "count", count, 0, ~std::uint64_t{0});
  number(app, "duration", duration_s, 0, 4000000);
  number(app, "response-ms", response_ms, 0, 60000);
  if (watched.line.line_kind == serial_line::kind::modbus) {
    flag(app, "ascii", ascii);
  }
}

void watch_options::bind(CLI::App& app) {
  CLI::Option* on = flag(app, "watch", watch);
  number(app, "interval-ms", interval_ms, 1, 3600000)->needs(on);
  number(app, "count", count, 0, ~std::uint64_t{0})->needs(on);
  number(app, "max-step", max_step, 0, max_position_step)->needs(on);
  number(app, "lose-after", lose_after, 1, 65535)->needs(on);
  number(app, "restore-after", restore_after, 1, 65535)->needs(on);
}

uart_capture_options uart_capture_options::modbus() {
  uart_capture_options o;
  o.watched = monitored_line::modbus();
  return o;
}

void uart_capture_options::bind(CLI::App& app) {
  recording(app, file);
  channel(app, "line", line_channel);
  watched.bind(app, false);
}

endpoint endpoint_of(const std::string& name, const std::string& text) {
  endpoint e;
  std::string port = text;
  const std::size_t colon = text.rfind(':');
  if (colon != std::string::npos) {
    e.host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (e.host.size() >= 2 && e.host.front() == '[' && e.host.back() == ']') {
      e.host = e.host.substr(1, e.host.size() - 2);
    }
    if (e.host.empty()) {
      throw usage_error{"--" + name + " takes HOST:PORT (or PORT), not \"" + text + "\""};
    }
  }
  e.port = static_cast<std::uint16_t>(number_in_range(name, port, 0, 65535));
  return e;
}

std::vector<std::uint8_t> number_list(const std::string& name, const std::string& text,
                                      std::uint64_t min, std::uint64_t max) {
  std::vector<bool> in(max + 1, false);
  std::string item;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i < text.size() && text[i] != ',') {
      item += text[i];
      continue;
    }
    const std::size_t dash = item.find('-');
    const std::uint64_t first =
        number_in_range(name, dash == std::string::npos ? item : item.substr(0, dash), min, max);
    const std::uint64_t last =
        dash == std::string::npos ? first : number_in_range(name, item.substr(dash + 1), min, max);
    if (last < first) {
      std::string message = "--" + name;
      message += ": the range " + item + " is empty";
      throw usage_error{message};
    }
    for (std::uint64_t v = first; v <= last; ++v) {
      in[v] = true;
    }
    item.clear();
  }
  std::vector<std::uint8_t> out;
  for (std::uint64_t v = 0; v <= max; ++v) {
    if (in[v]) {
      out.push_back(static_cast<std::uint8_t>(v));
    }
  }
  return out;
}

void gateway_options::bind(CLI::App& app) {
  text(app, "listen", listen);
  line.bind(app);
  flag(app, "rtu-over-tcp", rtu_over_tcp);
  number(app, "max-clients", max_clients, 1, 8);
  number(app, "idle-timeout-ms", idle_timeout_ms, 1, 86400000);
  number(app, "timeout-ms", timeout_ms, 1, 60000);
  number(app, "turnaround-ms", turnaround_ms, 0, 60000);
  text(app, "units", units);
  text(app, "functions", functions);
  flag(app, "read-only", read_only);
  flag(app, "answer-broadcasts", answer_broadcasts);
  text(app, "fc11", fc11);
}

CLI::Option* recording(CLI::App& app, std::string& file) {
  return app.add_option("file", file, "the recording: a sigrok session (.sr), VCD or CSV")
      ->required();
}

CLI::Option* channel(CLI::App& app, const std::string& name, std::string& field) {
  return text(app, name, field)->required();
}

}  // namespace cli
