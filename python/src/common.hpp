// motionbus Python binding — what every protocol's binding file shares: bytes-like input
// without a copy, bytes output, the one failure convention (motionbus.DecodeError and
// motionbus.EncodeError, raised with their evidence), the Python enums, reprs.
// The library itself (include/) is used as it is: no heap, no exceptions there; the binding
// copies what a decoder returns as a view into owned Python objects.
#ifndef MOTIONBUS_PYTHON_COMMON_HPP
#define MOTIONBUS_PYTHON_COMMON_HPP

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace mbpy {

namespace py = pybind11;
using motionbus::byte_view;
using motionbus::errc;
using motionbus::mutable_byte_view;

/// A bytes-like argument (bytes, bytearray, memoryview, array('B'), ...): a contiguous buffer
/// of bytes, viewed in place for the call. Anything else is a TypeError.
class bytes_arg {
 public:
  explicit bytes_arg(const py::handle& obj, const char* what = "data") {
    if (PyUnicode_Check(obj.ptr()) != 0 || PyObject_CheckBuffer(obj.ptr()) == 0) {
      throw py::type_error(std::string(what) +
                           " must be bytes-like (bytes, bytearray, memoryview), not " +
                           std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
    }
    if (PyObject_GetBuffer(obj.ptr(), &buf_, PyBUF_C_CONTIGUOUS) != 0) {
      throw py::error_already_set();
    }
    if (buf_.itemsize != 1) {
      PyBuffer_Release(&buf_);
      throw py::type_error(std::string(what) + " must be a buffer of bytes (item size 1)");
    }
  }
  bytes_arg(const bytes_arg&) = delete;
  bytes_arg& operator=(const bytes_arg&) = delete;
  ~bytes_arg() { PyBuffer_Release(&buf_); }
  byte_view view() const noexcept {
    return byte_view(static_cast<const std::uint8_t*>(buf_.buf),
                     static_cast<std::size_t>(buf_.len));
  }

 private:
  Py_buffer buf_{};
};

inline py::bytes to_bytes(const std::uint8_t* p, std::size_t n) {
  return py::bytes(reinterpret_cast<const char*>(p), n);
}
inline py::bytes to_bytes(byte_view v) {
  return to_bytes(v.data(), v.size());
}

/// A Python object the binding looks up once and keeps for the interpreter's life (never
/// released: no destructor runs at exit).
py::handle lookup(const char* module, const char* name);

/// The Python enum `cls_name` (motionbus._enums) member for `value`.
py::object enum_value(const char* cls_name, int value);

/// Registers a Python enum's members (built in motionbus/_enums.py from this table).
void add_enum(const char* name, std::vector<std::pair<const char*, int>> members);

/// A motionbus.DecodeError (or IncompleteError when `needed` != 0) for a failed or incomplete
/// decode, not raised: stream objects hand these back in their event lists.
py::object decode_error(errc e, std::size_t consumed, std::uint32_t expected,
                        std::uint32_t received, std::size_t needed, const char* context,
                        const char* unit = "bytes");

[[noreturn]] void raise_object(const py::object& err);
[[noreturn]] void raise_encode(errc e, const char* context);
[[noreturn]] void raise_invalid(const char* context, const std::string& what);

/// The error object of a decode_result that is not complete.
template <class T, motionbus::input_unit U>
py::object error_of(const motionbus::decode_result<T, U>& r, const char* context) {
  constexpr bool bits = U == motionbus::input_unit::bits;
  std::size_t consumed = 0;
  std::size_t needed = 0;
  if constexpr (bits) {
    consumed = r.consumed_bits();
    needed = r.needed_bits();
  } else {
    consumed = r.consumed();
    needed = r.needed();
  }
  return decode_error(r.is_incomplete() ? errc::truncated : r.error(), consumed, r.expected(),
                      r.received(), needed, context, bits ? "bits" : "bytes");
}

/// Raises unless `r` is complete.
template <class T, motionbus::input_unit U>
void check(const motionbus::decode_result<T, U>& r, const char* context) {
  if (!r.is_complete()) {
    raise_object(error_of(r, context));
  }
}

/// The value of an encoder's result, or EncodeError.
template <class T>
T value_or_raise(const motionbus::result<T>& r, const char* context) {
  if (!r.ok()) {
    raise_encode(r.error(), context);
  }
  return r.value();
}

/// An encoder call into a stack buffer of N bytes: the bytes written, or EncodeError.
template <std::size_t N, class Encode>
py::bytes encode_into(const char* context, Encode&& encode) {
  std::uint8_t out[N] = {};
  const motionbus::result<std::size_t> n = encode(mutable_byte_view(out, N));
  return to_bytes(out, value_or_raise(n, context));
}

/// An integer argument checked against [lo, hi] (ValueError naming it otherwise): the
/// binding takes Python ints for C++ uint8/16 fields so that 300 for a byte is a clear error,
/// not a silent truncation or an opaque TypeError.
std::uint64_t ranged(const py::handle& v, std::uint64_t hi, const char* name);
template <class T>
T as(const py::handle& v, const char* name) {
  return static_cast<T>(ranged(v, static_cast<std::uint64_t>(static_cast<T>(-1)), name));
}
std::vector<std::uint16_t> registers_arg(const py::handle& seq, const char* name);
std::vector<std::uint8_t> packed_bits(const py::handle& seq, const char* name);
py::list unpack_bits(byte_view packed, std::size_t count);
/// Line samples: a sequence of 0/1 (a sigrok decoder's, a test's) packed 8 a byte, the first in
/// the MSB (TypeError for anything else, bytes included: the bytes forms take those); and back.
std::vector<std::uint8_t> pack_samples(const py::handle& seq);
py::list unpack_samples(const std::uint8_t* packed, std::size_t count);

/// Gives a bound class `_fields` and lists it in `result_classes()`, whose members the package
/// gives a `__repr__` listing those fields and an `__eq__` comparing them (motionbus/_errors.py).
void add_repr(py::handle cls, std::vector<const char*> fields);
py::list& result_classes();

void bind_core(py::module_& m);
void bind_tformat(py::module_& m);
void bind_modbus(py::module_& m);
void bind_biss(py::module_& m);
void bind_ts5700n8500(py::module_& m);
void bind_sm_unit(py::module_& m);
void bind_absys(py::module_& m);

}  // namespace mbpy

#endif  // MOTIONBUS_PYTHON_COMMON_HPP
