// A stand-in for Google Benchmark's header that runs one benchmark a fixed number of times, so
// that valgrind's callgrind counts its instructions (bench/RESULTS.md, biss_chain3_decode):
//   g++ -std=c++17 -O3 -DNDEBUG -Ibench/count -Iinclude bench/biss/biss_bench.cpp -o count
//   valgrind --tool=callgrind ./count biss_chain3_decode/motionbus 100000
// Instructions per iteration: the difference of two counts, divided by the difference of their
// iteration counts (the setup cancels).
#ifndef MOTIONBUS_BENCH_COUNT_BENCHMARK_H
#define MOTIONBUS_BENCH_COUNT_BENCHMARK_H

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace benchmark {

class State {
 public:
  explicit State(std::size_t n) : n_(n) {}
  struct iterator {
    std::size_t k;
    bool operator!=(const iterator& o) const { return k != o.k; }
    void operator++() { ++k; }
    // a type with a destructor: `for (auto _ : state)` leaves `_` unused without a warning
    struct value {
      ~value() {}
    };
    value operator*() const { return {}; }
  };
  iterator begin() const { return {0}; }
  iterator end() const { return {n_}; }
  void SetItemsProcessed(std::int64_t) {}
  void SetBytesProcessed(std::int64_t) {}
  std::int64_t iterations() const { return static_cast<std::int64_t>(n_); }

 private:
  std::size_t n_;
};

template <class T>
inline void DoNotOptimize(const T& v) {
  asm volatile("" : : "m"(v) : "memory");
}
template <class T>
inline void DoNotOptimize(T& v) {
  asm volatile("" : "+m"(v) : : "memory");
}
inline void ClobberMemory() {
  asm volatile("" : : : "memory");
}

struct registration {
  std::string name;
  void (*run)(State&);
  registration* Name(const char* s) {
    name = s;
    return this;
  }
  registration* Arg(std::int64_t) { return this; }
};
inline std::vector<registration>& registrations() {
  static std::vector<registration> all;
  return all;
}
inline registration* add(void (*run)(State&)) {
  registrations().push_back({"", run});
  return &registrations().back();
}

}  // namespace benchmark

#define MOTIONBUS_COUNT_CAT2(a, b) a##b
#define MOTIONBUS_COUNT_CAT(a, b) MOTIONBUS_COUNT_CAT2(a, b)
#define BENCHMARK(f) \
  static ::benchmark::registration* MOTIONBUS_COUNT_CAT(count_, __LINE__) = ::benchmark::add(f)
#define BENCHMARK_TEMPLATE(f, ...)                                          \
  static ::benchmark::registration* MOTIONBUS_COUNT_CAT(count_, __LINE__) = \
      ::benchmark::add(f<__VA_ARGS__>)

int main(int argc, char** argv) {
  if (argc != 3) {
    return 2;
  }
  for (auto& r : benchmark::registrations()) {
    if (r.name == argv[1]) {
      benchmark::State s(static_cast<std::size_t>(std::strtoull(argv[2], nullptr, 10)));
      r.run(s);
      return 0;
    }
  }
  return 1;
}

#endif
