// motionbus's typed values (modbus/values.hpp) as text, for tests/interop/values_check.py, which
// compares them with pymodbus's BinaryPayloadBuilder/Decoder and libmodbus's helpers.
// Reads lines from stdin, answers one line each:
//   samples                      -> "TYPE HEXBITS" lines (tests/support/value_samples.hpp), then
//   "end" enc TYPE HEXBITS             -> "abcd R0 R1.. cdab .. badc .. dcba .." (registers in hex)
//   dec TYPE ORDER R0 R1 ..      -> HEXBITS of the value the registers hold in ORDER
// TYPE is u32 i32 f32 u64 i64 f64; integers' bits are their two's complement.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include "../support/value_samples.hpp"
#include "motionbus/modbus/values.hpp"

using namespace motionbus::modbus;

namespace {

constexpr const char* order_names[] = {"abcd", "cdab", "badc", "dcba"};
constexpr word_order orders[] = {word_order::abcd, word_order::cdab, word_order::badc,
                                 word_order::dcba};

template <class T, class U>
T of_bits(U u) {
  T v{};
  std::memcpy(&v, &u, sizeof(v));
  return v;
}
template <class T>
std::uint64_t bits_of(T v) {
  typename motionbus::modbus::detail::value_bits<T>::type u{};
  std::memcpy(&u, &v, sizeof(u));
  return u;
}

template <class T>
void encode(std::uint64_t bits) {
  using U = typename motionbus::modbus::detail::value_bits<T>::type;
  const T v = of_bits<T>(static_cast<U>(bits));
  for (std::size_t k = 0; k < 4; ++k) {
    std::printf("%s%s", k == 0 ? "" : " ", order_names[k]);
    for (const std::uint16_t r : to_registers(v, orders[k])) {
      std::printf(" %04x", r);
    }
  }
  std::printf("\n");
}

template <class T>
void decode(std::istringstream& in) {
  std::string order;
  in >> order;
  std::array<std::uint16_t, registers_of<T>> regs{};
  for (auto& r : regs) {
    unsigned x = 0;
    in >> std::hex >> x;
    r = static_cast<std::uint16_t>(x);
  }
  for (std::size_t k = 0; k < 4; ++k) {
    if (order == order_names[k]) {
      std::printf("%" PRIx64 "\n", bits_of(from_registers<T>(regs, orders[k])));
      return;
    }
  }
  std::printf("error\n");
}

template <class T>
void samples(const char* name, const std::vector<T>& values) {
  for (const T v : values) {
    std::printf("%s %" PRIx64 "\n", name, bits_of(v));
  }
}

}  // namespace

int main() {
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string op;
    std::string type;
    in >> op >> type;
    if (op == "samples") {
      samples("u32", testutil::u32_samples());
      samples("i32", testutil::i32_samples());
      samples("u64", testutil::u64_samples());
      samples("i64", testutil::i64_samples());
      for (const std::uint32_t b : testutil::f32_bit_samples()) {
        std::printf("f32 %" PRIx32 "\n", b);
      }
      for (const std::uint64_t b : testutil::f64_bit_samples()) {
        std::printf("f64 %" PRIx64 "\n", b);
      }
      std::printf("end\n");
      continue;
    }
    if (op == "enc") {
      std::uint64_t bits = 0;
      in >> std::hex >> bits;
      if (type == "u32")
        encode<std::uint32_t>(bits);
      else if (type == "i32")
        encode<std::int32_t>(bits);
      else if (type == "f32")
        encode<float>(bits);
      else if (type == "u64")
        encode<std::uint64_t>(bits);
      else if (type == "i64")
        encode<std::int64_t>(bits);
      else if (type == "f64")
        encode<double>(bits);
      else
        std::printf("error\n");
    } else if (op == "dec") {
      if (type == "u32")
        decode<std::uint32_t>(in);
      else if (type == "i32")
        decode<std::int32_t>(in);
      else if (type == "f32")
        decode<float>(in);
      else if (type == "u64")
        decode<std::uint64_t>(in);
      else if (type == "i64")
        decode<std::int64_t>(in);
      else if (type == "f64")
        decode<double>(in);
      else
        std::printf("error\n");
    } else {
      std::printf("error\n");
    }
  }
  return 0;
}
