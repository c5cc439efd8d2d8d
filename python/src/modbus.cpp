// motionbus Python binding — motionbus.modbus: PDU encoders and decoders of both roles, RTU and
// TCP framing, the RTU framer (server, client, listener; chunks or single bytes), timing, and
// a server over a Python object's coils and registers.
#include <memory>
#include <string>

#include "common.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/server.hpp"
#include "motionbus/modbus/tcp.hpp"
#include "motionbus/modbus/timing.hpp"

namespace mbpy {

namespace mb = motionbus::modbus;

namespace {

// A decoded request with its data copied out of the caller's buffer.
struct request_box {
  mb::request q;
  std::string data;
  explicit request_box(const mb::request& r)
      : q(r), data(reinterpret_cast<const char*>(r.data.data()), r.data.size()) {}
  mb::request view() const {
    mb::request r = q;
    r.data = byte_view(reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
    return r;
  }
};

struct response_box {
  mb::response r;
  std::string data;
  explicit response_box(const mb::response& v)
      : r(v), data(reinterpret_cast<const char*>(v.data.data()), v.data.size()) {}
  byte_view bytes() const {
    return byte_view(reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
  }
};

struct rtu_box {
  std::uint8_t slave = 0;
  std::string pdu;
  std::uint16_t crc = 0;
  py::object heard_response = py::none();  ///< listener: framed as a response (else None)
  static rtu_box of(const mb::rtu_frame& f) {
    rtu_box b;
    b.slave = f.slave;
    b.pdu.assign(reinterpret_cast<const char*>(f.pdu.data()), f.pdu.size());
    b.crc = f.crc;
    return b;
  }
};

struct tcp_box {
  std::uint16_t transaction = 0;
  std::uint16_t protocol = 0;
  std::uint8_t unit = 0;
  std::string pdu;
  std::size_t size = 0;
};

template <std::size_t N = mb::max_pdu_size, class Encode>
py::bytes pdu(const char* what, Encode&& e) {
  return encode_into<N>(what, e);
}

py::list registers_of(byte_view data) {
  py::list out;
  for (std::size_t i = 0; i + 1U < data.size(); i += 2U) {
    out.append(static_cast<int>((data[i] << 8U) | data[i + 1U]));
  }
  return out;
}

// The server's device: a Python object's methods, each optional (a missing one answers
// exception 01). A Python exception inside an accessor cannot cross the library's noexcept
// dispatch: it is kept, the request answered 04, and raised once serving returns.
struct py_device {
  py::object obj;
  py::object pending;  // the exception value kept, or None

  explicit py_device(py::object o) : obj(std::move(o)), pending(py::none()) {}

  template <class Call>
  std::uint8_t guarded(const char* method, Call&& call) {
    if (!pending.is_none()) {
      return 0x04;
    }
    try {
      if (!py::hasattr(obj, method)) {
        return 0x01;
      }
      return call(obj.attr(method));
    } catch (py::error_already_set& e) {
      static const py::handle modbus_exception = lookup("motionbus._errors", "ModbusException");
      if (e.matches(modbus_exception)) {
        const int code = e.value().attr("exception_code").cast<int>();
        return static_cast<std::uint8_t>(code < 1 || code > 255 ? 0x04 : code);
      }
      pending = e.value();
      return 0x04;
    } catch (std::exception& e) {
      pending = py::reinterpret_borrow<py::object>(PyExc_ValueError)(std::string(method) + ": " +
                                                                     e.what());
      return 0x04;
    }
  }

  std::uint8_t read_bits(std::uint8_t f, std::uint16_t address, std::uint16_t quantity,
                         mutable_byte_view packed) {
    return guarded(f == 0x01 ? "read_coils" : "read_discrete_inputs", [&](py::object m) {
      const py::object got = m(address, quantity);
      const std::vector<std::uint8_t> bits = packed_bits(got, "read_coils result");
      if (py::len(got) != quantity) {
        throw py::value_error("read_*: returned " + std::to_string(py::len(got)) + " values for " +
                              std::to_string(quantity));
      }
      for (std::size_t i = 0; i < bits.size() && i < packed.size(); ++i) {
        packed[i] = bits[i];
      }
      return std::uint8_t{0};
    });
  }
  std::uint8_t read_registers(std::uint8_t f, std::uint16_t address,
                              motionbus::span<std::uint16_t> out) {
    return guarded(
        f == 0x04 ? "read_input_registers" : "read_holding_registers", [&](py::object m) {
          const py::object got = m(address, out.size());
          const std::vector<std::uint16_t> regs = registers_arg(got, "read_*_registers result");
          if (regs.size() != out.size()) {
            throw py::value_error("read_*_registers: returned " + std::to_string(regs.size()) +
                                  " values for " + std::to_string(out.size()));
          }
          for (std::size_t i = 0; i < regs.size(); ++i) {
            out[i] = regs[i];
          }
          return std::uint8_t{0};
        });
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, byte_view packed) {
    return guarded("write_coils", [&](py::object m) {
      m(address, unpack_bits(packed, quantity));
      return std::uint8_t{0};
    });
  }
  std::uint8_t write_registers(std::uint16_t address, motionbus::span<const std::uint16_t> values) {
    return guarded("write_registers", [&](py::object m) {
      py::list v;
      for (const std::uint16_t x : values) {
        v.append(x);
      }
      m(address, v);
      return std::uint8_t{0};
    });
  }
  std::uint8_t report_server_id(mutable_byte_view out, std::size_t& size) {
    return guarded("report_server_id", [&](py::object m) {
      const py::object got = m();
      const bytes_arg b(got, "report_server_id result");
      if (b.view().size() > out.size()) {
        throw py::value_error("report_server_id: too long");
      }
      for (std::size_t i = 0; i < b.view().size(); ++i) {
        out[i] = b.view()[i];
      }
      size = b.view().size();
      return std::uint8_t{0};
    });
  }

  void rethrow() {
    if (!pending.is_none()) {
      const py::object e = pending;
      pending = py::none();
      raise_object(e);
    }
  }
};

struct framer_box {
  mb::framer_role role;
  std::unique_ptr<mb::rtu_framer> either;
  std::unique_ptr<mb::rtu_listener> listener;

  framer_box(mb::framer_role r, const mb::framer_options& o) : role(r) {
    if (r == mb::framer_role::listener) {
      listener = std::make_unique<mb::rtu_listener>(o);
    } else {
      either = std::make_unique<mb::rtu_framer>(r, o);
    }
  }
  py::object event(const motionbus::decode_result<mb::rtu_frame>& r) const {
    if (r.is_complete()) {
      rtu_box b = rtu_box::of(r.value());
      if (listener) {
        b.heard_response = py::bool_(listener->heard_response());
      }
      return py::cast(std::move(b));
    }
    return error_of(r, "modbus.RtuFramer");
  }
  template <class F>
  py::list feed_with(F& f, byte_view in) {
    py::list events;
    (void)motionbus::feed_all(f, in, [&](const auto& r) {
      events.append(event(r));
      return true;
    });
    return events;
  }
  py::list feed(byte_view in) {
    return listener ? feed_with(*listener, in) : feed_with(*either, in);
  }
  template <class F>
  py::list put_with(F& f, std::uint8_t byte) {
    py::list events;
    motionbus::put_each(f, byte, [&](const auto& r) {
      events.append(event(r));
      return true;
    });
    return events;
  }
  py::list put(std::uint8_t byte) {
    return listener ? put_with(*listener, byte) : put_with(*either, byte);
  }
  template <class F>
  py::list idle_with(F& f) {
    // The listener settles one result a call (each drops at least one byte held); the other
    // roles are empty after one: the next call reports incomplete.
    py::list events;
    for (;;) {
      const auto r = f.idle();
      if (r.is_incomplete()) {
        return events;
      }
      events.append(event(r));
    }
  }
  py::list idle() { return listener ? idle_with(*listener) : idle_with(*either); }
  template <class G>
  auto get(G&& g) const {
    return listener ? g(*listener) : g(*either);
  }
};

}  // namespace

void bind_modbus(py::module_& root) {
  py::module_ m = root.def_submodule("modbus", "Modbus PDU, RTU and TCP codec, framer and server.");
  add_enum("ExceptionCode", {{"illegal_function", 0x01},
                             {"illegal_data_address", 0x02},
                             {"illegal_data_value", 0x03},
                             {"server_device_failure", 0x04},
                             {"acknowledge", 0x05},
                             {"server_device_busy", 0x06},
                             {"memory_parity_error", 0x08},
                             {"gateway_path_unavailable", 0x0A},
                             {"gateway_target_failed", 0x0B}});
  add_enum("FunctionCode", {{"read_coils", 0x01},
                            {"read_discrete_inputs", 0x02},
                            {"read_holding_registers", 0x03},
                            {"read_input_registers", 0x04},
                            {"write_single_coil", 0x05},
                            {"write_single_register", 0x06},
                            {"read_exception_status", 0x07},
                            {"diagnostics", 0x08},
                            {"get_comm_event_counter", 0x0B},
                            {"get_comm_event_log", 0x0C},
                            {"write_multiple_coils", 0x0F},
                            {"write_multiple_registers", 0x10},
                            {"report_server_id", 0x11},
                            {"mask_write_register", 0x16},
                            {"read_write_multiple_registers", 0x17},
                            {"read_fifo_queue", 0x18},
                            {"encapsulated_interface", 0x2B}});
  add_enum("ReportIdFormat", {{"standard", 0}, {"two_bytes_no_count", 1}});
  add_enum("FrameEnd", {{"silence", 0}, {"length", 1}});
  add_enum("FramerRole", {{"server", 0}, {"client", 1}, {"listener", 2}});
  add_enum("Parity", {{"none", 0}, {"even", 1}, {"odd", 2}});
  m.attr("MAX_PDU_SIZE") = mb::max_pdu_size;
  m.attr("MAX_RTU_SIZE") = mb::max_rtu_size;
  m.attr("MAX_READ_BITS") = mb::max_read_bits;
  m.attr("MAX_READ_REGISTERS") = mb::max_read_registers;
  m.attr("MAX_WRITE_COILS") = mb::max_write_coils;
  m.attr("MAX_WRITE_REGISTERS") = mb::max_write_registers;

  // --- results ---------------------------------------------------------------------------
  py::class_<request_box> req(m, "Request", "A request PDU as a server decoded it.");
  req.def_property_readonly(
         "function", [](const request_box& b) { return enum_value("FunctionCode", b.q.function); })
      .def_property_readonly("address", [](const request_box& b) { return b.q.address; })
      .def_property_readonly("quantity", [](const request_box& b) { return b.q.quantity; })
      .def_property_readonly("value", [](const request_box& b) { return b.q.value; })
      .def_property_readonly("and_mask", [](const request_box& b) { return b.q.and_mask; })
      .def_property_readonly("or_mask", [](const request_box& b) { return b.q.or_mask; })
      .def_property_readonly("write_address",
                             [](const request_box& b) { return b.q.write_address; })
      .def_property_readonly("write_quantity",
                             [](const request_box& b) { return b.q.write_quantity; })
      .def_property_readonly("sub_function", [](const request_box& b) { return b.q.sub_function; })
      .def_property_readonly("mei_type", [](const request_box& b) { return b.q.mei_type; })
      .def_property_readonly("read_code", [](const request_box& b) { return b.q.read_code; })
      .def_property_readonly("object_id", [](const request_box& b) { return b.q.object_id; })
      .def_property_readonly(
          "data", [](const request_box& b) { return py::bytes(b.data); },
          "FC0F packed coils, FC10/17 register bytes, FC08 data, raw data.")
      .def_property_readonly(
          "registers",
          [](const request_box& b) {
            return registers_of(
                byte_view(reinterpret_cast<const std::uint8_t*>(b.data.data()), b.data.size()));
          },
          "FC10/FC17: the registers written.")
      .def_property_readonly(
          "coils",
          [](const request_box& b) {
            return unpack_bits(
                byte_view(reinterpret_cast<const std::uint8_t*>(b.data.data()), b.data.size()),
                b.q.quantity);
          },
          "FC0F: the coils written.");
  add_repr(req, {"function", "address", "quantity", "value", "data"});

  py::class_<response_box> rsp(m, "Response", "A response PDU as a client decoded it.");
  rsp.def_property_readonly(
         "function", [](const response_box& b) { return enum_value("FunctionCode", b.r.function); })
      .def_property_readonly("exception", [](const response_box& b) { return b.r.exception; })
      .def_property_readonly("exception_code",
                             [](const response_box& b) -> py::object {
                               if (!b.r.exception) {
                                 return py::none();
                               }
                               return enum_value("ExceptionCode", b.r.exception_code);
                             })
      .def_property_readonly("byte_count", [](const response_box& b) { return b.r.byte_count; })
      .def_property_readonly("address", [](const response_box& b) { return b.r.address; })
      .def_property_readonly("quantity", [](const response_box& b) { return b.r.quantity; })
      .def_property_readonly("value", [](const response_box& b) { return b.r.value; })
      .def_property_readonly("and_mask", [](const response_box& b) { return b.r.and_mask; })
      .def_property_readonly("or_mask", [](const response_box& b) { return b.r.or_mask; })
      .def_property_readonly("sub_function", [](const response_box& b) { return b.r.sub_function; })
      .def_property_readonly("status", [](const response_box& b) { return b.r.status; })
      .def_property_readonly("event_count", [](const response_box& b) { return b.r.event_count; })
      .def_property_readonly("message_count",
                             [](const response_box& b) { return b.r.message_count; })
      .def_property_readonly("fifo_count", [](const response_box& b) { return b.r.fifo_count; })
      .def_property_readonly("conformity", [](const response_box& b) { return b.r.conformity; })
      .def_property_readonly("more_follows", [](const response_box& b) { return b.r.more_follows; })
      .def_property_readonly("next_object", [](const response_box& b) { return b.r.next_object; })
      .def_property_readonly("object_count", [](const response_box& b) { return b.r.object_count; })
      .def_property_readonly("data", [](const response_box& b) { return py::bytes(b.data); })
      .def_property_readonly(
          "registers", [](const response_box& b) { return registers_of(b.bytes()); },
          "FC03/04/17/18: the registers read.")
      .def_property_readonly(
          "bits", [](const response_box& b) { return unpack_bits(b.bytes(), b.r.quantity); },
          "FC01/02: the bits read (quantity of them).")
      .def_property_readonly(
          "objects",
          [](const response_box& b) {
            py::list out;
            mb::response r = b.r;
            r.data = b.bytes();
            for (std::size_t i = 0;; ++i) {
              const auto o = mb::object_at(r, i);
              if (!o.ok()) {
                return out;
              }
              out.append(py::make_tuple(o.value().id, to_bytes(o.value().value)));
            }
          },
          "FC2B/0E: (object id, value) pairs.");
  add_repr(rsp,
           {"function", "exception", "exception_code", "address", "quantity", "value", "data"});

  py::class_<rtu_box> rtu(m, "RtuFrame", "An RTU frame: slave address, PDU, CRC as received.");
  rtu.def(py::init([](std::uint8_t slave, const py::handle& p, std::uint16_t c) {
            rtu_box b;
            b.slave = slave;
            const bytes_arg in(p, "pdu");
            b.pdu.assign(reinterpret_cast<const char*>(in.view().data()), in.view().size());
            b.crc = c;
            return b;
          }),
          py::arg("slave"), py::arg("pdu"), py::arg("crc") = 0)
      .def_readonly("slave", &rtu_box::slave)
      .def_property_readonly("pdu", [](const rtu_box& b) { return py::bytes(b.pdu); })
      .def_readonly("crc", &rtu_box::crc)
      .def_readonly("heard_response", &rtu_box::heard_response,
                    "Listener: True when framed as the response to the request before it, else "
                    "False; None for the other roles.")
      .def_property_readonly("broadcast",
                             [](const rtu_box& b) { return b.slave == mb::broadcast_address; });
  add_repr(rtu, {"slave", "pdu", "crc", "heard_response"});

  py::class_<tcp_box> tcp(m, "TcpFrame", "A Modbus TCP ADU (MBAP header and PDU).");
  tcp.def_readonly("transaction", &tcp_box::transaction)
      .def_readonly("protocol", &tcp_box::protocol)
      .def_readonly("unit", &tcp_box::unit)
      .def_property_readonly("pdu", [](const tcp_box& b) { return py::bytes(b.pdu); })
      .def_readonly("size", &tcp_box::size, "Bytes of the ADU in the stream.");
  add_repr(tcp, {"transaction", "protocol", "unit", "pdu", "size"});

  // --- client: request encoders, response decoders ----------------------------------------
  m.def(
      "encode_read",
      [](const py::handle& f, const py::handle& a, const py::handle& q) {
        const auto fc = as<std::uint8_t>(f, "function");
        const auto address = as<std::uint16_t>(a, "address");
        const auto quantity = as<std::uint16_t>(q, "quantity");
        return pdu("modbus.encode_read",
                   [&](mutable_byte_view o) { return mb::encode_read(fc, address, quantity, o); });
      },
      py::arg("function"), py::arg("address"), py::arg("quantity"),
      "FC01/02/03/04 request PDU: read `quantity` bits or registers from `address`.");
  m.def(
      "encode_write_single_coil",
      [](const py::handle& a, bool on) {
        const auto address = as<std::uint16_t>(a, "address");
        return pdu("modbus.encode_write_single_coil", [&](mutable_byte_view o) {
          return mb::encode_write_single_coil(address, on, o);
        });
      },
      py::arg("address"), py::arg("on"), "FC05 request PDU.");
  m.def(
      "encode_write_single_register",
      [](const py::handle& a, const py::handle& v) {
        const auto address = as<std::uint16_t>(a, "address");
        const auto value = as<std::uint16_t>(v, "value");
        return pdu("modbus.encode_write_single_register", [&](mutable_byte_view o) {
          return mb::encode_write_single_register(address, value, o);
        });
      },
      py::arg("address"), py::arg("value"), "FC06 request PDU.");
  m.def(
      "encode_write_multiple_coils",
      [](const py::handle& a, const py::handle& coils) {
        const auto address = as<std::uint16_t>(a, "address");
        const std::vector<std::uint8_t> packed = packed_bits(coils, "coils");
        const auto n = static_cast<std::uint16_t>(py::len(coils));
        return pdu("modbus.encode_write_multiple_coils", [&](mutable_byte_view o) {
          return mb::encode_write_multiple_coils(address, n,
                                                 byte_view(packed.data(), packed.size()), o);
        });
      },
      py::arg("address"), py::arg("coils"), "FC0F request PDU: the coils (bools) from `address`.");
  m.def(
      "encode_write_multiple_registers",
      [](const py::handle& a, const py::handle& values) {
        const auto address = as<std::uint16_t>(a, "address");
        const std::vector<std::uint16_t> v = registers_arg(values, "values");
        return pdu("modbus.encode_write_multiple_registers", [&](mutable_byte_view o) {
          return mb::encode_write_multiple_registers(
              address, motionbus::span<const std::uint16_t>(v.data(), v.size()), o);
        });
      },
      py::arg("address"), py::arg("values"), "FC10 request PDU.");
  m.def(
      "encode_mask_write_register",
      [](const py::handle& a, const py::handle& am, const py::handle& om) {
        const auto address = as<std::uint16_t>(a, "address");
        const auto and_mask = as<std::uint16_t>(am, "and_mask");
        const auto or_mask = as<std::uint16_t>(om, "or_mask");
        return pdu("modbus.encode_mask_write_register", [&](mutable_byte_view o) {
          return mb::encode_mask_write_register(address, and_mask, or_mask, o);
        });
      },
      py::arg("address"), py::arg("and_mask"), py::arg("or_mask"), "FC16 request PDU.");
  m.def(
      "encode_read_write_multiple_registers",
      [](const py::handle& ra, const py::handle& rq, const py::handle& wa,
         const py::handle& values) {
        const auto read_address = as<std::uint16_t>(ra, "read_address");
        const auto read_quantity = as<std::uint16_t>(rq, "read_quantity");
        const auto write_address = as<std::uint16_t>(wa, "write_address");
        const std::vector<std::uint16_t> v = registers_arg(values, "values");
        return pdu("modbus.encode_read_write_multiple_registers", [&](mutable_byte_view o) {
          return mb::encode_read_write_multiple_registers(
              read_address, read_quantity, write_address,
              motionbus::span<const std::uint16_t>(v.data(), v.size()), o);
        });
      },
      py::arg("read_address"), py::arg("read_quantity"), py::arg("write_address"),
      py::arg("values"), "FC17 request PDU.");
  m.def(
      "encode_raw",
      [](const py::handle& f, const py::handle& data) {
        const auto fc = as<std::uint8_t>(f, "function");
        const bytes_arg d(data);
        return pdu("modbus.encode_raw",
                   [&](mutable_byte_view o) { return mb::encode_raw(fc, d.view(), o); });
      },
      py::arg("function"), py::arg("data") = py::bytes(),
      "A PDU of any function with an opaque data part.");
  m.def(
      "encode_diagnostics",
      [](const py::handle& s, const py::handle& data) {
        const auto sub = as<std::uint16_t>(s, "sub_function");
        const bytes_arg d(data);
        return pdu("modbus.encode_diagnostics",
                   [&](mutable_byte_view o) { return mb::encode_diagnostics(sub, d.view(), o); });
      },
      py::arg("sub_function"), py::arg("data"), "FC08 request PDU.");
  m.def(
      "encode_read_fifo_queue",
      [](const py::handle& a) {
        const auto address = as<std::uint16_t>(a, "address");
        return pdu("modbus.encode_read_fifo_queue",
                   [&](mutable_byte_view o) { return mb::encode_read_fifo_queue(address, o); });
      },
      py::arg("address"), "FC18 request PDU.");
  m.def(
      "encode_read_device_identification",
      [](const py::handle& rc, const py::handle& id) {
        const auto read_code = as<std::uint8_t>(rc, "read_code");
        const auto object_id = as<std::uint8_t>(id, "object_id");
        return pdu("modbus.encode_read_device_identification", [&](mutable_byte_view o) {
          return mb::encode_read_device_identification(read_code, object_id, o);
        });
      },
      py::arg("read_code"), py::arg("object_id") = 0, "FC2B/0E request PDU.");

  m.def(
      "decode_response_for",
      [](const py::handle& sent, const py::handle& data, const py::handle& fc11) {
        const bytes_arg q(sent, "request");
        const bytes_arg in(data);
        const auto f = as<std::uint8_t>(fc11, "fc11");
        const auto r =
            mb::decode_response_for(q.view(), in.view(), static_cast<mb::report_id_format>(f & 1U));
        check(r, "modbus.decode_response_for");
        return response_box(r.value());
      },
      py::arg("request"), py::arg("data"), py::arg("fc11") = 0,
      "Decodes the response PDU `data` to the request PDU `request`, checking the echoes. An "
      "exception response is a Response with exception set.");
  m.def(
      "decode_response",
      [](const py::handle& data, const py::handle& fc11) {
        const bytes_arg in(data);
        const auto f = as<std::uint8_t>(fc11, "fc11");
        const auto r =
            mb::decode_response_unpaired(in.view(), static_cast<mb::report_id_format>(f & 1U));
        check(r, "modbus.decode_response");
        return response_box(r.value());
      },
      py::arg("data"), py::arg("fc11") = 0,
      "Decodes a response PDU seen without its request (a monitor, a capture).");

  // --- server: request decoder, response encoders -----------------------------------------
  m.def(
      "decode_request",
      [](const py::handle& data) {
        const bytes_arg in(data);
        const auto r = mb::decode_request(in.view());
        check(r, "modbus.decode_request");
        return request_box(r.value());
      },
      py::arg("data"), "Decodes a request PDU (the checks a server makes, in its order).");
  m.def(
      "exception_for",
      [](int code) {
        return enum_value("ExceptionCode",
                          static_cast<int>(mb::exception_for(static_cast<errc>(code))));
      },
      py::arg("code"), "The exception a server answers for a decode_request error code.");
  m.def(
      "encode_exception",
      [](const py::handle& f, const py::handle& c) {
        const auto fc = as<std::uint8_t>(f, "function");
        const auto code = as<std::uint8_t>(c, "code");
        return pdu("modbus.encode_exception",
                   [&](mutable_byte_view o) { return mb::encode_exception(fc, code, o); });
      },
      py::arg("function"), py::arg("code"), "Exception response PDU: function | 0x80, code.");
  m.def(
      "encode_read_bits_response",
      [](const py::handle& f, const py::handle& bits) {
        const auto fc = as<std::uint8_t>(f, "function");
        const std::vector<std::uint8_t> packed = packed_bits(bits, "bits");
        const auto n = static_cast<std::uint16_t>(py::len(bits));
        return pdu("modbus.encode_read_bits_response", [&](mutable_byte_view o) {
          return mb::encode_read_bits_response(fc, n, byte_view(packed.data(), packed.size()), o);
        });
      },
      py::arg("function"), py::arg("bits"), "FC01/02 response PDU.");
  m.def(
      "encode_read_registers_response",
      [](const py::handle& f, const py::handle& values) {
        const auto fc = as<std::uint8_t>(f, "function");
        const std::vector<std::uint16_t> v = registers_arg(values, "values");
        return pdu("modbus.encode_read_registers_response", [&](mutable_byte_view o) {
          return mb::encode_read_registers_response(
              fc, motionbus::span<const std::uint16_t>(v.data(), v.size()), o);
        });
      },
      py::arg("function"), py::arg("values"), "FC03/04/17 response PDU.");
  m.def(
      "encode_write_response",
      [](const request_box& q) {
        const mb::request r = q.view();
        return pdu("modbus.encode_write_response",
                   [&](mutable_byte_view o) { return mb::encode_write_response(r, o); });
      },
      py::arg("request"), "The normal response PDU to a decoded write request (FC05/06/0F/10/16).");
  m.def(
      "encode_exception_status_response",
      [](const py::handle& s) {
        const auto status = as<std::uint8_t>(s, "status");
        return pdu("modbus.encode_exception_status_response", [&](mutable_byte_view o) {
          return mb::encode_exception_status_response(status, o);
        });
      },
      py::arg("status"), "FC07 response PDU.");
  m.def(
      "encode_comm_event_counter_response",
      [](const py::handle& s, const py::handle& c) {
        const auto status = as<std::uint16_t>(s, "status");
        const auto count = as<std::uint16_t>(c, "event_count");
        return pdu("modbus.encode_comm_event_counter_response", [&](mutable_byte_view o) {
          return mb::encode_comm_event_counter_response(status, count, o);
        });
      },
      py::arg("status"), py::arg("event_count"), "FC0B response PDU.");
  m.def(
      "encode_comm_event_log_response",
      [](const py::handle& s, const py::handle& c, const py::handle& mc, const py::handle& events) {
        const auto status = as<std::uint16_t>(s, "status");
        const auto count = as<std::uint16_t>(c, "event_count");
        const auto messages = as<std::uint16_t>(mc, "message_count");
        const bytes_arg e(events, "events");
        return pdu("modbus.encode_comm_event_log_response", [&](mutable_byte_view o) {
          return mb::encode_comm_event_log_response(status, count, messages, e.view(), o);
        });
      },
      py::arg("status"), py::arg("event_count"), py::arg("message_count"), py::arg("events"),
      "FC0C response PDU.");
  m.def(
      "encode_fifo_response",
      [](const py::handle& values) {
        const std::vector<std::uint16_t> v = registers_arg(values, "values");
        return pdu("modbus.encode_fifo_response", [&](mutable_byte_view o) {
          return mb::encode_fifo_response(motionbus::span<const std::uint16_t>(v.data(), v.size()),
                                          o);
        });
      },
      py::arg("values"), "FC18 response PDU.");
  m.def(
      "encode_device_identification_response",
      [](const py::handle& rc, const py::handle& conf, bool more, const py::handle& next,
         const py::handle& objects) {
        const auto read_code = as<std::uint8_t>(rc, "read_code");
        const auto conformity = as<std::uint8_t>(conf, "conformity");
        const auto next_object = as<std::uint8_t>(next, "next_object");
        if (PySequence_Check(objects.ptr()) == 0) {
          throw py::type_error("objects must be a sequence of (id, bytes) pairs");
        }
        std::vector<std::uint8_t> laid;
        std::size_t count = 0;
        for (const py::handle o : py::reinterpret_borrow<py::sequence>(objects)) {
          const py::sequence pair = py::reinterpret_borrow<py::sequence>(o);
          if (py::len(pair) != 2) {
            throw py::type_error("objects must be (id, bytes) pairs");
          }
          const py::object item = pair[1];
          const bytes_arg value(item, "object value");
          if (value.view().size() > 255U) {
            raise_invalid("modbus.encode_device_identification_response",
                          "an object value above 255 bytes");
          }
          laid.push_back(as<std::uint8_t>(static_cast<py::object>(pair[0]), "object id"));
          laid.push_back(static_cast<std::uint8_t>(value.view().size()));
          laid.insert(laid.end(), value.view().begin(), value.view().end());
          ++count;
        }
        if (count > 255U) {
          raise_invalid("modbus.encode_device_identification_response", "more than 255 objects");
        }
        return pdu("modbus.encode_device_identification_response", [&](mutable_byte_view o) {
          return mb::encode_device_identification_response(read_code, conformity, more, next_object,
                                                           static_cast<std::uint8_t>(count),
                                                           byte_view(laid.data(), laid.size()), o);
        });
      },
      py::arg("read_code"), py::arg("conformity"), py::arg("more_follows"), py::arg("next_object"),
      py::arg("objects"), "FC2B/0E response PDU from (object id, value bytes) pairs.");

  // --- RTU, TCP, timing -------------------------------------------------------------------
  m.def(
      "encode_rtu",
      [](const py::handle& s, const py::handle& p) {
        const auto slave = as<std::uint8_t>(s, "slave");
        const bytes_arg in(p, "pdu");
        return encode_into<mb::max_rtu_size>("modbus.encode_rtu", [&](mutable_byte_view o) {
          return mb::encode_rtu(slave, in.view(), o);
        });
      },
      py::arg("slave"), py::arg("pdu"),
      "The RTU ADU: slave address, PDU, CRC-16 (low byte first).");
  m.def(
      "decode_rtu",
      [](const py::handle& data) {
        const bytes_arg in(data);
        const auto r = mb::decode_rtu(in.view());
        check(r, "modbus.decode_rtu");
        return rtu_box::of(r.value());
      },
      py::arg("data"), "Decodes one whole RTU ADU (the bytes between two silences).");
  m.def(
      "encode_tcp",
      [](const py::handle& t, const py::handle& u, const py::handle& p) {
        const auto transaction = as<std::uint16_t>(t, "transaction");
        const auto unit = as<std::uint8_t>(u, "unit");
        const bytes_arg in(p, "pdu");
        return encode_into<mb::max_tcp_size>("modbus.encode_tcp", [&](mutable_byte_view o) {
          return mb::encode_tcp(transaction, unit, in.view(), o);
        });
      },
      py::arg("transaction"), py::arg("unit"), py::arg("pdu"), "The TCP ADU: MBAP header and PDU.");
  m.def(
      "decode_tcp",
      [](const py::handle& data) {
        const bytes_arg in(data);
        const auto r = mb::decode_tcp(in.view());
        check(r, "modbus.decode_tcp");
        tcp_box b;
        b.transaction = r.value().transaction;
        b.protocol = r.value().protocol;
        b.unit = r.value().unit;
        b.pdu.assign(reinterpret_cast<const char*>(r.value().pdu.data()), r.value().pdu.size());
        b.size = r.consumed();
        return b;
      },
      py::arg("data"), "Decodes the TCP ADU at the start of a stream (TcpFrame.size: bytes used).");
  m.def(
      "t15_us",
      [](std::uint32_t baud, int parity, unsigned stop_bits) {
        return mb::t15_us(baud, static_cast<mb::parity>(parity & 3), stop_bits);
      },
      py::arg("baud"), py::arg("parity") = 1, py::arg("stop_bits") = 1, "t1.5 in microseconds.");
  m.def(
      "t35_us",
      [](std::uint32_t baud, int parity, unsigned stop_bits) {
        return mb::t35_us(baud, static_cast<mb::parity>(parity & 3), stop_bits);
      },
      py::arg("baud"), py::arg("parity") = 1, py::arg("stop_bits") = 1, "t3.5 in microseconds.");

  // --- the framer -------------------------------------------------------------------------
  py::class_<framer_box>(
      m, "RtuFramer",
      "The RTU stream framer: feed it bytes as they arrive (feed for chunks, "
      "put for single bytes) and call idle() at the t3.5 silence. Roles: "
      "server (requests for `address` and broadcasts), client (responses to "
      "the request given to sent()), listener (both directions of a tapped line).")
      .def(py::init([](const py::handle& role, const py::handle& address, const py::handle& ends,
                       const py::handle& fc11) {
             const auto r = as<std::uint8_t>(role, "role");
             if (r > 2U) {
               throw py::value_error("role must be FramerRole.server, client or listener");
             }
             mb::framer_options o;
             o.address = as<std::uint8_t>(address, "address");
             const auto e = as<std::uint8_t>(ends, "ends");
             if (e > 1U) {
               throw py::value_error("ends must be FrameEnd.silence or FrameEnd.length");
             }
             o.ends = static_cast<mb::frame_end>(e);
             o.fc11 = static_cast<mb::report_id_format>(as<std::uint8_t>(fc11, "fc11") & 1U);
             return new framer_box(static_cast<mb::framer_role>(r), o);  // NOLINT: pybind11 owns it
           }),
           py::arg("role") = 0, py::kw_only(), py::arg("address") = 0, py::arg("ends") = 0,
           py::arg("fc11") = 0)
      .def(
          "sent",
          [](framer_box& b, const py::handle& adu) {
            const bytes_arg in(adu, "request");
            if (b.either) {
              b.either->sent(in.view());
            }
          },
          py::arg("request"),
          "Client: the request ADU just sent (its slave and function shape the response).")
      .def(
          "feed",
          [](framer_box& b, const py::handle& data) {
            const bytes_arg in(data);
            return b.feed(in.view());
          },
          py::arg("data"),
          "Takes bytes; returns the events: RtuFrame objects and DecodeError objects (not raised).")
      .def(
          "put",
          [](framer_box& b, int byte) {
            if (byte < 0 || byte > 255) {
              throw py::value_error("byte must be 0..255");
            }
            return b.put(static_cast<std::uint8_t>(byte));
          },
          py::arg("byte"), "The per-byte step: the events this byte completes.")
      .def("idle", &framer_box::idle,
           "The t3.5 silence: the events the bytes held end in (frames or errors).")
      .def_property_readonly(
          "dropped",
          [](const framer_box& b) { return b.get([](const auto& f) { return f.dropped(); }); })
      .def_property_readonly(
          "skipped",
          [](const framer_box& b) { return b.get([](const auto& f) { return f.skipped(); }); })
      .def_property_readonly(
          "pending",
          [](const framer_box& b) { return b.get([](const auto& f) { return f.pending(); }); })
      .def_property_readonly("role", [](const framer_box& b) {
        return enum_value("FramerRole", static_cast<int>(b.role));
      });

  // --- the server -------------------------------------------------------------------------
  m.def(
      "serve_rtu",
      [](const py::object& device, const py::handle& a, const py::handle& adu) {
        const auto address = as<std::uint8_t>(a, "address");
        if (address < 1U || address > mb::max_unicast_address) {
          throw py::value_error("address must be 1..247");
        }
        const bytes_arg in(adu, "request");
        py_device dev(device);
        std::uint8_t out[mb::max_rtu_size] = {};
        const auto n = mb::serve_rtu(dev, address, in.view(), mutable_byte_view(out, sizeof out));
        dev.rethrow();
        return to_bytes(out, value_or_raise(n, "modbus.serve_rtu"));
      },
      py::arg("device"), py::arg("address"), py::arg("request"),
      "Serves one RTU request ADU for a server at `address` over `device`, a Python object with "
      "any of read_coils, read_discrete_inputs, read_holding_registers, read_input_registers "
      "(address, count) -> values; write_coils, write_registers (address, values); "
      "report_server_id() -> bytes (the FC11 data part after the function code: byte count, then "
      "the device bytes). A missing method answers exception 01; a method raising "
      "ModbusException(code) answers that code; any other exception answers 04 and is then "
      "raised here. Returns the response ADU, b'' when none is due (another address, a "
      "broadcast, a corrupted frame).");
}

}  // namespace mbpy
