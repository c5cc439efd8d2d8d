// T-format in the CLI:
//   decode tformat request <hex>                      encoder side: what an encoder received
//   decode tformat response <hex> [--resolution N]    master side (ID3's ENID may select N)
//   encode tformat request --id ID [--address N] [--data N]
//   serve tformat-encoder --device PATH [--baud N]    the TS5700N8500 emulator on a serial line
//   read tformat --device PATH --id ID [--address N] [--data N] [--baud N] [--echo]
//   read tformat --device PATH --id 0|1|3 --watch [--interval-ms N] [--count N] [--max-step N]
//                [--lose-after N] [--restore-after N]     repeated reads (tformat_watch.cpp)
#include <motionbus/core/errc.hpp>
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/tformat.hpp>
#include <motionbus/tformat/position.hpp>

#include <cstdint>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "capture.hpp"
#include "cli.hpp"
#include "options_bind.hpp"
#include "serial.hpp"
#include "tformat_io.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

// The EEPROM's addresses: 0..127 (T-format, EEPROM read/write: ADF).
constexpr std::uint64_t max_eeprom_address = 127;

// --resolution: the single-turn bits, 1..24; absent, an ID3 response's ENID selects them.
constexpr std::uint64_t max_resolution = 24;

tf::decode_options options_for(std::optional<std::uint8_t> resolution) {
  tf::decode_options o;
  if (resolution) {
    o.res.single_turn_bits = *resolution;
  } else {
    o.resolution_from_enid = true;
  }
  return o;
}

struct response_options {
  std::optional<std::uint8_t> resolution;
  void bind(CLI::App& app) { cli::number(app, "resolution", resolution, 1, max_resolution); }
};

cli::outcome decode_response_line(const std::string& input, const response_options& opts) {
  std::string error;
  const auto bytes = cli::parse_hex(input, error);
  if (!bytes) {
    return cli::outcome::failure(error);
  }
  const auto r = tf::decode_response_frame(mb::byte_view(bytes->data(), bytes->size()),
                                           options_for(opts.resolution));
  if (!r.is_complete()) {
    return cli::failure_of(r, 2);
  }
  return cli::outcome::success(tformat_io::response_record(r.value()));
}

cli::outcome decode_request_line(const std::string& input, const cli::no_options&) {
  std::string error;
  const auto bytes = cli::parse_hex(input, error);
  if (!bytes) {
    return cli::outcome::failure(error);
  }
  const mb::byte_view in(bytes->data(), bytes->size());
  const auto q = tf::decode_request(in);
  if (q.is_incomplete()) {
    return cli::outcome::failure("truncated");
  }
  if (q.is_failed()) {
    return cli::failure_of(q, 2);
  }
  if (q.consumed() != in.size()) {
    cli::record e;
    e.add("expected_bytes", q.consumed()).add("received_bytes", in.size());
    return cli::outcome::failure(mb::to_string(mb::errc::tformat_length), e);
  }
  return cli::outcome::success(tformat_io::request_record(q.value()));
}

// Parses a Data ID given as one hex digit ("3", "D", "0xD").
std::optional<std::uint8_t> parse_data_id(const std::string& text) {
  std::string t = text;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t = t.substr(2);
  }
  if (t.size() != 1) {
    return std::nullopt;
  }
  const auto v = cli::parse_uint("0x" + t);
  if (!v) {
    return std::nullopt;
  }
  return static_cast<std::uint8_t>(*v);
}

const char* const data_id_usage = "--id takes a Data ID: one hex digit 0..F";

std::uint8_t data_id_of(const std::string& text) {
  const auto id = parse_data_id(text);
  if (!id) {
    throw cli::usage_error{data_id_usage};
  }
  return *id;
}

// The request frame (its size); a usage error when the library refuses the Data ID or the
// address (an unknown Data ID, an EEPROM address past 127).
std::size_t request_of(std::uint8_t id, unsigned address, unsigned data,
                       std::uint8_t (&out)[tf::max_request_size]) {
  return cli::built(
      tf::encode_request(static_cast<tf::data_id>(id), static_cast<std::uint8_t>(address),
                         static_cast<std::uint8_t>(data), out),
      "--id " + std::to_string(static_cast<unsigned>(id)) + " --address " +
          std::to_string(address));
}

// --id, --address and --data: a request (encode, read). The library refuses an EEPROM address
// past 127 (out_of_range); `max_address` lets encode show that refusal.
struct request_options {
  std::optional<std::uint8_t> id;  ///< read from its hex digit as the line is parsed
  unsigned address = 0;
  unsigned data = 0;
  void bind(CLI::App& app, std::uint64_t max_address) {
    app.add_option_function<std::string>(
           "--id", [this](const std::string& text) { id = data_id_of(text); },
           cli::option_help("id").help)
        ->type_name(cli::option_help("id").type);
    cli::number(app, "address", address, 0, max_address);
    cli::number(app, "data", data, 0, 0xFF);
  }
  std::uint8_t required_id() const {
    if (!id) {
      throw cli::usage_error{data_id_usage};
    }
    return *id;
  }
  // The request frame (its size).
  std::size_t build(std::uint8_t (&out)[tf::max_request_size]) const {
    return request_of(required_id(), address, data, out);
  }
};

struct encode_options {
  request_options request;
  std::optional<std::string> vcd;
  std::uint64_t baud = cli::tformat_baud;
  void bind(CLI::App& app) {
    request.bind(app, 0xFF);
    cli::text(app, "vcd", vcd);
    cli::number(app, "baud", baud, 1, 100000000);
  }
};

int encode_request(const encode_options& opts) {
  std::uint8_t out[tf::max_request_size] = {};
  const std::size_t n = opts.request.build(out);
  cli::record f;
  f.bytes("hex", out, n);
  if (opts.vcd) {  // the UART line, 8N1 at --baud, from 1 us
    capture::channel line;
    line.name = "line";
    capture::uart_levels(std::vector<std::uint8_t>(out, out + n), static_cast<double>(opts.baud),
                         'N', 1, 1e-6, line);
    capture::write_vcd_file(*opts.vcd, {line});
    f.add("vcd", *opts.vcd);
  }
  return cli::finish(cli::outcome::success(f));
}

struct serve_options {
  cli::serial_line line = cli::serial_line::tformat();
  void bind(CLI::App& app) { line.bind(app); }
};

// serve tformat-encoder: answers each request as the TS5700N8500 emulator does. A frame ends when
// its length (from the CF) is reached, or when the line is idle for 1 ms.
int serve_encoder(const serve_options& opts) {
  serial::port port;
  if (!opts.line.open(port)) {
    return 1;
  }
  serial::install_stop_handler();
  motionbus::devices::ts5700n8500::emulator enc;
  const std::uint64_t start = serial::now_us64();  // 64-bit: the times printed do not wrap
  std::uint8_t frame[tf::max_request_size] = {};
  std::size_t size = 0;
  std::cerr << "motionbus: T-format encoder emulator on " << opts.line.device << '\n';
  while (!serial::stop_requested()) {
    std::uint8_t byte = 0;
    const long n = port.read_some(&byte, 1, size == 0 ? 100 : 1);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      return 1;
    }
    // The shaft turns slowly so that successive reads differ.
    const std::uint64_t since_start = serial::now_us64() - start;
    const auto now = static_cast<std::uint32_t>(since_start);  // the emulator's clock, 32-bit
    const auto elapsed_ms = static_cast<std::uint32_t>(since_start / 1000U);
    enc.set_position((elapsed_ms * 13U) % (1U << 17U), (elapsed_ms / 10000U) % 65536U);
    bool complete = false;
    if (n == 1) {
      frame[size++] = byte;
      const auto q = tf::decode_request(mb::byte_view(frame, size));
      complete = !q.is_incomplete() || size == tf::max_request_size;
    } else if (size > 0) {
      complete = true;  // idle: end of frame
    }
    if (complete) {
      const motionbus::devices::ts5700n8500::reply r = enc.respond(mb::byte_view(frame, size), now);
      if (r.size > 0 && !port.write_all(r.bytes, r.size)) {
        std::cerr << "motionbus: write error\n";
        return 1;
      }
      // what was served: the request's fields (or why it is not one) and the reply's bytes
      const auto q = tf::decode_request(mb::byte_view(frame, size));
      cli::outcome o = q.is_complete()
                           ? cli::outcome::success(tformat_io::request_record(q.value()))
                       : q.is_failed() ? cli::failure_of(q, 2)
                                       : cli::outcome::failure("truncated");
      cli::record& fields = o.ok ? o.fields : o.evidence;
      if (r.size > 0) {
        fields.bytes("answer", r.bytes, r.size);
      } else {
        fields.add("answer", "none");
      }
      cli::record at;
      at.add("time_us", since_start);
      cli::print(o, at);
      std::cout.flush();
      size = 0;
    }
  }
  return 0;
}

// read tformat: one transaction, printed like `decode tformat response`.
struct read_options {
  cli::serial_line line = cli::serial_line::tformat();
  request_options request;
  std::optional<std::uint8_t> resolution;
  int timeout_ms = 200;
  bool echo = false;
  cli::watch_options watch;
  void bind(CLI::App& app) {
    line.bind(app);
    request.bind(app, max_eeprom_address);
    cli::number(app, "resolution", resolution, 1, max_resolution);
    cli::number(app, "timeout-ms", timeout_ms, 0, 60000);
    cli::flag(app, "echo", echo);
    watch.bind(app);
  }
};

// --watch: the Data IDs whose response carries a position (ID0 ABS, ID1 ABM, ID3 both); the
// resets (7, 8, C) carry ABS too but are not sent over and over. A --max-step that unwrapping
// cannot tell from its opposite is refused (at the resolution known before the first response).
tformat_io::watch_setup watch_setup_of(const read_options& opts, std::uint8_t id,
                                       const std::uint8_t* request, std::size_t size,
                                       const tf::receiver_options& ro) {
  const auto polled = static_cast<tf::data_id>(id);
  if (polled != tf::data_id::read_abs && polled != tf::data_id::read_abm &&
      polled != tf::data_id::read_all) {
    throw cli::usage_error{"--watch reads a position: --id 0, 1 or 3"};
  }
  const mb::position_config cfg =
      tf::position_config_for(ro.decode.res, polled, opts.watch.max_step);
  if (!cfg.valid()) {
    throw cli::usage_error{"--max-step: at most " + std::to_string(cfg.unambiguous_step()) +
                           " counts for --id " + std::to_string(static_cast<unsigned>(id)) +
                           " (half the reading's range)"};
  }
  tformat_io::watch_setup s;
  s.id = polled;
  s.request = request;
  s.request_size = size;
  s.receiver = ro;
  s.baud = static_cast<std::uint32_t>(opts.line.baud);
  s.timeout_ms = static_cast<std::uint32_t>(opts.timeout_ms);
  return s;
}

int read_encoder(const read_options& opts) {
  std::uint8_t request[tf::max_request_size] = {};
  const std::size_t n = opts.request.build(request);
  const int timeout_ms = opts.timeout_ms;
  tf::receiver_options ro;
  ro.echo_mode = opts.echo ? tf::echo::expected : tf::echo::none;
  ro.decode = options_for(opts.resolution);
  std::optional<tformat_io::watch_setup> watching;
  if (opts.watch.watch) {  // usage errors before the port is opened
    watching = watch_setup_of(opts, opts.request.required_id(), request, n, ro);
  }
  serial::port port;
  if (!opts.line.open(port)) {
    return 1;
  }
  if (watching) {
    return tformat_io::watch(port, *watching, opts.watch);
  }
  port.flush_input();
  tf::receiver rx(ro);
  if (!port.write_all(request, n)) {
    std::cerr << "motionbus: write error\n";
    return 1;
  }
  rx.sent(mb::byte_view(request, n));
  const std::uint32_t deadline = serial::now_us() + static_cast<std::uint32_t>(timeout_ms) * 1000U;
  std::uint8_t buffer[64];
  while (static_cast<std::int32_t>(deadline - serial::now_us()) > 0) {
    const long got = port.read_some(buffer, sizeof buffer, 5);
    if (got < 0) {
      break;
    }
    int status = -1;  // a response, or a failure: the first result settles the command
    mb::feed_all(rx, mb::byte_view(buffer, static_cast<std::size_t>(got)), [&](const auto& r) {
      if (r.is_complete()) {
        cli::record fields = tformat_io::response_record(r.value());
        if (rx.echo_missed()) {  // --echo, and the line does not echo: the response came alone
          fields.add_bool("echo_missed", true);
        }
        cli::print(cli::outcome::success(fields));
        status = 0;
      } else {
        cli::print(cli::failure_of(r, 2));
        status = 1;
      }
      return false;
    });
    if (status >= 0) {
      return status;
    }
  }
  cli::print(cli::outcome::failure("timeout"));
  return 1;
}

}  // namespace

namespace cli {

protocol_entries tformat_entries() {
  protocol_entries e;
  e.decoders.push_back(
      lines("decode", "tformat", "request",
            "a request as the encoder receives it (CF, and ADF/EDF/CRC for EEPROM)",
            &decode_request_line));
  e.decoders.push_back(lines("decode", "tformat", "response",
                             "a response as the master receives it: position, status, alarms, CRC",
                             &decode_response_line));
  e.typed.push_back(cli::typed("encode", "tformat", "request",
                               "a request frame for a Data ID (EEPROM: with --address and --data)",
                               &encode_request));
  e.typed.push_back(cli::typed(
      "serve", "tformat-encoder", "",
      "the TS5700N8500 encoder emulator: answers every request on the port and prints it with "
      "the answer's bytes",
      &serve_encoder));
  e.typed.push_back(cli::typed(
      "read", "tformat", "",
      "one request to an encoder and its response, decoded; --watch: repeated reads with the "
      "continuous position, speed and link health",
      &read_encoder));
  return e;
}

}  // namespace cli
