// The C runtime an rv32imc image needs from the compiler's calls, for the firmware examples and
// the meter's images (Debian has no C library for that target):
// memcpy, memmove and memset:
// a word at a time where both pointers are aligned, else a byte at a time; and the 64-bit
// unsigned division and remainder a 32-bit core calls (libgcc's __udivdi3 and __umoddi3), by
// shift and subtract. The ARM images use newlib's and libgcc's. Compile it with -fno-builtin so
// that the loops are not turned back into calls.
#include <cstddef>
#include <cstdint>

extern "C" {
void* memcpy(void* d, const void* s, std::size_t n) {
  auto* a = static_cast<unsigned char*>(d);
  const auto* b = static_cast<const unsigned char*>(s);
  if (((reinterpret_cast<std::uintptr_t>(a) | reinterpret_cast<std::uintptr_t>(b)) & 3U) == 0U) {
    for (; n >= 4U; n -= 4U, a += 4, b += 4) {
      *reinterpret_cast<std::uint32_t*>(a) = *reinterpret_cast<const std::uint32_t*>(b);
    }
  }
  for (; n > 0U; --n) {
    *a++ = *b++;
  }
  return d;
}
void* memmove(void* d, const void* s, std::size_t n) {
  auto* a = static_cast<unsigned char*>(d);
  const auto* b = static_cast<const unsigned char*>(s);
  if (a <= b || a >= b + n) {
    return memcpy(d, s, n);
  }
  for (std::size_t i = n; i > 0U; --i) {
    a[i - 1U] = b[i - 1U];
  }
  return d;
}
void* memset(void* d, int v, std::size_t n) {
  auto* a = static_cast<unsigned char*>(d);
  const auto c = static_cast<unsigned char>(v);
  if ((reinterpret_cast<std::uintptr_t>(a) & 3U) == 0U) {
    const std::uint32_t w = 0x01010101U * c;
    for (; n >= 4U; n -= 4U, a += 4) {
      *reinterpret_cast<std::uint32_t*>(a) = w;
    }
  }
  for (; n > 0U; --n) {
    *a++ = c;
  }
  return d;
}
// Quotient and remainder of n / d (d != 0), one bit a step.
static std::uint64_t divide64(std::uint64_t n, std::uint64_t d, std::uint64_t* rem) {
  std::uint64_t q = 0;
  std::uint64_t r = 0;
  for (int bit = 63; bit >= 0; --bit) {
    r = (r << 1U) | ((n >> static_cast<unsigned>(bit)) & 1U);
    if (r >= d) {
      r -= d;
      q |= std::uint64_t{1} << static_cast<unsigned>(bit);
    }
  }
  *rem = r;
  return q;
}
std::uint64_t __udivdi3(std::uint64_t n, std::uint64_t d) {
  std::uint64_t r = 0;
  return divide64(n, d, &r);
}
std::uint64_t __umoddi3(std::uint64_t n, std::uint64_t d) {
  std::uint64_t r = 0;
  (void)divide64(n, d, &r);
  return r;
}
}
