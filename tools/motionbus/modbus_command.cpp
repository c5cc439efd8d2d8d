// Modbus RTU in the CLI:
//   decode modbus request <hex>                     a server's view of an RTU ADU
//   decode modbus response <hex> [--request <hex>] [--fc11 standard|sm]
//                                                   a client's view (checked against the request
//                                                   when given; alone, every check the response
//                                                   carries itself)
//   encode modbus request --function FC --slave N [--address N] [--quantity N]
//                         [--values a,b,...] [--write-address N] [--data HEX]
//   read modbus --device PATH --function FC --slave N [...] [--baud N] [--parity E|O|N]
//               [--type u32|i32|f32|u64|i64|f64 [--word-order abcd|cdab|badc|dcba]]
//   read modbus --tcp HOST:PORT --function FC --slave N [...]   the same over Modbus TCP
//   read modbus --device PATH --ascii [...]                     in Modbus ASCII
#include <motionbus/core/errc.hpp>
#include <motionbus/modbus.hpp>
#include <motionbus/modbus/framer.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "capture.hpp"
#include "cli.hpp"
#include "modbus_io.hpp"
#include "options_bind.hpp"
#include "serial.hpp"
#include "tcp_io.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

// The input as hex bytes holding one whole RTU ADU. `frame.pdu` points into `bytes`: the vector
// owns the data and moving it keeps the pointer valid.
struct parsed_adu {
  std::vector<std::uint8_t> bytes;
  mo::rtu_frame frame;
};

// `size` is the frame's size by the length rule (predict_request_size or
// predict_response_size): a frame shorter than it is `truncated` (expected and received byte
// counts as its evidence), not a CRC mismatch of its last two bytes.
std::optional<parsed_adu> adu_of(const std::string& input, std::string& error,
                                 cli::record& evidence,
                                 const std::function<std::size_t(mb::byte_view)>& size) {
  auto bytes = cli::parse_hex(input, error);
  if (!bytes) {
    return std::nullopt;
  }
  parsed_adu p{std::move(*bytes), {}};
  const mb::byte_view in(p.bytes.data(), p.bytes.size());
  const auto f = mo::decode_rtu(in);
  if (!f.is_complete()) {
    const std::size_t wanted = size(in);
    if (wanted != mo::unknown_length && (wanted == 0 || wanted > in.size())) {
      error = mb::to_string(mb::errc::truncated);
      if (wanted != 0) {
        evidence.add("expected_bytes", wanted).add("received_bytes", in.size());
      }
      return std::nullopt;
    }
    error = mb::to_string(f.error());
    evidence = cli::failure_of(f, 4).evidence;
    return std::nullopt;
  }
  p.frame = f.value();
  return p;
}

std::size_t request_size(mb::byte_view in) {
  return mo::predict_request_size(in);
}

}  // namespace

namespace {

cli::outcome decode_request_line(const std::string& input, const cli::no_options&) {
  std::string error;
  cli::record evidence;
  const auto parsed = adu_of(input, error, evidence, &request_size);
  if (!parsed) {
    return cli::outcome::failure(error, evidence);
  }
  return modbus_io::describe_request(parsed->frame);
}

// A response in hex as a client sees it, checked against the request (hex) when given.
cli::outcome describe_response_hex(const std::string& input,
                                   const std::optional<std::string>& request_hex,
                                   mo::report_id_format fc11) {
  std::optional<parsed_adu> request;
  if (request_hex) {
    std::string request_error;
    cli::record request_evidence;
    request = adu_of(*request_hex, request_error, request_evidence, &request_size);
    if (!request || !mo::decode_request(request->frame.pdu).is_complete()) {
      throw cli::usage_error{"--request is not a valid RTU request"};
    }
  }
  // the length rule of the request's function (alone: of the response's own)
  const auto size = [&](mb::byte_view in) {
    const std::uint8_t fc = request ? request->frame.pdu[0] : (in.size() > 1U ? in[1] : 0U);
    return mo::predict_response_size(in, fc, fc11);
  };
  std::string error;
  cli::record evidence;
  const auto parsed = adu_of(input, error, evidence, size);
  if (!parsed) {
    return cli::outcome::failure(error, evidence);
  }
  return modbus_io::describe_response(parsed->frame, request ? &request->frame : nullptr, fc11);
}

struct response_options {
  std::optional<std::string> request;
  std::string fc11 = "standard";
  void bind(CLI::App& app) {
    cli::text(app, "request", request);
    cli::text(app, "fc11", fc11);
  }
};

cli::outcome decode_response_line(const std::string& input, const response_options& opts) {
  return describe_response_hex(input, opts.request, modbus_io::fc11_of(opts.fc11));
}

// --values as numbers: registers 0..65535, or coils on/off (1/0), the only two states of a coil
// (Modbus Application Protocol V1.1b3 §6.5: FF00 on, 0000 off; any other is refused).
std::vector<std::uint16_t> parse_values(const std::string& text, bool coils) {
  std::vector<std::uint16_t> out;
  std::string item;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i < text.size() && text[i] != ',') {
      item += static_cast<char>(std::tolower(static_cast<unsigned char>(text[i])));
      continue;
    }
    if (coils) {
      if (item != "on" && item != "off" && item != "1" && item != "0") {
        throw cli::usage_error{"--values: a coil is on or off (1 or 0), not \"" + item + "\""};
      }
      out.push_back(item == "on" || item == "1" ? 1U : 0U);
    } else {
      const auto v = cli::parse_uint(item);
      if (!v || *v > 0xFFFF) {
        throw cli::usage_error{"--values takes comma-separated numbers 0..65535"};
      }
      out.push_back(static_cast<std::uint16_t>(*v));
    }
    item.clear();
  }
  return out;
}

// The request's options (encode and read): --function, --slave, their fields, --values, --data.
struct request_options {
  std::optional<std::uint8_t> function;
  std::optional<std::uint8_t> slave;
  std::uint16_t address = 0;
  std::uint16_t quantity = 1;
  std::uint16_t write_address = 0;
  std::optional<std::string> values;
  std::optional<std::string> data;
  void bind(CLI::App& app) {
    cli::number(app, "function", function, 1, 0x7F);
    cli::number(app, "slave", slave, 0, 0xFF);  // a byte; the codec refuses 248..255
    cli::number(app, "address", address, 0, 0xFFFF);
    cli::number(app, "quantity", quantity, 0, 0xFFFF);
    cli::text(app, "values", values);
    cli::number(app, "write-address", write_address, 0, 0xFFFF);
    cli::text(app, "data", data);
  }
};

// How many --values a function takes: at least `min`, at most `max` (0: none, it takes no
// --values). A write is never sent with a value the user did not give.
struct values_rule {
  std::size_t min;
  std::size_t max;
};
values_rule values_rule_of(std::uint8_t fc) {
  switch (fc) {
    case 0x05:
    case 0x06: return {1, 1};
    case 0x0F:
    case 0x10:
    case 0x17: return {1, static_cast<std::size_t>(-1)};
    case 0x16: return {2, 2};
    default: return {0, 0};
  }
}

// The --values of function `fc`, checked against what it takes (a usage error otherwise).
std::vector<std::uint16_t> values_for(const request_options& opts, std::uint8_t fc) {
  const values_rule rule = values_rule_of(fc);
  const auto& text = opts.values;
  char fc_text[8];
  std::snprintf(fc_text, sizeof fc_text, "0x%02X", static_cast<unsigned>(fc));
  if (rule.max == 0) {
    if (text) {
      throw cli::usage_error{std::string("FC ") + fc_text +
                             " takes no --values (they are for FC 05, 06, 0F, 10, 16, 17)"};
    }
    return {};
  }
  if (!text) {
    throw cli::usage_error{
        std::string("FC ") + fc_text +
        (fc == 0x16 ? " needs --values AND,OR" : " needs --values: what to write")};
  }
  std::vector<std::uint16_t> values = parse_values(*text, fc == 0x05 || fc == 0x0F);
  if (values.size() < rule.min || values.size() > rule.max) {
    throw cli::usage_error{std::string("FC ") + fc_text +
                           (fc == 0x16 ? " takes --values AND,OR" : " takes one value")};
  }
  return values;
}

// Builds the request ADU from the options; a usage error when they are incomplete or the codec
// refuses them (nothing is sent).
std::vector<std::uint8_t> build_request(const request_options& opts) {
  if (!opts.function) {
    throw cli::usage_error{"--function FC is required"};
  }
  if (!opts.slave) {
    throw cli::usage_error{"--slave N is required"};
  }
  const std::uint8_t fc = *opts.function;
  const std::uint8_t slave = *opts.slave;
  const std::uint16_t address = opts.address;
  const std::vector<std::uint16_t> regs = values_for(opts, fc);
  const mb::span<const std::uint16_t> reg_view(regs.data(), regs.size());
  const bool raw = fc > 0x06 && fc != 0x0F && fc != 0x10 && fc != 0x16 && fc != 0x17;
  if (!raw && opts.data) {
    throw cli::usage_error{"--data is for the function codes without their own options"};
  }
  std::uint8_t pdu[mo::max_pdu_size] = {};
  mb::result<std::size_t> n = mb::errc::invalid_argument;
  switch (fc) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04: n = mo::encode_read(fc, address, opts.quantity, pdu); break;
    case 0x05: n = mo::encode_write_single_coil(address, regs[0] != 0, pdu); break;
    case 0x06: n = mo::encode_write_single_register(address, regs[0], pdu); break;
    case 0x0F: {
      std::vector<std::uint8_t> packed((regs.size() + 7) / 8, 0);
      for (std::size_t i = 0; i < regs.size(); ++i) {
        if (regs[i] != 0) {
          packed[i / 8] = static_cast<std::uint8_t>(packed[i / 8] | (1U << (i % 8)));
        }
      }
      n = mo::encode_write_multiple_coils(address, static_cast<std::uint16_t>(regs.size()),
                                          mb::byte_view(packed.data(), packed.size()), pdu);
      break;
    }
    case 0x10: n = mo::encode_write_multiple_registers(address, reg_view, pdu); break;
    case 0x16: n = mo::encode_mask_write_register(address, regs[0], regs[1], pdu); break;
    case 0x17:
      n = mo::encode_read_write_multiple_registers(address, opts.quantity, opts.write_address,
                                                   reg_view, pdu);
      break;
    default: {
      std::string hex_error;
      std::vector<std::uint8_t> data;
      if (opts.data) {
        const auto parsed = cli::parse_hex(*opts.data, hex_error);
        if (!parsed) {
          throw cli::usage_error{"--data takes hex bytes"};
        }
        data = *parsed;
      }
      n = mo::encode_raw(fc, mb::byte_view(data.data(), data.size()), pdu);
    }
  }
  const std::size_t size = cli::built(n, "the request's fields");
  std::uint8_t adu[mo::max_rtu_size] = {};
  const std::size_t k = cli::built(mo::encode_rtu(slave, mb::byte_view(pdu, size), adu),
                                   "--slave " + std::to_string(slave));
  return std::vector<std::uint8_t>(adu, adu + k);
}

struct encode_options {
  request_options request;
  std::optional<std::string> vcd;
  cli::serial_line line = cli::serial_line::modbus();  // the --vcd waveform's line settings
  void bind(CLI::App& app) {
    request.bind(app);
    cli::text(app, "vcd", vcd);
    line.bind_settings(app);
  }
};

int encode_request(const encode_options& opts) {
  const auto adu = build_request(opts.request);
  cli::record f;
  f.bytes("hex", adu.data(), adu.size());
  if (const auto& vcd = opts.vcd) {  // the UART line at the line settings, from 1 us
    const serial::settings s = opts.line.settings();
    capture::channel line;
    line.name = "line";
    capture::uart_levels(adu, s.baud, s.parity, s.stop_bits, 1e-6, line);
    capture::write_vcd_file(*vcd, {line});
    f.add("vcd", *vcd);
  }
  return cli::finish(cli::outcome::success(f));
}

// --type and --word-order (read modbus): 32- and 64-bit values over registers
// (modbus/values.hpp; docs/modbus.md section 9). A read (FC03, 04, 17) asks for --quantity
// values (their registers) and prints them; a write (FC10, 17) takes them in --values.
struct typed_values {
  std::string type;  // u32 i32 f32 u64 i64 f64
  mo::word_order order = mo::word_order::abcd;
  std::size_t registers = 2;  // per value
};

std::optional<typed_values> typed_of(const std::optional<std::string>& type,
                                     const std::optional<std::string>& order, std::uint8_t fc) {
  if (!type) {
    if (order) {
      throw cli::usage_error{"--word-order is for --type"};
    }
    return std::nullopt;
  }
  typed_values t;
  t.type = *type;
  if (t.type != "u32" && t.type != "i32" && t.type != "f32" && t.type != "u64" && t.type != "i64" &&
      t.type != "f64") {
    throw cli::usage_error{"--type takes u32, i32, f32, u64, i64 or f64"};
  }
  t.registers = t.type[1] == '3' ? 2U : 4U;
  const std::string o = order.value_or("abcd");
  if (o == "abcd") {
    t.order = mo::word_order::abcd;
  } else if (o == "cdab") {
    t.order = mo::word_order::cdab;
  } else if (o == "badc") {
    t.order = mo::word_order::badc;
  } else if (o == "dcba") {
    t.order = mo::word_order::dcba;
  } else {
    throw cli::usage_error{"--word-order takes abcd, cdab, badc or dcba"};
  }
  if (fc != 0x03 && fc != 0x04 && fc != 0x10 && fc != 0x17) {
    throw cli::usage_error{"--type is for FC 03, 04 (reads), 10 (writes) and 17"};
  }
  return t;
}

// One --values item as a value of `t`, appended as its registers to `regs`.
template <class T>
void append_registers(T v, const typed_values& t, std::vector<std::uint16_t>& regs) {
  for (const std::uint16_t r : mo::to_registers(v, t.order)) {
    regs.push_back(r);
  }
}
void append_typed(const std::string& item, const typed_values& t,
                  std::vector<std::uint16_t>& regs) {
  const auto refuse = [&] {
    return cli::usage_error{"--values: \"" + item + "\" is no " + t.type};
  };
  char* end = nullptr;
  errno = 0;
  if (item.empty()) {
    throw refuse();
  }
  if (t.type == "f32" || t.type == "f64") {
    const double d = t.type == "f32" ? static_cast<double>(std::strtof(item.c_str(), &end))
                                     : std::strtod(item.c_str(), &end);
    if (*end != '\0' || (errno == ERANGE && std::isinf(d))) {
      throw refuse();
    }
    if (t.type == "f32") {
      append_registers(static_cast<float>(d), t, regs);
    } else {
      append_registers(d, t, regs);
    }
  } else if (t.type[0] == 'u') {
    const auto v = item[0] == '-' ? std::nullopt : cli::parse_uint(item);
    if (!v || (t.type == "u32" && *v > 0xFFFFFFFFU)) {
      throw refuse();
    }
    if (t.type == "u32") {
      append_registers(static_cast<std::uint32_t>(*v), t, regs);
    } else {
      append_registers(static_cast<std::uint64_t>(*v), t, regs);
    }
  } else {
    const long long v = std::strtoll(item.c_str(), &end, 10);
    if (*end != '\0' || errno == ERANGE || (t.type == "i32" && (v < INT32_MIN || v > INT32_MAX))) {
      throw refuse();
    }
    if (t.type == "i32") {
      append_registers(static_cast<std::int32_t>(v), t, regs);
    } else {
      append_registers(static_cast<std::int64_t>(v), t, regs);
    }
  }
}

// The typed values of `t` in the register bytes `data` (a read response's): JSON numbers (a
// float's NaN or infinity as the text "nan", "inf", "-inf") and their text.
template <class T>
void add_typed(mb::byte_view data, const typed_values& t, nlohmann::ordered_json& json,
               std::string& text) {
  for (std::size_t i = 0; i + t.registers <= data.size() / 2U; i += t.registers) {
    const T v = mo::value_at<T>(data, i, t.order).value();
    std::string item;
    if constexpr (std::is_floating_point<T>::value) {
      char buf[40];
      std::snprintf(buf, sizeof buf, sizeof(T) == 4 ? "%.9g" : "%.17g", static_cast<double>(v));
      item = std::isnan(v) ? "nan" : std::isinf(v) ? (v < 0 ? "-inf" : "inf") : buf;
      if (std::isfinite(v)) {
        json.push_back(static_cast<double>(v));
      } else {
        json.push_back(item);
      }
    } else {
      item = std::to_string(v);
      json.push_back(v);
    }
    text += (text.empty() ? "" : ",") + item;
  }
}
void add_typed_values(mb::byte_view data, const typed_values& t, cli::record& fields) {
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  std::string text;
  if (t.type == "u32")
    add_typed<std::uint32_t>(data, t, json, text);
  else if (t.type == "i32")
    add_typed<std::int32_t>(data, t, json, text);
  else if (t.type == "f32")
    add_typed<float>(data, t, json, text);
  else if (t.type == "u64")
    add_typed<std::uint64_t>(data, t, json, text);
  else if (t.type == "i64")
    add_typed<std::int64_t>(data, t, json, text);
  else
    add_typed<double>(data, t, json, text);
  fields.add("typed_values", json, text);
}

// read modbus: one transaction as a client; the response printed like `decode modbus response
// --request`.
struct read_options {
  cli::serial_line line = cli::serial_line::modbus();
  request_options request;
  int timeout_ms = 1000;
  std::string fc11 = "standard";
  std::optional<std::string> type;
  std::optional<std::string> word_order;
  std::optional<std::string> tcp;  // HOST:PORT: Modbus TCP instead of the serial line
  bool ascii = false;              // Modbus ASCII on the serial line
  void bind(CLI::App& app) {
    cli::text(app, "device", line.device);  // required unless --tcp
    line.bind_settings(app);
    cli::text(app, "tcp", tcp);
    cli::flag(app, "ascii", ascii);
    request.bind(app);
    cli::number(app, "timeout-ms", timeout_ms, 0, 60000);
    cli::text(app, "fc11", fc11);
    cli::text(app, "type", type);
    cli::text(app, "word-order", word_order);
  }
};

// The request's options with --type applied: --quantity counts values, --values holds them.
request_options typed_request(const request_options& given, const typed_values& t,
                              std::uint8_t fc) {
  request_options r = given;
  if (fc != 0x10) {  // a read: registers for --quantity values
    r.quantity = static_cast<std::uint16_t>(
        std::min<std::size_t>(std::size_t{given.quantity} * t.registers, 0xFFFF));
  }
  if (fc == 0x10 || fc == 0x17) {
    if (!given.values) {
      throw cli::usage_error{"FC " + std::to_string(fc) + " needs --values: what to write"};
    }
    std::vector<std::uint16_t> regs;
    std::string item;
    for (std::size_t i = 0; i <= given.values->size(); ++i) {
      if (i < given.values->size() && (*given.values)[i] != ',') {
        item += (*given.values)[i];
        continue;
      }
      append_typed(item, t, regs);
      item.clear();
    }
    std::string text;
    for (const std::uint16_t v : regs) {
      text += (text.empty() ? "" : ",") + std::to_string(v);
    }
    r.values = text;
  }
  return r;
}

int read_modbus(const read_options& opts) {
  const std::uint8_t fc = opts.request.function.value_or(0);
  const std::optional<typed_values> typed = typed_of(opts.type, opts.word_order, fc);
  const auto adu = build_request(typed ? typed_request(opts.request, *typed, fc) : opts.request);
  if (adu[0] == 0) {
    throw cli::usage_error{"read modbus needs a unicast --slave (1..247)"};
  }
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts.fc11);
  modbus_io::exchange e;
  const mb::byte_view request_pdu(adu.data() + 1, adu.size() - 3U);  // the RTU ADU's
  if (opts.tcp) {  // the RTU request's PDU in an MBAP ADU, the unit its address
    if (!opts.line.device.empty() || opts.ascii) {
      throw cli::usage_error{"--tcp is instead of --device (and --ascii)"};
    }
    const cli::endpoint to = cli::endpoint_of("tcp", *opts.tcp);
    e = tcp_io::transact(to, adu[0], request_pdu, 1, opts.timeout_ms);
  } else {
    serial::port port;
    if (!opts.line.open(port)) {
      return 1;
    }
    e = opts.ascii
            ? modbus_io::transact_ascii(port, adu[0], request_pdu, opts.timeout_ms)
            : modbus_io::transact(port, adu[0], adu.data(), adu.size(), fc11, opts.timeout_ms);
  }
  if (!e.error.empty()) {
    cli::print(cli::outcome::failure(e.error));
    return 1;
  }
  std::uint8_t response[mo::max_rtu_size] = {};
  const auto k = mo::encode_rtu(adu[0], mb::byte_view(e.pdu.data(), e.pdu.size()), response);
  cli::outcome o = describe_response_hex(cli::to_hex(response, k.value_or(0)),
                                         cli::to_hex(adu.data(), adu.size()), fc11);
  if (o.ok && (e.pdu[0] & mo::exception_flag) != 0U) {
    // The server refused the request (Modbus Application Protocol V1.1b3 §7): the transaction
    // failed, exit status 1, with the exception's fields as the evidence.
    o = cli::outcome::failure("exception", o.fields);
  }
  if (o.ok && typed && fc != 0x10) {  // the values read
    const std::uint8_t* data = e.pdu.data() + 2;
    add_typed_values(mb::byte_view(data, e.pdu.size() - 2U), *typed, o.fields);
  }
  cli::print(o);
  return o.ok ? 0 : 1;
}

}  // namespace

namespace cli {

protocol_entries modbus_entries() {
  protocol_entries e;
  e.decoders.push_back(lines("decode", "modbus", "request",
                             "a request RTU ADU as a server sees it: slave, function, fields, CRC",
                             &decode_request_line));
  e.decoders.push_back(
      lines("decode", "modbus", "response",
            "a response RTU ADU as a client sees it (paired with --request if given)",
            &decode_response_line));
  e.typed.push_back(
      cli::typed("encode", "modbus", "request", "a request RTU ADU", &encode_request));
  e.typed.push_back(cli::typed("read", "modbus", "",
                               "one request to a Modbus RTU server and its response, decoded",
                               &read_modbus));
  return e;
}

}  // namespace cli
