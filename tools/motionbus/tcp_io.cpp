// Modbus TCP client transactions on standalone Asio (tcp_io.hpp).
#include "tcp_io.hpp"

#include <motionbus/core/errc.hpp>
#include <motionbus/modbus/tcp.hpp>

#include <asio.hpp>

#include <chrono>
#include <vector>

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace tcp_io {

modbus_io::exchange transact(const cli::endpoint& to, std::uint8_t unit, mb::byte_view pdu,
                             std::uint16_t transaction, int timeout_ms) {
  modbus_io::exchange out;
  std::uint8_t request[mo::max_tcp_size] = {};
  const mb::result<std::size_t> n = mo::encode_tcp(transaction, unit, pdu, request);
  if (!n) {
    out.error = mb::to_string(n.error());
    return out;
  }
  asio::io_context io;
  asio::ip::tcp::socket socket(io);
  std::vector<std::uint8_t> response(mo::max_tcp_size);
  std::size_t held = 0;
  std::string error = "timeout";
  asio::ip::tcp::resolver resolver(io);
  std::error_code ec;
  const auto endpoints = resolver.resolve(to.host, std::to_string(to.port), ec);
  if (ec) {
    out.error = "connect_error";
    return out;
  }
  // Reads until the ADU its header announces is whole (tcp_adu_size).
  std::function<void()> read_more = [&] {
    socket.async_read_some(asio::buffer(response.data() + held, response.size() - held),
                           [&](const std::error_code& e, std::size_t got) {
                             if (e) {
                               error = "read_error";
                               io.stop();
                               return;
                             }
                             held += got;
                             const auto size =
                                 mo::tcp_adu_size(mb::byte_view(response.data(), held));
                             if (size.is_failed()) {
                               error = mb::to_string(size.error());
                               io.stop();
                             } else if (size.is_complete() && held >= size.value()) {
                               held = size.value();
                               error.clear();
                               io.stop();
                             } else {
                               read_more();
                             }
                           });
  };
  asio::async_connect(socket, endpoints, [&](const std::error_code& e, const auto&) {
    if (e) {
      error = "connect_error";
      io.stop();
      return;
    }
    asio::async_write(socket, asio::buffer(request, n.value()),
                      [&](const std::error_code& w, std::size_t) {
                        if (w) {
                          error = "write_error";
                          io.stop();
                          return;
                        }
                        read_more();
                      });
  });
  io.run_for(std::chrono::milliseconds(timeout_ms));
  if (!error.empty()) {
    out.error = error;
    return out;
  }
  const auto frame = mo::decode_tcp(mb::byte_view(response.data(), held));
  if (!frame.is_complete()) {
    out.error = mb::to_string(frame.error());
  } else if (frame.value().transaction != transaction) {
    out.error = "transaction_mismatch";
  } else if (frame.value().unit != unit) {
    out.error = "unit_mismatch";
  } else {
    out.pdu.assign(frame.value().pdu.begin(), frame.value().pdu.end());
  }
  return out;
}

}  // namespace tcp_io
