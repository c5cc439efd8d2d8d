#!/usr/bin/env bash
# Reproduces bench/RESULTS.md: builds the benchmarks in Release with the host compiler and runs
# them (3 repetitions, median reported). Run on an otherwise idle machine.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MOTIONBUS_BUILD_DIR:-$root/build}/bench-release"
bash "$root/tools/scripts/ensure-packages.sh" cmake ninja-build g++ libbenchmark-dev pkg-config \
  libmodbus-dev
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMOTIONBUS_BUILD_TESTS=OFF \
  -DMOTIONBUS_BUILD_TOOLS=OFF -DMOTIONBUS_BUILD_EXAMPLES=OFF -DMOTIONBUS_BUILD_FUZZ=OFF >/dev/null
cmake --build "$build" --target motionbus_bench motionbus_bench_libmodbus \
  motionbus_bench_libmodbus_o2 |
  grep -E "error|FAILED" -A5 || true
for program in motionbus_bench motionbus_bench_libmodbus_o2 motionbus_bench_libmodbus; do
  # a filter may select benchmarks of one program only
  if "$build/bench/$program" --benchmark_list_tests --benchmark_filter="${1:-.}" 2>/dev/null |
      grep -q .; then
    "$build/bench/$program" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
      --benchmark_filter="${1:-.}" "${@:2}"
  fi
done
