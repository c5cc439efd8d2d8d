// motionbus gateway --listen ADDR:PORT --device PATH [line options] [--rtu-over-tcp] [...]:
// Modbus TCP clients to one Modbus RTU serial line, through the library's gateway core
// (modbus/gateway.hpp, docs/modbus.md section 12). The core decides everything (ids, the
// queue, the checks, 0A/0B, what closes a connection); this file is its I/O: an Asio event
// loop with the listening socket, up to 8 client sockets, the serial line (a POSIX stream
// descriptor on the port libserialport opened) and one timer for the core's wait_us(), one
// per client for the idle timeout. One line printed per transaction (text or --json).
#include <motionbus/core/errc.hpp>
#include <motionbus/core/stream.hpp>
#include <motionbus/modbus/framer.hpp>
#include <motionbus/modbus/gateway.hpp>
#include <motionbus/modbus/rtu.hpp>
#include <motionbus/modbus/tcp.hpp>

#include <asio.hpp>

#ifndef _WIN32  // the serial port joins the loop as a POSIX descriptor
#include <termios.h>
#include <unistd.h>
#endif

#include <array>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "modbus_io.hpp"
#include "options.hpp"
#include "serial.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
using asio::ip::tcp;

namespace {

constexpr std::size_t max_connections = 8;  // mo::gateway's
using rtu_over_tcp_framer = mo::basic_rtu_framer<mb::default_crc_table, mo::framer_role::server>;

// The core's options from the command's.
mo::gateway_options core_options(const cli::gateway_options& o) {
  mo::gateway_options g;
  g.response_timeout_us = o.timeout_ms * 1000U;
  g.turnaround_us = o.turnaround_ms * 1000U;
  const serial::settings s = o.line.settings();
  g.line = mo::serial_line_timing(s.baud, modbus_io::parity_of(s), s.stop_bits);
  if (o.units) {
    g.units = mo::unit_set::none();
    for (const std::uint8_t u : cli::number_list("units", *o.units, 0, 247)) {
      g.units.add(u);
    }
  }
  if (o.functions) {
    g.functions = 0;
    for (const std::uint8_t f : cli::number_list("functions", *o.functions, 1, 63)) {
      g.functions |= mo::function_set{1} << f;
    }
  }
  g.read_only = o.read_only;
  g.answer_broadcasts = o.answer_broadcasts;
  g.fc11 = modbus_io::fc11_of(o.fc11);
  return g;
}

#ifndef _WIN32
class gateway_loop {
 public:
  gateway_loop(const cli::gateway_options& o, int line_fd)
      : opts_(o),
        gw_(core_options(o)),
        acceptor_(io_),
        line_(io_, ::dup(line_fd)),
        timer_(io_),
        signals_(io_, SIGINT, SIGTERM) {
    for (std::size_t i = 0; i < max_connections; ++i) {
      clients_[i].idle = std::make_unique<asio::steady_timer>(io_);
    }
  }

  // Binds and listens; false (said on stderr) when it cannot.
  bool listen(const cli::endpoint& at) {
    std::error_code ec;
    const asio::ip::address address = asio::ip::make_address(at.host, ec);
    if (ec) {
      std::cerr << "motionbus: --listen " << at.host << ": not an IP address\n";
      return false;
    }
    const tcp::endpoint ep(address, at.port);
    acceptor_.open(ep.protocol(), ec);
    if (!ec) {
      acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
      acceptor_.bind(ep, ec);
    }
    if (!ec) {
      acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    }
    if (ec) {
      std::cerr << "motionbus: cannot listen on " << at.text() << ": " << ec.message() << '\n';
      return false;
    }
    return true;
  }

  int run() {
    const tcp::endpoint local = acceptor_.local_endpoint();
    cli::record start;
    start.add("listening", local.address().to_string() + ":" + std::to_string(local.port()));
    start.add("device", opts_.line.device);
    start.add("framing", opts_.rtu_over_tcp ? "rtu_over_tcp" : "mbap");
    cli::print_record(start);
    std::cout.flush();
    signals_.async_wait([this](const std::error_code&, int) { io_.stop(); });
    accept();
    read_line();
    io_.run();
    return 0;
  }

 private:
  struct client {
    std::unique_ptr<tcp::socket> socket;
    std::unique_ptr<asio::steady_timer> idle;
    std::array<std::uint8_t, 512> in{};
    std::string peer;
    std::uint32_t serial = 0;                   // which connection this slot holds (reuse)
    std::optional<rtu_over_tcp_framer> framer;  // --rtu-over-tcp
    std::uint16_t next_transaction = 0;         // --rtu-over-tcp: the ids given to its requests
  };

  std::uint32_t now() const { return serial::now_us(); }

  void accept() {
    acceptor_.async_accept([this](const std::error_code& ec, tcp::socket s) {
      if (!ec) {
        admit(std::move(s));
      }
      accept();
    });
  }

  void admit(tcp::socket s) {
    std::error_code ec;
    const tcp::endpoint peer = s.remote_endpoint(ec);
    const std::string name =
        ec ? "?" : peer.address().to_string() + ":" + std::to_string(peer.port());
    std::size_t c = 0;
    while (c < opts_.max_clients && clients_[c].socket) {
      ++c;
    }
    if (c == opts_.max_clients) {
      log_connection("refused", name, c, "client_limit");
      s.close(ec);
      return;
    }
    client& k = clients_[c];
    k.socket = std::make_unique<tcp::socket>(std::move(s));
    k.socket->set_option(tcp::no_delay(true), ec);
    k.peer = name;
    ++k.serial;
    k.next_transaction = 0;
    if (opts_.rtu_over_tcp) {
      mo::framer_options f;
      f.address = 1;
      f.last_address = mo::max_unicast_address;
      f.ends = mo::frame_end::length;
      k.framer.emplace(f);
    }
    log_connection("connected", name, c, "");
    arm_idle(c);
    read_client(c);
  }

  void arm_idle(std::size_t c) {
    client& k = clients_[c];
    k.idle->expires_after(std::chrono::milliseconds(opts_.idle_timeout_ms));
    const std::uint32_t serial = k.serial;
    k.idle->async_wait([this, c, serial](const std::error_code& ec) {
      if (!ec && clients_[c].socket && clients_[c].serial == serial) {
        gw_.close(c);
        drop(c, "idle_timeout");
      }
    });
  }

  void read_client(std::size_t c) {
    client& k = clients_[c];
    const std::uint32_t serial = k.serial;
    k.socket->async_read_some(asio::buffer(k.in),
                              [this, c, serial](const std::error_code& ec, std::size_t n) {
                                client& self = clients_[c];
                                if (!self.socket || self.serial != serial) {
                                  return;  // closed meanwhile
                                }
                                if (ec) {
                                  gw_.close(c);
                                  drop(c, ec == asio::error::eof ? "" : "read_error");
                                  return;
                                }
                                arm_idle(c);
                                take_client(c, mb::byte_view(self.in.data(), n));
                                if (clients_[c].socket && clients_[c].serial == serial) {
                                  read_client(c);
                                }
                                settle();
                              });
  }

  // A client's bytes to the core: as they are (MBAP), or framed as RTU ADUs first, each made
  // an MBAP request with an id of the connection's own (--rtu-over-tcp).
  void take_client(std::size_t c, mb::byte_view in) {
    client& k = clients_[c];
    const auto act = [this](const mo::gateway_step& s) { do_step(s); };
    if (!k.framer) {
      mo::feed_client(gw_, c, in, act);
      return;
    }
    const std::uint32_t serial = k.serial;
    (void)mb::feed_all(*k.framer, in, [&](const auto& r) {
      if (!r.is_complete()) {
        cli::record e;
        e.add("event", "discarded").add("connection", c).add("peer", k.peer);
        e.add("error", mb::to_string(r.error()));
        cli::print_record(e);
        return true;
      }
      std::uint8_t adu[mo::max_tcp_size] = {};
      const auto n = mo::encode_tcp(k.next_transaction++, r.value().slave, r.value().pdu, adu);
      if (n) {
        mo::feed_client(gw_, c, mb::byte_view(adu, n.value()), act);
      }
      return clients_[c].socket != nullptr && clients_[c].serial == serial;
    });
  }

  void read_line() {
    line_.async_read_some(asio::buffer(line_in_), [this](const std::error_code& ec, std::size_t n) {
      if (ec) {
        std::cerr << "motionbus: " << opts_.line.device << ": " << ec.message() << '\n';
        status_ = 1;
        io_.stop();
        return;
      }
      mo::feed_line(gw_, mb::byte_view(line_in_.data(), n), now(),
                    [this](const mo::gateway_step& s) { do_step(s); });
      settle();
      read_line();
    });
  }

  // What is due now, then the timer for what is due next.
  void settle() {
    mo::poll_all(gw_, now(), [this](const mo::gateway_step& s) { do_step(s); });
    const std::uint32_t wait = gw_.wait_us(now());
    timer_.cancel();
    if (wait == ~std::uint32_t{0}) {
      return;
    }
    timer_.expires_after(std::chrono::microseconds(wait));
    timer_.async_wait([this](const std::error_code& ec) {
      if (!ec) {
        settle();
      }
    });
  }

  void do_step(const mo::gateway_step& s) {
    switch (s.action) {
      case mo::gateway_action::to_line: {
        std::error_code ec;
        asio::write(line_, asio::buffer(s.bytes.data(), s.bytes.size()), ec);
        if (ec) {
          std::cerr << "motionbus: " << opts_.line.device << ": write: " << ec.message() << '\n';
          status_ = 1;
          io_.stop();
        }
        started_[s.connection] = now();
        break;
      }
      case mo::gateway_action::to_client: send(s); break;
      case mo::gateway_action::close: drop(s.connection, mb::to_string(s.error)); break;
      default: break;
    }
  }

  // A response to its client (as RTU under --rtu-over-tcp), and its line in the log.
  void send(const mo::gateway_step& s) {
    const std::size_t c = s.connection;
    client& k = clients_[c];
    const mb::byte_view adu = s.bytes;  // MBAP: transaction, protocol, length, unit, PDU
    const std::uint8_t unit = adu[6];
    const mb::byte_view pdu = adu.subspan(7);
    log_transaction(s, unit, pdu);
    if (!k.socket) {
      return;
    }
    auto out = std::make_shared<std::vector<std::uint8_t>>();
    if (k.framer) {
      std::uint8_t rtu[mo::max_rtu_size] = {};
      const auto n = mo::encode_rtu(unit, pdu, rtu);
      out->assign(rtu, rtu + n.value_or(0));
    } else {
      out->assign(adu.begin(), adu.end());
    }
    const std::uint32_t serial = k.serial;
    asio::async_write(*k.socket, asio::buffer(*out),
                      [this, out, c, serial](const std::error_code& ec, std::size_t) {
                        if (ec && clients_[c].socket && clients_[c].serial == serial) {
                          gw_.close(c);
                          drop(c, "write_error");
                        }
                      });
  }

  void log_transaction(const mo::gateway_step& s, std::uint8_t unit, mb::byte_view pdu) {
    cli::record r;
    r.add("event", "transaction").add("connection", s.connection);
    r.add("peer", clients_[s.connection].peer).add("transaction", s.transaction);
    r.add("unit", unit).hex("function", pdu[0] & 0x7FU);
    if ((pdu[0] & mo::exception_flag) != 0U && pdu.size() >= 2U) {
      r.hex("exception", pdu[1]).add("exception_name", modbus_io::exception_name(pdu[1]));
      r.add("by", s.exception != 0U ? "gateway" : "device");
    }
    r.bytes("response", pdu.data(), pdu.size());
    if (s.exception == 0U || s.exception == 0x0BU) {
      r.add("line_us", now() - started_[s.connection]);
    }
    cli::print_record(r);
    std::cout.flush();
  }

  void log_connection(const char* event, const std::string& peer, std::size_t c,
                      const std::string& why) {
    cli::record r;
    r.add("event", event).add("connection", c).add("peer", peer);
    if (!why.empty()) {
      r.add("reason", why);
    }
    cli::print_record(r);
    std::cout.flush();
  }

  // Closes slot `c`'s socket (the core has dropped it, or is told here).
  void drop(std::size_t c, const std::string& why) {
    client& k = clients_[c];
    if (!k.socket) {
      return;
    }
    std::error_code ec;
    k.socket->shutdown(tcp::socket::shutdown_both, ec);
    k.socket->close(ec);
    k.socket.reset();
    k.idle->cancel();
    k.framer.reset();
    log_connection("closed", k.peer, c, why);
  }

  const cli::gateway_options& opts_;
  mo::gateway gw_;
  asio::io_context io_;
  tcp::acceptor acceptor_;
  asio::posix::stream_descriptor line_;
  asio::steady_timer timer_;
  asio::signal_set signals_;
  std::array<client, max_connections> clients_{};
  std::array<std::uint8_t, 256> line_in_{};
  std::array<std::uint32_t, 256> started_{};
  int status_ = 0;

 public:
  int status() const { return status_; }
};

int run_gateway(const cli::gateway_options& opts) {
  const cli::endpoint at = cli::endpoint_of("listen", opts.listen);
  (void)core_options(opts);  // the lists checked before anything opens
  serial::port port;
  if (!opts.line.open(port)) {
    return 1;
  }
  if (port.native_handle() < 0) {
    std::cerr << "motionbus: " << opts.line.device << ": no file descriptor to wait on\n";
    return 1;
  }
  // A read returns once a byte is in (VMIN 1): with VMIN 0, as the port is opened for polled
  // reads, a non-blocking read of nothing returns 0, which Asio takes for the end of file.
  termios t{};
  if (::tcgetattr(port.native_handle(), &t) == 0) {
    t.c_cc[VMIN] = 1;
    t.c_cc[VTIME] = 0;
    (void)::tcsetattr(port.native_handle(), TCSANOW, &t);
  }
  auto loop = std::make_unique<gateway_loop>(opts, port.native_handle());
  if (!loop->listen(at)) {
    return 1;
  }
  loop->run();
  return loop->status();
}
#else
int run_gateway(const cli::gateway_options& opts) {
  (void)core_options(opts);
  std::cerr << "motionbus: gateway needs a POSIX host (its serial port in the event loop)\n";
  return 1;
}
#endif

}  // namespace

namespace cli {

protocol_entries gateway_entries() {
  protocol_entries e;
  e.typed.push_back(cli::typed("gateway", "", "",
                               "Modbus TCP clients (MBAP, or RTU over TCP) to a Modbus RTU "
                               "serial line: ids mapped, one request on the line at a time",
                               &run_gateway));
  return e;
}

}  // namespace cli
