// The motionbus command line, parsed by CLI11: every command and subcommand is built from the
// registry of each protocol's file (decoders and commands), with one catalogue of options so
// that one idea has one option name, one help text and one set of allowed values everywhere.
//
//   motionbus crc <tformat|modbus|biss6|biss4> <input|->
//   motionbus decode <protocol> <kind> <input|-> [options]
//   motionbus decode <protocol> capture FILE [options]
//   motionbus encode <protocol> <kind> [options]
//   motionbus serve <emulator> --device PATH [options]
//   motionbus read <device> --device PATH [options]
//   motionbus monitor <protocol> --device PATH [options]
//
// Output: readable text, or with --json one JSON object per line. Exit status (docs/cli.md): 0
// every input decoded, or the transaction done; 1 an input failed, or the transaction did (no
// or a bad response, a Modbus exception response); 2 usage error (an option, or arguments the
// library's builders refuse: nothing is sent); 3 a fault of the tool itself.
#include <CLI/CLI.hpp>

#include <deque>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <motionbus/version.hpp>
#include "cli.hpp"
#include "options_bind.hpp"

namespace cli {

namespace {

const std::vector<protocol_entries>& all_protocols() {
  static const std::vector<protocol_entries> list = {
      crc_entries(),     tformat_entries(), modbus_entries(),
      sm_unit_entries(), biss_entries(),    monitor_entries(),
      capture_entries(), gateway_entries(), serve_modbus_entries()};
  return list;
}

const std::map<std::string, option_info>& catalogue() {
  static const std::map<std::string, option_info> c = {
      // T-format
      {"id", {"HEX", "T-format Data ID, one hex digit 0-F", {}}},
      {"resolution",
       {"BITS", "single-turn resolution in bits (default: from an ID3 response's ENID)", {}}},
      {"watch",
       {"",
        "read repeatedly: the continuous position, speed and link health, a live line on a "
        "terminal (a line per read otherwise, a JSON object per read with --json)",
        {}}},
      {"interval-ms", {"MS", "--watch: from one read's start to the next's, in milliseconds", {}}},
      {"max-step",
       {"COUNTS",
        "--watch: the largest plausible change of the position in one read, in counts (0: the "
        "largest unwrapping can tell); a larger step is reported, not applied",
        {}}},
      {"lose-after", {"N", "--watch: consecutive failed reads that lose the link", {}}},
      {"restore-after", {"N", "--watch: consecutive good reads that restore it", {}}},
      {"echo",
       {"", "the adapter hands back the request (half duplex, receiver always on): skip it", {}}},
      // Modbus
      {"function", {"FC", "Modbus function code (decimal or 0x..)", {}}},
      {"slave",
       {"N",
        "Modbus slave address, 1..247 (0: broadcast, where a command allows it; the SM unit: "
        "1..16)",
        {}}},
      {"quantity", {"N", "number of registers or coils to read", {}}},
      {"values",
       {"LIST",
        "comma-separated values to write: registers 0..65535, coils on/off (or 1/0); "
        "required by FC 05, 06, 0F, 10, 16 (AND,OR) and 17",
        {}}},
      {"write-address", {"ADDR", "FC17: the first register to write", {}}},
      {"type",
       {"TYPE",
        "read modbus: values of u32, i32, f32 (2 registers) or u64, i64, f64 (4) for FC 03, 04, "
        "10, 17: --quantity counts them, --values holds them",
        {}}},
      {"word-order",
       {"ORDER",
        "with --type: abcd (default), cdab, badc or dcba; A is the value's most significant "
        "byte (docs/modbus.md, typed values)",
        {}}},
      {"request", {"HEX", "the request ADU in hex: the response is checked against it", {}}},
      {"fc11",
       {"LAYOUT",
        "FC11 response layout: standard (byte count first) or sm (the SM unit's)",
        {"standard", "sm"}}},
      // Both
      {"address",
       {"ADDR",
        "Modbus: first register or coil; T-format: EEPROM address 0..127 (decimal or 0x..)",
        {}}},
      {"data",
       {"DATA",
        "T-format: the EEPROM byte to write; Modbus: PDU data bytes in hex (other codes); "
        "decode biss capture: the channel holding SLO",
        {}}},
      // Serial lines
      {"device", {"PORT", "serial port: /dev/ttyUSB0, COM3, /dev/tty.usbserial-...", {}}},
      {"baud", {"BAUD", "line speed in bit/s", {}}},
      {"parity", {"P", "parity: E (even), O (odd) or N (none)", {"E", "O", "N"}}},
      {"stop-bits", {"N", "stop bits: 1 or 2", {"1", "2"}}},
      {"timeout-ms", {"MS", "how long to wait for the response, in milliseconds", {}}},
      // SM unit
      {"password",
       {"TEXT",
        "the SM unit's password: 8 to 16 characters, each ! (0x21) to ~ (0x7E) (SM unit "
        "guideline, section 10)",
        {}}},
      {"read", {"WHAT", "what to read", {"instantaneous", "password"}}},
      // BiSS-C
      {"data-bits", {"N", "BiSS-C single-cycle data bits", {}}},
      {"crc-bits", {"N", "BiSS-C CRC bits", {}}},
      {"crc-poly", {"HEX", "BiSS-C CRC polynomial, BiSS notation with the x^N term (43)", {}}},
      {"crc-start", {"N", "BiSS-C CRC start value", {}}},
      {"no-crc-invert", {"", "the BiSS-C CRC is sent as computed (not inverted)", {}}},
      {"hex", {"WORDS", "the SL samples as hex words, most significant bit first", {}}},
      {"bits", {"N", "how many of the --hex bits to use", {}}},
      {"position", {"N", "BiSS-C position to encode", {}}},
      {"ne", {"0|1", "BiSS-C nE (error) bit, active low: 1 = no error", {}}},
      {"nw", {"0|1", "BiSS-C nW (warning) bit, active low: 1 = no warning", {}}},
      {"ack", {"N", "BiSS-C Ack bits before the Start bit", {}}},
      {"cds", {"0|1", "BiSS-C CDS bit", {}}},
      {"line-delay", {"N", "the line delay: idle (high) bits before the Ack", {}}},
      // Recordings and waveforms
      {"line", {"CHANNEL", "the channel holding the UART line (as the recording names it)", {}}},
      {"clock", {"CHANNEL", "the channel holding BiSS-C MA (as the recording names it)", {}}},
      {"vcd",
       {"FILE", "also write the frame as a waveform (VCD: the UART line, or MA and SLO)", {}}},
      // The gateway and TCP
      {"listen",
       {"ADDR:PORT",
        "where to accept Modbus TCP clients: ADDR:PORT, or PORT alone on 127.0.0.1 (0: any free "
        "port, printed at start)",
        {}}},
      {"rtu-over-tcp",
       {"", "the clients speak RTU over TCP (the RTU ADU with its CRC, no MBAP header)", {}}},
      {"max-clients", {"N", "client connections at once; one more is closed at once", {}}},
      {"idle-timeout-ms",
       {"MS", "a client connection silent this long is closed (with any half request)", {}}},
      {"turnaround-ms", {"MS", "the line's silence after a broadcast, in milliseconds", {}}},
      {"units",
       {"LIST",
        "unit addresses, e.g. 1-4,7: gateway: those forwarded (default: all; others get 0A); "
        "serve modbus: those served, one device each (default: 1)",
        {}}},
      {"tcp-listen",
       {"ADDR:PORT",
        "serve Modbus TCP (MBAP) there instead of --device (PORT alone: 127.0.0.1)",
        {}}},
      {"points", {"N", "serve modbus: coils, inputs and registers of each unit, at 0..N-1", {}}},
      {"functions",
       {"LIST", "the function codes forwarded, e.g. 1-4,6,16 (default: all; others get 01)", {}}},
      {"read-only", {"", "forward reads only: every write is refused with exception 01", {}}},
      {"answer-broadcasts",
       {"", "answer a broadcast write (unit 0) once it is on the line (default: never)", {}}},
      {"tcp", {"HOST:PORT", "a Modbus TCP server (MBAP) instead of --device", {}}},
      {"ascii",
       {"", "Modbus ASCII on the line (':' hex LRC CR LF) instead of RTU; 8 data bits", {}}},
      // Monitors
      {"count", {"N", "stop after N frames (monitor) or N reads (read --watch); 0: no limit", {}}},
      {"duration", {"S", "stop after S seconds (0: no limit; Ctrl-C stops too)", {}}},
      {"response-ms",
       {"MS", "a request not answered within this many milliseconds is flagged", {}}},
      {"gap-us",
       {"US",
        "the line's silence, in microseconds, that settles a frame cut short (a hint: length "
        "and CRC frame; default monitor: t3.5 or 20000 for Modbus, 20000 for T-format; "
        "capture: t3.5, or 10 byte times for T-format)",
        {}}},
  };
  return c;
}

}  // namespace

const option_info& option_help(const std::string& name) {
  const auto it = catalogue().find(name);
  if (it == catalogue().end()) {
    throw std::logic_error("motionbus: option --" + name + " is not in the catalogue");
  }
  return it->second;
}

namespace {

// A leaf command as CLI11 parses it: its app, --json, and what runs once its options (a
// struct: options.hpp) are parsed.
struct leaf {
  CLI::App* app = nullptr;
  bool json = false;
  std::function<int()> run;
};

CLI::App* child(CLI::App* parent, const std::string& name, const std::string& help) {
  for (CLI::App* sub : parent->get_subcommands([](CLI::App*) { return true; })) {
    if (sub->get_name() == name) {
      return sub;
    }
  }
  CLI::App* sub = parent->add_subcommand(name, help);
  sub->require_subcommand(0, 1);
  return sub;
}

void add_json(leaf& l) {
  l.app->add_flag("--json", l.json, "print one JSON object per line instead of text");
}

std::string protocol_help(const std::string& protocol) {
  static const std::map<std::string, std::string> help = {
      {"tformat", "T-format (Tamagawa Smart-Abs encoders, 2.5 Mbps half duplex)"},
      {"modbus", "Modbus RTU (any server; the SM unit has its own commands)"},
      {"biss", "BiSS-C (sensor data frames, AMO ABSYS by default)"},
  };
  const auto it = help.find(protocol);
  return it != help.end() ? it->second : protocol;
}

std::string listing() {
  std::string out = "Commands by protocol:\n";
  for (const decoder& d : decoders()) {
    out += std::string("  ") + d.group + " " + d.protocol + (*d.kind ? " " : "") + d.kind +
           (d.input ? " <input|->" : "") + "\n";
  }
  for (const typed_command& c : typed_commands()) {
    out += std::string("  ") + c.group + (*c.protocol ? " " : "") + c.protocol +
           (*c.kind ? " " : "") + c.kind + (*c.arguments ? " " : "") + c.arguments + "\n";
  }
  return out + "Run `motionbus <command> ... --help` for a command's options.";
}

}  // namespace

namespace {

template <class T>
std::vector<T> gather(std::vector<T> protocol_entries::*member) {
  std::vector<T> out;
  for (const auto& p : all_protocols()) {
    out.insert(out.end(), (p.*member).begin(), (p.*member).end());
  }
  return out;
}

}  // namespace

const std::vector<decoder>& decoders() {
  static const std::vector<decoder> list = gather(&protocol_entries::decoders);
  return list;
}

const std::vector<typed_command>& typed_commands() {
  static const std::vector<typed_command> list = gather(&protocol_entries::typed);
  return list;
}

int main_of(int argc, char** argv) {
  const std::string version = std::to_string(MOTIONBUS_VERSION_MAJOR) + "." +
                              std::to_string(MOTIONBUS_VERSION_MINOR) + "." +
                              std::to_string(MOTIONBUS_VERSION_PATCH);
  CLI::App app{"motionbus " + version +
                   ": T-format, Modbus RTU and BiSS-C frames decoded, encoded, served and watched",
               "motionbus"};
  app.require_subcommand(1);
  app.set_version_flag("--version", version);
  const std::map<std::string, std::string> group_help = {
      {"crc", "the CRC of hex bytes (tformat, modbus) or of a 0/1 bit string (biss6, biss4)"},
      {"decode", "decode frames given as hex or bits, or every frame in a capture file"},
      {"encode", "encode a frame (as hex or bits, or as a waveform with --vcd)"},
      {"serve", "run a device emulator on a serial port"},
      {"read", "one transaction with a device on a serial port"},
      {"monitor", "watch a tapped line: every frame, paired, checked and timed"},
  };
  for (const auto& g : group_help) {
    child(&app, g.first, g.second)->require_subcommand(1);
  }
  CLI::App* version_app = app.add_subcommand("version", "print the library version");
  bool version_json = false;
  version_app->add_flag("--json", version_json, "print one JSON object");

  std::deque<leaf> leaves;  // stable addresses: CLI11 binds to their members
  // a leaf at group / protocol [/ kind]
  auto add_leaf = [&](const char* group, const char* protocol, const char* kind,
                      const char* help) -> leaf& {
    leaf& l = leaves.emplace_back();
    if (!*protocol) {  // a command of its own (gateway)
      l.app = app.add_subcommand(group, help);
      return l;
    }
    CLI::App* parent = child(&app, group, "");
    CLI::App* at = *kind ? child(parent, protocol, protocol_help(protocol)) : parent;
    l.app = at->add_subcommand(*kind ? kind : protocol, help);
    return l;
  };
  for (const decoder& d : decoders()) {
    leaf& l = add_leaf(d.group, d.protocol, d.kind, d.help);
    auto input = std::make_shared<std::string>();
    CLI::Option* in = l.app->add_option(
        "input", *input,
        std::string("the input: ") + d.input_help + "; - reads one per line from standard input");
    if (d.input) {
      in->required();
    }
    const line_function handle = d.bind(*l.app);
    add_json(l);
    const bool needs_input = d.input;
    l.run = [handle, needs_input, input] {
      if (!needs_input && input->empty()) {
        return finish(handle(""));
      }
      return run_inputs(*input, handle);
    };
  }
  for (const typed_command& c : typed_commands()) {
    leaf& l = add_leaf(c.group, c.protocol, c.kind, c.help);
    l.run = c.bind(*l.app);
    add_json(l);
  }

  app.footer(listing());  // after the subcommands: only the top level lists every command
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    (void)app.exit(e);
    return 2;
  } catch (const usage_error& e) {  // a typed option out of its range
    std::cerr << "motionbus: " << e.message << "\nRun with --help for more information.\n";
    return 2;
  }
  if (version_app->parsed()) {
    if (version_json) {
      std::cout << nlohmann::ordered_json{{"ok", true}, {"version", version}}.dump() << '\n';
    } else {
      std::cout << "motionbus " << version << '\n';
    }
    return 0;
  }
  for (const leaf& l : leaves) {
    if (!l.app->parsed()) {
      continue;
    }
    set_output_format(l.json ? format::json : format::text);
    try {
      return l.run();
    } catch (const usage_error& e) {
      std::cerr << "motionbus: " << e.message << "\nRun with --help for more information.\n";
      return 2;
    }
  }
  std::cerr << "motionbus: a command is required\n" << app.help();
  return 2;
}

}  // namespace cli

int main(int argc, char** argv) {
  try {
    return cli::main_of(argc, argv);
  } catch (const std::exception& e) {  // a fault of the tool itself (e.g. out of memory)
    std::cerr << "motionbus: " << e.what() << '\n';
    return 3;
  }
}
