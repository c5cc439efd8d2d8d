// Modbus RTU in the CLI:
//   decode modbus request <hex>                     a server's view of an RTU ADU
//   decode modbus response <hex> [--request <hex>] [--fc11 standard|sm]
//                                                   a client's view (checked against the request
//                                                   when given; alone, every check the response
//                                                   carries itself)
//   encode modbus request --function FC --slave N [--address N] [--quantity N]
//                         [--values a,b,...] [--write-address N] [--data HEX]
//   read modbus --device PATH --function FC --slave N [...] [--baud N] [--parity E|O|N]
#include <motionbus/core/errc.hpp>
#include <motionbus/modbus.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "capture.hpp"
#include "cli.hpp"
#include "modbus_io.hpp"
#include "serial.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

std::vector<std::int64_t> registers_of(mb::byte_view data) {
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i + 1 < data.size(); i += 2) {
    out.push_back(mo::register_at(data, i / 2));
  }
  return out;
}

std::vector<std::int64_t> bits_of(mb::byte_view packed, std::size_t count) {
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i < count && i / 8 < packed.size(); ++i) {
    out.push_back(mo::bit_at(packed, i) ? 1 : 0);
  }
  return out;
}

// The input as hex bytes holding one whole RTU ADU. `frame.pdu` points into `bytes`: the vector
// owns the data and moving it keeps the pointer valid.
struct parsed_adu {
  std::vector<std::uint8_t> bytes;
  mo::rtu_frame frame;
};

std::optional<parsed_adu> adu_of(const std::string& input, std::string& error,
                                 cli::record& evidence) {
  auto bytes = cli::parse_hex(input, error);
  if (!bytes) {
    return std::nullopt;
  }
  parsed_adu p{std::move(*bytes), {}};
  const auto f = mo::decode_rtu(mb::byte_view(p.bytes.data(), p.bytes.size()));
  if (!f.is_complete()) {
    error = mb::to_string(f.error());
    evidence = cli::failure_of(f, 4).evidence;
    return std::nullopt;
  }
  p.frame = f.value();
  return p;
}

}  // namespace

namespace modbus_io {

cli::outcome describe_request(const mo::rtu_frame& frame) {
  const mo::rtu_frame* adu = &frame;
  const auto q = mo::decode_request(adu->pdu);
  if (!q.is_complete()) {
    return cli::failure_of(q, 2);
  }
  cli::record f;
  f.add("slave", static_cast<std::int64_t>(adu->slave));
  f.hex("function", static_cast<std::int64_t>(q->function));
  const std::uint8_t fc = q->function;
  if (fc <= 0x06 || fc == 0x0F || fc == 0x10 || fc == 0x16 || fc == 0x17) {
    f.hex("address", static_cast<std::int64_t>(q->address), 4);
  }
  if (fc <= 0x04 || fc == 0x0F || fc == 0x10 || fc == 0x17) {
    f.add("quantity", static_cast<std::int64_t>(q->quantity));
  }
  if (fc == 0x05 || fc == 0x06) {
    f.add("value", static_cast<std::int64_t>(q->value));
  }
  if (fc == 0x16) {
    f.hex("and_mask", static_cast<std::int64_t>(q->and_mask), 4);
    f.hex("or_mask", static_cast<std::int64_t>(q->or_mask), 4);
  }
  if (fc == 0x17) {
    f.hex("write_address", static_cast<std::int64_t>(q->write_address), 4);
    f.add("write_quantity", static_cast<std::int64_t>(q->write_quantity));
  }
  if (fc == 0x0F) {
    f.add("byte_count", static_cast<std::int64_t>(q->data.size()));
    f.add("values", bits_of(q->data, q->quantity));
  } else if (fc == 0x10 || fc == 0x17) {
    f.add("byte_count", static_cast<std::int64_t>(q->data.size()));
    f.add("values", registers_of(q->data));
  } else if (!q->data.empty()) {
    f.bytes("data", q->data.data(), q->data.size());
  }
  f.hex("crc", static_cast<std::int64_t>(adu->crc), 4);
  return cli::outcome::success(f);
}

cli::outcome describe_response(const mo::rtu_frame& frame, const mo::rtu_frame* request_adu,
                               mo::report_id_format fc11) {
  const mo::rtu_frame* adu = &frame;
  const mb::byte_view pdu = adu->pdu;
  std::optional<mo::request> request;
  mb::decode_result<mo::response> r = mb::need_input{1};
  if (request_adu != nullptr) {
    if (request_adu->slave != adu->slave && request_adu->slave != 0) {
      cli::record e;
      e.add("expected_slave", static_cast<std::int64_t>(request_adu->slave))
          .add("received_slave", static_cast<std::int64_t>(adu->slave));
      return cli::outcome::failure(mb::to_string(mb::errc::modbus_mismatch), e);
    }
    const auto q = mo::decode_request(request_adu->pdu);
    if (q.is_complete()) {
      request = q.value();
    }
    r = mo::decode_response(pdu, request_adu->pdu, fc11);
  } else {
    r = mo::decode_response_unpaired(pdu, fc11);  // no request: what the response carries
  }
  if (!r.is_complete()) {
    return cli::failure_of(r, 2);
  }
  cli::record f;
  f.add("slave", static_cast<std::int64_t>(adu->slave));
  const std::uint8_t fc = r->function;
  f.hex("function", static_cast<std::int64_t>(fc));
  if (r->exception) {
    f.hex("exception", static_cast<std::int64_t>(r->exception_code));
    f.add("exception_name", modbus_io::exception_name(r->exception_code));
  } else if (fc <= 0x04 || fc == 0x17) {
    f.add("byte_count", static_cast<std::int64_t>(r->byte_count));
    if (fc <= 0x02) {
      f.add("values", bits_of(r->data, request ? request->quantity : r->data.size() * 8U));
    } else {
      f.add("values", registers_of(r->data));
    }
  } else if (fc == 0x05 || fc == 0x06 || fc == 0x0F || fc == 0x10) {
    f.hex("address", static_cast<std::int64_t>(r->address), 4);
    f.add(fc <= 0x06 ? "value" : "quantity",
          static_cast<std::int64_t>(fc <= 0x06 ? r->value : r->quantity));
  } else if (fc == 0x16) {
    f.hex("address", static_cast<std::int64_t>(r->address), 4);
    f.hex("and_mask", static_cast<std::int64_t>(r->and_mask), 4);
    f.hex("or_mask", static_cast<std::int64_t>(r->or_mask), 4);
  } else if (fc == 0x11 && fc11 == mo::report_id_format::two_bytes_no_count) {
    // the SM unit's layout: version upper, version lower (SM unit guideline §11)
    f.add("version_upper", static_cast<std::int64_t>(r->data[0]));
    f.add("version_lower", static_cast<std::int64_t>(r->data[1]));
    f.add("version", modbus_io::sm_version_text(r->data[0], r->data[1]));
  } else {
    // FC11 (standard layout: byte count, then the device's bytes) and the other functions:
    // the data part as hex
    f.bytes("data", pdu.data() + 1, pdu.size() - 1);
  }
  f.hex("crc", static_cast<std::int64_t>(adu->crc), 4);
  return cli::outcome::success(f);
}

}  // namespace modbus_io

namespace {

cli::outcome decode_request_line(const std::string& input, const cli::options&) {
  std::string error;
  cli::record evidence;
  const auto parsed = adu_of(input, error, evidence);
  if (!parsed) {
    return cli::outcome::failure(error, evidence);
  }
  return modbus_io::describe_request(parsed->frame);
}

cli::outcome decode_response_line(const std::string& input, const cli::options& opts) {
  std::string error;
  cli::record evidence;
  const auto parsed = adu_of(input, error, evidence);
  if (!parsed) {
    return cli::outcome::failure(error, evidence);
  }
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts, mo::report_id_format::standard);
  if (const auto text = opts.get("request")) {
    std::string request_error;
    cli::record request_evidence;
    const auto request = adu_of(*text, request_error, request_evidence);
    if (!request || !mo::decode_request(request->frame.pdu).is_complete()) {
      throw cli::usage_error{"--request is not a valid RTU request"};
    }
    return modbus_io::describe_response(parsed->frame, &request->frame, fc11);
  }
  return modbus_io::describe_response(parsed->frame, nullptr, fc11);
}

std::vector<std::uint64_t> parse_values(const std::string& text) {
  std::vector<std::uint64_t> out;
  std::string item;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i == text.size() || text[i] == ',') {
      const auto v = cli::parse_uint(item);
      if (!v || *v > 0xFFFF) {
        throw cli::usage_error{"--values takes comma-separated numbers 0..65535"};
      }
      out.push_back(*v);
      item.clear();
    } else {
      item += text[i];
    }
  }
  return out;
}

std::uint16_t option16(const cli::options& opts, const char* name, std::uint16_t fallback) {
  const auto v = opts.get(name);
  if (!v) {
    return fallback;
  }
  const auto n = cli::parse_uint(*v);
  if (!n || *n > 0xFFFF) {
    throw cli::usage_error{std::string("--") + name + " takes 0..65535"};
  }
  return static_cast<std::uint16_t>(*n);
}

// Builds the request ADU from the options; an error code when the codec refuses it.
std::vector<std::uint8_t> build_request(const cli::options& opts, std::string& error) {
  const auto fc_value = cli::parse_uint(opts.get("function").value_or(""));
  if (!fc_value || *fc_value == 0 || *fc_value > 0x7F) {
    throw cli::usage_error{"--function takes a function code 1..127 (decimal or 0x..)"};
  }
  const auto slave_text = opts.get("slave");
  const auto slave = slave_text ? cli::parse_uint(*slave_text) : std::nullopt;
  if (!slave || *slave > 255) {
    throw cli::usage_error{"--slave N (0..247) is required"};
  }
  const auto fc = static_cast<std::uint8_t>(*fc_value);
  const std::uint16_t address = option16(opts, "address", 0);
  const std::vector<std::uint64_t> values =
      opts.get("values") ? parse_values(*opts.get("values")) : std::vector<std::uint64_t>{};
  std::vector<std::uint16_t> regs(values.begin(), values.end());
  const mb::span<const std::uint16_t> reg_view(regs.data(), regs.size());
  std::uint8_t pdu[mo::max_pdu_size] = {};
  mb::result<std::size_t> n = mb::errc::invalid_argument;
  switch (fc) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04: n = mo::encode_read(fc, address, option16(opts, "quantity", 1), pdu); break;
    case 0x05:
      n = mo::encode_write_single_coil(address, !values.empty() && values[0] != 0, pdu);
      break;
    case 0x06:
      n = mo::encode_write_single_register(address, regs.empty() ? 0 : regs[0], pdu);
      break;
    case 0x0F: {
      std::vector<std::uint8_t> packed((values.size() + 7) / 8, 0);
      for (std::size_t i = 0; i < values.size(); ++i) {
        if (values[i] != 0) {
          packed[i / 8] = static_cast<std::uint8_t>(packed[i / 8] | (1U << (i % 8)));
        }
      }
      n = mo::encode_write_multiple_coils(address, static_cast<std::uint16_t>(values.size()),
                                          mb::byte_view(packed.data(), packed.size()), pdu);
      break;
    }
    case 0x10: n = mo::encode_write_multiple_registers(address, reg_view, pdu); break;
    case 0x16:
      if (regs.size() != 2) {
        throw cli::usage_error{"FC 0x16 takes --values AND,OR"};
      }
      n = mo::encode_mask_write_register(address, regs[0], regs[1], pdu);
      break;
    case 0x17:
      n = mo::encode_read_write_multiple_registers(address, option16(opts, "quantity", 1),
                                                   option16(opts, "write-address", 0), reg_view,
                                                   pdu);
      break;
    default: {
      std::string hex_error;
      std::vector<std::uint8_t> data;
      if (const auto d = opts.get("data")) {
        const auto parsed = cli::parse_hex(*d, hex_error);
        if (!parsed) {
          throw cli::usage_error{"--data takes hex bytes"};
        }
        data = *parsed;
      }
      n = mo::encode_raw(fc, mb::byte_view(data.data(), data.size()), pdu);
    }
  }
  if (!n) {
    error = mb::to_string(n.error());
    return {};
  }
  std::uint8_t adu[mo::max_rtu_size] = {};
  const auto k =
      mo::encode_rtu(static_cast<std::uint8_t>(*slave), mb::byte_view(pdu, n.value()), adu);
  if (!k) {
    error = mb::to_string(k.error());
    return {};
  }
  return std::vector<std::uint8_t>(adu, adu + k.value());
}

int encode_request(const cli::options& opts) {
  std::string error;
  const auto adu = build_request(opts, error);
  if (adu.empty()) {
    return cli::finish(cli::outcome::failure(error));
  }
  cli::record f;
  f.bytes("hex", adu.data(), adu.size());
  if (const auto vcd = opts.get("vcd")) {  // the UART line at the line settings, from 1 us
    const serial::settings s = modbus_io::line_settings(opts);
    capture::channel line;
    line.name = "line";
    capture::uart_levels(adu, s.baud, s.parity, s.stop_bits, 1e-6, line);
    capture::write_vcd_file(*vcd, {line});
    f.add("vcd", *vcd);
  }
  return cli::finish(cli::outcome::success(f));
}

// read modbus: one transaction as a client; the response printed like `decode modbus response
// --request`.
int read_modbus(const cli::options& opts) {
  std::string error;
  const auto adu = build_request(opts, error);
  if (adu.empty()) {
    cli::print(cli::outcome::failure(error));
    return 1;
  }
  if (adu[0] == 0) {
    throw cli::usage_error{"read modbus needs a unicast --slave (1..247)"};
  }
  serial::port port;
  if (!modbus_io::open_port(port, opts)) {
    return 1;
  }
  const auto timeout = cli::option_number(opts, "timeout-ms", 1000, 60000);
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts, mo::report_id_format::standard);
  const auto e =
      modbus_io::transact(port, adu[0], adu.data(), adu.size(), fc11, static_cast<int>(timeout));
  if (!e.error.empty()) {
    cli::print(cli::outcome::failure(e.error));
    return 1;
  }
  std::uint8_t response[mo::max_rtu_size] = {};
  const auto k = mo::encode_rtu(adu[0], mb::byte_view(e.pdu.data(), e.pdu.size()), response);
  cli::options decode_opts;
  decode_opts.values["request"] = cli::to_hex(adu.data(), adu.size());
  decode_opts.values["fc11"] = modbus_io::fc11_name(fc11);
  const cli::outcome o = decode_response_line(cli::to_hex(response, k.value_or(0)), decode_opts);
  cli::print(o);
  return o.ok ? 0 : 1;
}

}  // namespace

namespace cli {

protocol_entries modbus_entries() {
  protocol_entries e;
  e.decoders.push_back({"decode",
                        "modbus",
                        "request",
                        "a request RTU ADU as a server sees it: slave, function, fields, CRC",
                        &decode_request_line,
                        {},
                        {}});
  e.decoders.push_back({"decode",
                        "modbus",
                        "response",
                        "a response RTU ADU as a client sees it (paired with --request if given)",
                        &decode_response_line,
                        {"request", {"fc11", "standard"}},
                        {}});
  e.commands.push_back({"encode",
                        "modbus",
                        "request",
                        "a request RTU ADU",
                        &encode_request,
                        {"function",
                         "slave",
                         {"address", "0"},
                         {"quantity", "1"},
                         "values",
                         "write-address",
                         "data",
                         "vcd",
                         {"baud", "9600"},
                         {"parity", "E"},
                         {"stop-bits", "1"}},
                        {},
                        {}});
  e.commands.push_back({"read",
                        "modbus",
                        "",
                        "one request to a Modbus RTU server and its response, decoded",
                        &read_modbus,
                        {"device",
                         "slave",
                         "function",
                         {"address", "0"},
                         {"quantity", "1"},
                         "values",
                         "write-address",
                         "data",
                         {"baud", "9600"},
                         {"parity", "E"},
                         {"stop-bits", "1"},
                         {"timeout-ms", "1000"},
                         {"fc11", "standard"}},
                        {},
                        {}});
  return e;
}

}  // namespace cli
