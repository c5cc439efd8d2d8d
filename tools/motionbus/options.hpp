// Typed options for the CLI's commands: a command's options are a struct whose fields CLI11
// fills, each bound once with its range (the field's initial value is the default, the help
// text is the catalogue's, commands.cpp); the serial-line group that read, serve and monitor
// share, with the one way the CLI opens a port; the bus monitors' options (monitor, decode
// modbus|tformat capture).
#ifndef MOTIONBUS_TOOLS_OPTIONS_HPP
#define MOTIONBUS_TOOLS_OPTIONS_HPP

// CLI11's types by name only: a command that binds options with number() includes
// options_bind.hpp (CLI11 whole); the others compile without CLI11.
namespace CLI {
class App;
class Option;
}  // namespace CLI

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "serial.hpp"

namespace cli {

/// T-format's line rate: 2.5 Mbps (Tamagawa T-format, "communication specification").
constexpr unsigned tformat_baud = 2500000;
/// The Modbus RTU default line: 9600 bit/s, even parity (Modbus over Serial Line V1.02 §2.5.1).
constexpr unsigned modbus_baud = 9600;

/// The largest --max-step taken (the position tracker's readings span at most 2^62 counts).
constexpr std::uint64_t max_position_step = std::uint64_t{1} << 62U;

/// An option of the catalogue (commands.cpp): what its value looks like, what it means, the
/// values allowed (empty: any).
struct option_info {
  const char* type;
  const char* help;
  std::vector<std::string> allowed;
};
/// The catalogue's entry for `--name` (a logic error when there is none).
const option_info& option_help(const std::string& name);

/// The number `text` as --name takes it, from `min` to `max`, else a usage error.
std::uint64_t number_in_range(const std::string& name, const std::string& text, std::uint64_t min,
                              std::uint64_t max);

/// The catalogue's help of `--name` with its range, as number() binds it: "... (min..max)"
/// (the range written once, where the option is bound; none shown for an unbounded count).
std::string help_with_range(const std::string& name, std::uint64_t min, std::uint64_t max);

/// Binds `--name` to `field`: a number, decimal or 0x.. (parse_uint), from `min` to `max`, else
/// a usage error. The field's value before parsing is the default, shown in --help.
CLI::Option* number(CLI::App& app, const std::string& name, std::uint64_t& field, std::uint64_t min,
                    std::uint64_t max);
// number() for other integer types and std::optional fields: options_bind.hpp.
/// Binds `--name` to a text field (checked against the catalogue's allowed values, if any);
/// a non-empty initial value is the default shown in --help.
CLI::Option* text(CLI::App& app, const std::string& name, std::string& field);
CLI::Option* text(CLI::App& app, const std::string& name, std::optional<std::string>& field);
/// Binds the switch `--name`.
CLI::Option* flag(CLI::App& app, const std::string& name, bool& field);

/// The serial line of read, serve and monitor: --device (required), --baud, and for Modbus
/// --parity and --stop-bits (8 data bits always).
struct serial_line {
  enum class kind : std::uint8_t { tformat, modbus };
  std::string device;
  std::uint64_t baud = tformat_baud;
  std::string parity = "N";
  unsigned stop_bits = 1;
  kind line_kind = kind::tformat;

  /// T-format: 2.5 Mbaud 8N1, --device and --baud.
  static serial_line tformat();
  /// Modbus: 9600 8E1, --device, --baud, --parity, --stop-bits.
  static serial_line modbus();
  void bind(CLI::App& app);
  /// --baud, --parity and --stop-bits alone (encode --vcd draws the line without opening it).
  void bind_settings(CLI::App& app);
  serial::settings settings() const;
  /// Opens the port (an error or warning on stderr, "motionbus: ..."); false when it cannot.
  bool open(serial::port& port) const;
};

/// A bus monitor's line (monitor, decode modbus|tformat capture): the serial-line settings,
/// for Modbus --fc11, and --gap-us, the silence that settles what the monitor holds.
struct monitored_line {
  serial_line line;
  std::string fc11 = "standard";
  std::optional<std::uint32_t> gap_us;  ///< 1 us to 60 s; empty: the command's default

  static monitored_line tformat();
  static monitored_line modbus();
  /// The settings, --device as well when `device` (monitor; a recording has none).
  void bind(CLI::App& app, bool device);
  std::uint32_t gap_or(std::uint32_t fallback) const { return gap_us.value_or(fallback); }
};

/// monitor modbus|tformat: the line, and when to stop or flag: --count frames and --duration
/// seconds (0: no limit; Ctrl-C stops too), --response-ms.
struct monitor_options {
  monitored_line watched = monitored_line::tformat();
  std::uint64_t count = 0;
  std::uint32_t duration_s = 0;
  std::uint32_t response_ms = 1000;
  bool ascii = false;  ///< Modbus: the line speaks Modbus ASCII

  static monitor_options modbus();
  void bind(CLI::App& app);
};

/// read tformat --watch: a read every --interval-ms (from the start of one to the start of the
/// next; a read that takes longer delays the next), --count reads (0: until Ctrl-C); the
/// position's plausible step per read, --max-step counts (0: the largest unwrapping can tell),
/// and the link's hysteresis, --lose-after consecutive failures and --restore-after consecutive
/// successes (core/position.hpp, core/link_health.hpp). The options other than --watch need it.
struct watch_options {
  bool watch = false;
  std::uint32_t interval_ms = 100;
  std::uint64_t count = 0;
  std::uint64_t max_step = 0;
  std::uint16_t lose_after = 3;
  std::uint16_t restore_after = 3;

  void bind(CLI::App& app);
};

/// decode modbus|tformat capture FILE --line CHANNEL: the recording, the channel holding the
/// UART line (as the recording names it), the line's settings.
struct uart_capture_options {
  std::string file;
  std::string line_channel;
  monitored_line watched = monitored_line::tformat();

  static uart_capture_options modbus();
  void bind(CLI::App& app);
};

/// A TCP endpoint, ADDR:PORT (or PORT alone: 127.0.0.1).
struct endpoint {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string text() const { return host + ":" + std::to_string(port); }
};
/// `text` as --name takes an endpoint (HOST:PORT, [v6]:PORT, or PORT), else a usage error.
endpoint endpoint_of(const std::string& name, const std::string& text);
/// A list of numbers and ranges, "1-4,7", each from `min` to `max`, else a usage error: the
/// numbers in it (each once, ascending).
std::vector<std::uint8_t> number_list(const std::string& name, const std::string& text,
                                      std::uint64_t min, std::uint64_t max);

/// gateway: Modbus TCP clients (MBAP, or RTU over TCP) to one Modbus RTU serial line, through
/// modbus/gateway.hpp: --listen, the line, the client limit, the idle and response timeouts,
/// the allow-list of units and functions, --read-only.
struct gateway_options {
  std::string listen = "127.0.0.1:502";
  serial_line line = serial_line::modbus();
  bool rtu_over_tcp = false;
  unsigned max_clients = 8;  ///< 1..8, the core's connections
  std::uint32_t idle_timeout_ms = 60000;
  std::uint32_t timeout_ms = 1000;  ///< the response timeout on the line
  std::uint32_t turnaround_ms = 100;
  std::optional<std::string> units;      ///< "1-4,7"; empty: 0..247
  std::optional<std::string> functions;  ///< "3,4,6"; empty: every function
  bool read_only = false;
  bool answer_broadcasts = false;
  std::string fc11 = "standard";  ///< the line's FC11 response layout (standard or sm)

  void bind(CLI::App& app);
};

/// Binds the positional FILE, a recording (.sr, .vcd, .csv): required.
CLI::Option* recording(CLI::App& app, std::string& file);
/// Binds `--name CHANNEL`, a channel of a recording: required.
CLI::Option* channel(CLI::App& app, const std::string& name, std::string& field);

/// A typed_command for `run`, whose options are `Options` (with `void bind(CLI::App&)`),
/// `initial` before parsing (the defaults); `arguments` its positional arguments, for the
/// listing ("<file>").
template <class Options>
typed_command typed(const char* group, const char* protocol, const char* kind, const char* help,
                    int (*run)(const Options&), Options initial = {}, const char* arguments = "") {
  return {group,
          protocol,
          kind,
          help,
          [run, initial](CLI::App& app) {
            auto o = std::make_shared<Options>(initial);
            o->bind(app);
            return std::function<int()>([o, run] { return run(*o); });
          },
          arguments};
}

/// Options of a decoder that takes none.
struct no_options {
  void bind(CLI::App&) {}
};

/// A decoder whose options are `Options` (with `void bind(CLI::App&)`): `handle` runs on each
/// input with them.
template <class Options>
decoder lines(const char* group, const char* protocol, const char* kind, const char* help,
              outcome (*handle)(const std::string&, const Options&)) {
  decoder d{group, protocol, kind, help, {}};
  d.bind = [handle](CLI::App& app) {
    auto o = std::make_shared<Options>();
    o->bind(app);
    return line_function([o, handle](const std::string& input) { return handle(input, *o); });
  };
  return d;
}

}  // namespace cli

#endif
