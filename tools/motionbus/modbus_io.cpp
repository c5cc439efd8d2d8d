// Modbus RTU pieces shared by the CLI's commands (decode, read, serve, monitor): records of
// requests and responses, transactions on a serial port, line settings.
#include "modbus_io.hpp"

#include <motionbus/modbus.hpp>
#include <motionbus/modbus/framer.hpp>

#include <iostream>
#include <string>
#include <vector>

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

}  // namespace

namespace modbus_io {

namespace {

// The response `rx` frames from what the port delivers within `timeout_ms`. `silence_ends`:
// 20 ms of silence ends what the framer holds (RTU: far more than t3.5); ASCII frames carry
// their own end, and a pause inside one is no error (Serial Line §2.5.2.2: up to 1 s).
template <class Framer>
exchange await_response(serial::port& port, Framer& rx, int timeout_ms, bool silence_ends) {
  const std::uint32_t deadline = serial::now_us() + static_cast<std::uint32_t>(timeout_ms) * 1000U;
  std::uint8_t buffer[256];
  std::string failure;
  while (static_cast<std::int32_t>(deadline - serial::now_us()) > 0) {
    const long n = port.read_some(buffer, sizeof buffer, 20);
    if (n < 0) {
      return {{}, "read_error"};
    }
    if (n == 0 && silence_ends && rx.pending() > 0) {
      const auto r = rx.idle();
      if (r.is_complete()) {
        return {std::vector<std::uint8_t>(r->pdu.begin(), r->pdu.end()), {}};
      }
      if (r.is_failed()) {  // the silence ended a bad frame: e.g. truncated, crc_mismatch
        return {{}, mb::to_string(r.error())};
      }
      continue;  // only a frame for another address
    }
    std::vector<std::uint8_t> pdu;
    bool framed = false;
    mb::feed_all(rx, mb::byte_view(buffer, static_cast<std::size_t>(n)), [&](const auto& r) {
      if (r.is_complete()) {
        pdu.assign(r->pdu.begin(), r->pdu.end());
        framed = true;
      } else {
        failure = mb::to_string(r.error());  // a valid frame may still follow
      }
      return !framed;
    });
    if (framed) {
      return {pdu, {}};
    }
  }
  // nothing valid in time: what was wrong with what came, else nothing came
  return {{}, failure.empty() ? "timeout" : failure};
}

}  // namespace

exchange transact(serial::port& port, std::uint8_t slave, const std::uint8_t* adu, std::size_t size,
                  mo::report_id_format fc11, int timeout_ms) {
  port.flush_input();
  if (!port.write_all(adu, size)) {
    return {{}, "write_error"};
  }
  mo::framer_options options{slave};
  options.fc11 = fc11;
  mo::rtu_client_framer rx(options);
  rx.sent(mb::byte_view(adu, size));
  return await_response(port, rx, timeout_ms, true);
}

exchange transact_ascii(serial::port& port, std::uint8_t slave, mb::byte_view pdu, int timeout_ms) {
  std::uint8_t adu[mo::max_ascii_size] = {};
  const mb::result<std::size_t> n = mo::encode_ascii(slave, pdu, adu);
  if (!n) {
    return {{}, mb::to_string(n.error())};
  }
  port.flush_input();
  if (!port.write_all(adu, n.value())) {
    return {{}, "write_error"};
  }
  mo::ascii_framer rx(mo::framer_role::client, mo::ascii_options{slave, '\n'});
  rx.sent(mb::byte_view(adu, n.value()));
  return await_response(port, rx, timeout_ms, false);
}

mo::report_id_format fc11_of(const std::string& name) {
  const std::string* v = &name;
  if (*v == "standard") {
    return mo::report_id_format::standard;
  }
  if (*v == "sm") {
    return mo::report_id_format::two_bytes_no_count;
  }
  throw cli::usage_error{"--fc11 is standard (byte count, then data) or sm (two version bytes)"};
}

const char* fc11_name(mo::report_id_format f) {
  return f == mo::report_id_format::two_bytes_no_count ? "sm" : "standard";
}

void print_served(const mo::rtu_frame& request, const std::uint8_t* reply, std::size_t size,
                  std::uint64_t time_us) {
  cli::outcome o = describe_request(request);
  cli::record& r = o.ok ? o.fields : o.evidence;
  if (size > 0) {
    r.bytes("answer", reply, size);
  } else {
    r.add("answer", "none");
  }
  cli::record at;
  at.add("time_us", time_us);
  cli::print(o, at);
  std::cout.flush();
}

std::string exception_name(std::uint8_t code) {
  switch (static_cast<mo::exception_code>(code)) {
    case mo::exception_code::illegal_function: return "illegal_function";
    case mo::exception_code::illegal_data_address: return "illegal_data_address";
    case mo::exception_code::illegal_data_value: return "illegal_data_value";
    case mo::exception_code::server_device_failure: return "server_device_failure";
    case mo::exception_code::acknowledge: return "acknowledge";
    case mo::exception_code::server_device_busy: return "server_device_busy";
    case mo::exception_code::memory_parity_error: return "memory_parity_error";
    case mo::exception_code::gateway_path_unavailable: return "gateway_path_unavailable";
    case mo::exception_code::gateway_target_failed: return "gateway_target_failed";
  }
  return "unknown";
}

std::string sm_version_text(std::uint8_t upper, std::uint8_t lower) {
  return std::to_string(upper) + "." + std::to_string(lower >> 4U) + "." +
         std::to_string(lower & 0x0FU);
}

mo::parity parity_of(const serial::settings& s) {
  return s.parity == 'N' ? mo::parity::none
                         : (s.parity == 'O' ? mo::parity::odd : mo::parity::even);
}

cli::outcome describe_request(const mo::rtu_frame& frame) {
  const mo::rtu_frame* adu = &frame;
  const auto q = mo::decode_request(adu->pdu);
  if (!q.is_complete()) {
    return cli::failure_of(q, 2);
  }
  cli::record f;
  f.add("slave", adu->slave);
  f.hex("function", q->function);
  const std::uint8_t fc = q->function;
  if (fc <= 0x06 || fc == 0x0F || fc == 0x10 || fc == 0x16 || fc == 0x17) {
    f.hex("address", q->address, 4);
  }
  if (fc <= 0x04 || fc == 0x0F || fc == 0x10 || fc == 0x17) {
    f.add("quantity", q->quantity);
  }
  if (fc == 0x05 || fc == 0x06) {
    f.add("value", q->value);
  }
  if (fc == 0x16) {
    f.hex("and_mask", q->and_mask, 4);
    f.hex("or_mask", q->or_mask, 4);
  }
  if (fc == 0x17) {
    f.hex("write_address", q->write_address, 4);
    f.add("write_quantity", q->write_quantity);
  }
  if (fc == 0x0F) {
    f.add("byte_count", q->data.size());
    f.add("values", bits_of(q->data, q->quantity));
  } else if (fc == 0x10 || fc == 0x17) {
    f.add("byte_count", q->data.size());
    f.add("values", registers_of(q->data));
  } else if (!q->data.empty()) {
    f.bytes("data", q->data.data(), q->data.size());
  }
  f.hex("crc", adu->crc, 4);
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
      e.add("expected_slave", request_adu->slave).add("received_slave", adu->slave);
      return cli::outcome::failure(mb::to_string(mb::errc::modbus_mismatch), e);
    }
    const auto q = mo::decode_request(request_adu->pdu);
    if (q.is_complete()) {
      request = q.value();
    }
    r = mo::decode_response_for(request_adu->pdu, pdu, fc11);
  } else {
    r = mo::decode_response_unpaired(pdu, fc11);  // no request: what the response carries
  }
  if (!r.is_complete()) {
    return cli::failure_of(r, 2);
  }
  cli::record f;
  f.add("slave", adu->slave);
  const std::uint8_t fc = r->function;
  f.hex("function", fc);
  if (r->exception) {
    f.hex("exception", r->exception_code);
    f.add("exception_name", modbus_io::exception_name(r->exception_code));
  } else if (fc <= 0x04 || fc == 0x17) {
    f.add("byte_count", r->byte_count);
    if (fc <= 0x02) {
      f.add("values", bits_of(r->data, request ? request->quantity : r->data.size() * 8U));
    } else {
      f.add("values", registers_of(r->data));
    }
  } else if (fc == 0x05 || fc == 0x06 || fc == 0x0F || fc == 0x10) {
    f.hex("address", r->address, 4);
    f.add(fc <= 0x06 ? "value" : "quantity", fc <= 0x06 ? r->value : r->quantity);
  } else if (fc == 0x16) {
    f.hex("address", r->address, 4);
    f.hex("and_mask", r->and_mask, 4);
    f.hex("or_mask", r->or_mask, 4);
  } else if (fc == 0x11 && fc11 == mo::report_id_format::two_bytes_no_count) {
    // the SM unit's layout: version upper, version lower (SM unit guideline §11)
    f.add("version_upper", r->data[0]);
    f.add("version_lower", r->data[1]);
    f.add("version", modbus_io::sm_version_text(r->data[0], r->data[1]));
  } else {
    // FC11 (standard layout: byte count, then the device's bytes) and the other functions:
    // the data part as hex
    f.bytes("data", pdu.data() + 1, pdu.size() - 1);
  }
  f.hex("crc", adu->crc, 4);
  return cli::outcome::success(f);
}

}  // namespace modbus_io
