// Deterministic pseudo-random numbers for reproducible randomized tests (splitmix64), and the
// two ways a random stream damages a frame.
#ifndef MOTIONBUS_TESTS_PRNG_HPP
#define MOTIONBUS_TESTS_PRNG_HPP

#include <cstddef>
#include <cstdint>
#include <vector>

namespace testutil {

class splitmix64 {
 public:
  explicit splitmix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
  }
  /// Uniform-ish value in [0, bound), bound > 0.
  std::uint64_t below(std::uint64_t bound) { return next() % bound; }
  std::uint8_t byte() { return static_cast<std::uint8_t>(next() & 0xFFU); }

 private:
  std::uint64_t state_;
};

/// One byte of `frame` changed: a random place XOR-ed with a random non-zero value.
inline void flip_a_byte(splitmix64& rng, std::vector<std::uint8_t>& frame) {
  frame[static_cast<std::size_t>(rng.below(frame.size()))] ^=
      static_cast<std::uint8_t>(1U + rng.below(255));
}

/// `frame` cut short: a random length below its own.
inline void cut_short(splitmix64& rng, std::vector<std::uint8_t>& frame) {
  frame.resize(static_cast<std::size_t>(rng.below(frame.size())));
}

}  // namespace testutil

#endif
