// Freestanding memcpy/memset/memmove for the footprint probes (no C library is linked).
#include <cstddef>
extern "C" {
void* memcpy(void* d, const void* s, std::size_t n) {
  auto* a = static_cast<volatile unsigned char*>(d);
  const auto* b = static_cast<const unsigned char*>(s);
  for (std::size_t i = 0; i < n; ++i)
    a[i] = b[i];
  return d;
}
void* memmove(void* d, const void* s, std::size_t n) {
  auto* a = static_cast<volatile unsigned char*>(d);
  const auto* b = static_cast<const unsigned char*>(s);
  if (a < b) {
    for (std::size_t i = 0; i < n; ++i)
      a[i] = b[i];
  } else {
    for (std::size_t i = n; i > 0; --i)
      a[i - 1] = b[i - 1];
  }
  return d;
}
void* memset(void* d, int v, std::size_t n) {
  auto* a = static_cast<volatile unsigned char*>(d);
  for (std::size_t i = 0; i < n; ++i)
    a[i] = static_cast<unsigned char>(v);
  return d;
}
}
