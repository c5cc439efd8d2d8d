// motionbus serve modbus (--device PATH [line options] [--ascii] | --tcp-listen ADDR:PORT)
// [--units LIST] [--points N]: a generic Modbus server, one device per unit address, through the
// library's dispatch (modbus/server.hpp: serve_units on an RTU line, serve_pdu over Modbus TCP).
// Each unit u has --points coils, discrete inputs, holding and input registers at 0..points-1:
// coils and holding registers as written (0 at start), discrete input i on when i % 3 == 0,
// input register i reading 1000 * u + i (modulo 65536), so that units answer as different
// devices; FC11 reports server id 0x4D, run 0xFF, "motionbus" and the unit. Functions 01-06,
// 0F, 10, 11, 16, 17; any other is answered with exception 01, an address past the points 02.
#include <motionbus/core/errc.hpp>
#include <motionbus/core/stream.hpp>
#include <motionbus/modbus.hpp>
#include <motionbus/modbus/framer.hpp>
#include <motionbus/modbus/server.hpp>
#include <motionbus/modbus/tcp.hpp>

#include <asio.hpp>

#include <array>
#include <cstdint>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "modbus_io.hpp"
#include "options_bind.hpp"
#include "serial.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
using asio::ip::tcp;

namespace {

class generic_device {
 public:
  generic_device(std::uint8_t unit, std::size_t points)
      : unit_(unit), coils_(points, false), holding_(points, 0) {}

  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) const {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      const std::size_t a = std::size_t{address} + i;
      if (function == 0x01 ? coils_[a] : a % 3U == 0U) {
        packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (1U << (i % 8U)));
      }
    }
    return 0;
  }
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              mb::span<std::uint16_t> out) const {
    if (!fits(address, out.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = function == 0x04 ? static_cast<std::uint16_t>(1000U * unit_ + address + i)
                                : holding_[address + i];
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, mb::byte_view packed) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      coils_[std::size_t{address} + i] = mo::bit_at(packed, i);
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    if (!fits(address, values.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      holding_[address + i] = values[i];
    }
    return 0;
  }
  std::uint8_t report_server_id(mb::mutable_byte_view out, std::size_t& size) const {
    const std::string id = std::string("\x4D\xFF") + "motionbus unit " + std::to_string(unit_);
    out[0] = static_cast<std::uint8_t>(id.size());
    for (std::size_t i = 0; i < id.size(); ++i) {
      out[1U + i] = static_cast<std::uint8_t>(id[i]);
    }
    size = 1U + id.size();
    return 0;
  }

 private:
  bool fits(std::uint16_t address, std::size_t quantity) const {
    return std::size_t{address} + quantity <= holding_.size();
  }
  std::uint8_t unit_;
  std::vector<bool> coils_;
  std::vector<std::uint16_t> holding_;
};

struct serve_modbus_options {
  cli::serial_line line = cli::serial_line::modbus();
  std::optional<std::string> tcp_listen;
  std::string units = "1";
  std::uint32_t points = 100;
  bool ascii = false;  // Modbus ASCII on the serial line
  void bind(CLI::App& app) {
    cli::flag(app, "ascii", ascii);
    cli::text(app, "device", line.device);  // required unless --tcp-listen
    line.bind_settings(app);
    cli::text(app, "tcp-listen", tcp_listen);
    cli::text(app, "units", units);
    cli::number(app, "points", points, 1, 65536);
  }
};

// The devices by unit (the unit list's; 1..247).
using devices = std::map<std::uint8_t, generic_device>;

generic_device* device_of(devices& d, std::uint8_t unit) {
  const auto it = d.find(unit);
  return it == d.end() ? nullptr : &it->second;
}

// What was served, one line: the transport's request, the unit, the response PDU.
void log_served(std::uint8_t unit, mb::byte_view request, mb::byte_view response,
                const std::string& peer) {
  cli::record r;
  if (!peer.empty()) {
    r.add("peer", peer);
  }
  r.add("unit", unit).hex("function", request.empty() ? 0U : request[0]);
  r.bytes("request", request.data(), request.size());
  if (response.empty()) {
    r.add("answer", "none");
  } else {
    r.bytes("answer", response.data(), response.size());
  }
  cli::print_record(r);
  std::cout.flush();
}

// Modbus ASCII (Serial Line §2.5.2): every frame on the line, by the ASCII framer as a listener
// (its server role takes one address), served by the unit's device if there is one; a
// broadcast is executed by every unit's device and not answered.
int serve_ascii(serial::port& port, devices& units) {
  mo::ascii_framer rx(mo::framer_role::listener);
  std::uint8_t buffer[256];
  while (!serial::stop_requested()) {
    const long n = port.read_some(buffer, sizeof buffer, 100);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      return 1;
    }
    bool ok = true;
    (void)mb::feed_all(rx, mb::byte_view(buffer, static_cast<std::size_t>(n)), [&](const auto& r) {
      if (!r.is_complete()) {
        return true;  // a bad frame (LRC, a character): no answer, as the spec has it
      }
      const mo::ascii_frame f = r.value();
      std::uint8_t pdu[mo::max_pdu_size] = {};
      std::size_t size = 0;
      if (f.broadcast()) {
        for (auto& u : units) {
          (void)mo::serve_pdu(u.second, f.pdu, pdu);
        }
      } else if (generic_device* dev = device_of(units, f.slave)) {
        size = mo::serve_pdu(*dev, f.pdu, pdu).value_or(0);
      }
      std::uint8_t out[mo::max_ascii_size] = {};
      const std::size_t k =
          size > 0 ? mo::encode_ascii(f.slave, mb::byte_view(pdu, size), out).value_or(0) : 0;
      if (k > 0 && !port.write_all(out, k)) {
        std::cerr << "motionbus: write error\n";
        ok = false;
        return false;
      }
      log_served(f.slave, f.pdu, mb::byte_view(pdu, size), "");
      return true;
    });
    if (!ok) {
      return 1;
    }
  }
  return 0;
}

int serve_line(const serve_modbus_options& opts, devices& units) {
  serial::port port;
  if (!opts.line.open(port)) {
    return 1;
  }
  serial::install_stop_handler();
  if (opts.ascii) {
    return serve_ascii(port, units);
  }
  mo::framer_options f;
  f.address = units.begin()->first;
  f.last_address = units.rbegin()->first;  // the range; serve_units answers the units it has
  mo::rtu_framer rx(mo::framer_role::server, f);
  const serial::settings s = opts.line.settings();
  const int silence_ms =
      static_cast<int>((mo::t35_us(s.baud, modbus_io::parity_of(s), s.stop_bits) + 999U) / 1000U) +
      4;  // the OS adds its own delays
  std::uint8_t buffer[256];
  while (!serial::stop_requested()) {
    const long n = port.read_some(buffer, sizeof buffer, rx.pending() > 0 ? silence_ms : 100);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      return 1;
    }
    const auto handle = [&](const auto& r) {
      if (!r.is_complete()) {
        return true;
      }
      std::uint8_t out[mo::max_rtu_size] = {};
      std::size_t size = 0;
      if (r.value().broadcast()) {
        // executed by every unit's device, never answered (as on ASCII); serve_units asks its
        // lookup for unit 0, which no unit is (issue 28's soak: broadcasts were not executed)
        for (auto& u : units) {
          (void)mo::serve_units([&](std::uint8_t) { return &u.second; }, r.value(), out);
        }
      } else {
        size = mo::serve_units([&](std::uint8_t u) { return device_of(units, u); }, r.value(), out)
                   .value_or(0);
      }
      if (size > 0 && !port.write_all(out, size)) {
        std::cerr << "motionbus: write error\n";
        return false;
      }
      log_served(r.value().slave, r.value().pdu,
                 size > 0 ? mb::byte_view(out + 1, size - 3U) : mb::byte_view{}, "");
      return true;
    };
    if (n == 0) {
      if (rx.pending() > 0) {
        (void)handle(rx.idle());
      }
      continue;
    }
    (void)mb::feed_all(rx, mb::byte_view(buffer, static_cast<std::size_t>(n)), handle);
  }
  return 0;
}

// Modbus TCP: each connection's MBAP ADUs served in order (serve_pdu); a unit with no device
// gets no answer (as on a line); a header that breaks the framing closes the connection.
class tcp_server {
 public:
  explicit tcp_server(devices& units)
      : units_(units), acceptor_(io_), signals_(io_, SIGINT, SIGTERM) {}

  int run(const cli::endpoint& at) {
    std::error_code ec;
    const tcp::endpoint ep(asio::ip::make_address(at.host, ec), at.port);
    if (!ec) {
      acceptor_.open(ep.protocol(), ec);
    }
    if (!ec) {
      acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
      acceptor_.bind(ep, ec);
    }
    if (!ec) {
      acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    }
    if (ec) {
      std::cerr << "motionbus: cannot listen on " << at.text() << ": " << ec.message() << '\n';
      return 1;
    }
    const tcp::endpoint local = acceptor_.local_endpoint();
    cli::record start;
    start.add("listening", local.address().to_string() + ":" + std::to_string(local.port()));
    cli::print_record(start);
    std::cout.flush();
    signals_.async_wait([this](const std::error_code&, int) { io_.stop(); });
    accept();
    io_.run();
    return 0;
  }

 private:
  struct connection {
    explicit connection(tcp::socket s) : socket(std::move(s)) {}
    tcp::socket socket;
    std::array<std::uint8_t, 512> in{};
    std::vector<std::uint8_t> held;
    std::string peer;
  };

  void accept() {
    acceptor_.async_accept([this](const std::error_code& ec, tcp::socket s) {
      if (!ec) {
        auto c = std::make_shared<connection>(std::move(s));
        std::error_code e;
        const tcp::endpoint p = c->socket.remote_endpoint(e);
        c->peer = e ? "?" : p.address().to_string() + ":" + std::to_string(p.port());
        read(c);
      }
      accept();
    });
  }

  void read(const std::shared_ptr<connection>& c) {
    c->socket.async_read_some(
        asio::buffer(c->in), [this, c](const std::error_code& ec, std::size_t n) {
          if (ec) {
            return;  // closed: the shared_ptr goes with the handler
          }
          c->held.insert(c->held.end(), c->in.begin(), c->in.begin() + static_cast<long>(n));
          for (;;) {
            const auto size = mo::tcp_adu_size(mb::byte_view(c->held.data(), c->held.size()));
            if (size.is_failed()) {
              std::error_code e;
              c->socket.close(e);
              return;
            }
            if (!size.is_complete() || c->held.size() < size.value()) {
              break;
            }
            serve(*c, mb::byte_view(c->held.data(), size.value()));
            c->held.erase(c->held.begin(), c->held.begin() + static_cast<long>(size.value()));
          }
          read(c);
        });
  }

  void serve(connection& c, mb::byte_view adu) {
    const auto t = mo::decode_tcp(adu).value();
    std::uint8_t pdu[mo::max_pdu_size] = {};
    generic_device* dev = device_of(units_, t.unit);
    const std::size_t n = dev != nullptr ? mo::serve_pdu(*dev, t.pdu, pdu).value_or(0) : 0U;
    log_served(t.unit, t.pdu, mb::byte_view(pdu, n), c.peer);
    if (n == 0U) {
      return;
    }
    std::uint8_t out[mo::max_tcp_size] = {};
    const std::size_t k =
        mo::encode_tcp(t.transaction, t.unit, mb::byte_view(pdu, n), out).value_or(0);
    std::error_code ec;
    asio::write(c.socket, asio::buffer(out, k), ec);
  }

  devices& units_;
  asio::io_context io_;
  tcp::acceptor acceptor_;
  asio::signal_set signals_;
};

int serve_modbus(const serve_modbus_options& opts) {
  devices units;
  for (const std::uint8_t u : cli::number_list("units", opts.units, 1, 247)) {
    units.emplace(u, generic_device(u, opts.points));
  }
  if (opts.tcp_listen) {
    if (!opts.line.device.empty() || opts.ascii) {
      throw cli::usage_error{"--tcp-listen is instead of --device (and --ascii)"};
    }
    const cli::endpoint at = cli::endpoint_of("tcp-listen", *opts.tcp_listen);
    return tcp_server(units).run(at);
  }
  return serve_line(opts, units);
}

}  // namespace

namespace cli {

protocol_entries serve_modbus_entries() {
  protocol_entries e;
  e.typed.push_back(cli::typed("serve", "modbus", "",
                               "a generic Modbus server (coils, inputs, registers) on a serial "
                               "line or Modbus TCP, one device per unit address",
                               &serve_modbus));
  return e;
}

}  // namespace cli
