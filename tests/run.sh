#!/usr/bin/env bash
# The whole motionbus test suite, from a fresh Debian machine: installs missing packages,
# then configures, builds and runs (ctest) each configuration:
#   gcc   C++17 at -O3 (Release): doctest suite, warnings at -O0/-O2/-O3/-Os, static suite, headers alone (C++17/20, no exceptions/RTTI),
#         include/ purity, no-heap run, CLI, footprint and meter (Cortex-M0+/M4, rv32imc),
#         firmware images under QEMU (Cortex-M4, rv32imc) with host Modbus peers,
#         package consumers (install, build tree, add_subdirectory, FetchContent, -I),
#         clang-format, fuzz corpus replay, bench smoke run
#   clang C++20 with ASan + UBSan: the same suites, plus each libFuzzer target for
#         MOTIONBUS_FUZZ_SECONDS (default 10) seconds
#   s390x (big-endian) and armhf (32-bit ARM): doctest, static and replay suites under qemu-user
#   coverage: gcc at -O0 with gcov; every test that executes library code, then the line and
#         branch coverage of include/ (tools/scripts/coverage_check.py, from gcov's JSON):
#         fails below 90 % of branches, or when a line no test executes or a branch no test
#         takes is not justified in the header; report in <build>/coverage/
# Environment: MOTIONBUS_BUILD_DIR (default ./build), MOTIONBUS_FUZZ_SECONDS.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${MOTIONBUS_BUILD_DIR:-$root/build}"
fuzz_seconds="${MOTIONBUS_FUZZ_SECONDS:-10}"
jobs="$(nproc 2>/dev/null || echo 2)"

bash tools/scripts/ensure-packages.sh \
  cmake ninja-build gcc g++ git clang llvm libclang-rt-14-dev clang-format doctest-dev \
  libbenchmark-dev gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib binutils-riscv64-unknown-elf \
  g++-s390x-linux-gnu g++-arm-linux-gnueabihf qemu-user \
  socat pkg-config libasio-dev libmodbus-dev python3-pymodbus python3-serial python3-serial-asyncio gcovr \
  python3-dev pybind11-dev python3-pybind11 python3-pytest python3-hypothesis python3-mypy \
  python3-pip python3-setuptools python3-wheel \
  python3-unicorn clang-tidy qemu-system-arm qemu-system-misc \
  libcli11-dev nlohmann-json3-dev libserialport-dev libzip-dev sigrok-cli iverilog

passed=0
failed=0
summary=""

# run_config NAME [cmake args...]: configure, build, ctest; tallies the results.
run_config() {
  local name="$1"
  shift
  local dir="$build/$name"
  echo "=== $name: configure and build"
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_EXTENSIONS=OFF "$@" >"$dir.configure.log" 2>&1 ||
    { cat "$dir.configure.log"; return 1; }
  cmake --build "$dir" -j "$jobs" || { echo "=== $name: build failed" >&2; failed=$((failed + 1)); summary+="  $name: build failed"$'\n'; return 1; }
  echo "=== $name: test"
  local log="$dir.ctest.log"
  local rc=0
  (cd "$dir" && ctest -j "$jobs" --output-on-failure --timeout 900) 2>&1 | tee "$log" || rc=$?
  local line
  line="$(grep -E 'tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | tail -n 1 || true)"
  if [ -z "$line" ]; then
    echo "=== $name: no ctest summary" >&2
    return 1
  fi
  local total bad
  total="$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$line")"
  bad="$(sed -E 's/.* ([0-9]+) tests failed.*/\1/' <<<"$line")"
  passed=$((passed + total - bad))
  failed=$((failed + bad))
  summary+="  $name: $((total - bad)) passed, $bad failed"$'\n'
  return "$rc"
}

mkdir -p "$build"
status=0
run_config gcc -DCMAKE_CXX_COMPILER=g++ -DCMAKE_BUILD_TYPE=Release -DMOTIONBUS_REQUIRE_ALL_CHECKS=ON ||
  status=1
run_config clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_STANDARD=20 -DMOTIONBUS_SANITIZE=ON \
  -DMOTIONBUS_BUILD_FUZZ=ON -DMOTIONBUS_FUZZ_SECONDS="$fuzz_seconds" \
  -DMOTIONBUS_REQUIRE_ALL_CHECKS=ON || status=1
for target in s390x-linux-gnu arm-linux-gnueabihf; do
  run_config "$target" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchains/$target.cmake" \
    -DMOTIONBUS_BUILD_TOOLS=OFF -DMOTIONBUS_BUILD_BENCH=OFF -DMOTIONBUS_BUILD_EXAMPLES=OFF \
    -DMOTIONBUS_BUILD_FUZZ=OFF || status=1
done

# Coverage: counters from this run only.
if [ -d "$build/coverage" ]; then
  find "$build/coverage" -name '*.gcda' -delete
fi
if run_config coverage -DCMAKE_CXX_COMPILER=g++ -DMOTIONBUS_COVERAGE=ON \
  -DMOTIONBUS_BUILD_BENCH=OFF -DMOTIONBUS_BUILD_FUZZ=OFF; then
  echo "=== coverage: report"
  if /usr/bin/python3 tools/scripts/coverage_check.py "$root" "$build/coverage"; then
    passed=$((passed + 1))
    summary+="  coverage report: passed"$'\n'
  else
    failed=$((failed + 1))
    summary+="  coverage report: FAILED"$'\n'
    status=1
  fi
else
  status=1
fi

# The failures again, at the end where a long log is read from: each failed test, and its
# failed checks (doctest's test case and check lines, the scripts' FAIL lines).
for log in "$build"/*.ctest.log; do
  if grep -qE '\*\*\*(Failed|Timeout|Exception)' "$log"; then
    echo "=== failed in $(basename "$log" .ctest.log)"
    grep -E '\*\*\*(Failed|Timeout|Exception)|TEST CASE:|ERROR:|^FAIL|  values: |logged: ' "$log" |
      head -n 80 || true
    # a suite stopped by its time-out reports no check: the case it was in (its listener's line)
    grep -E '^cli test case: ' "$log" | tail -n 1 | sed 's/^/last started: /' || true
  fi
done
echo "=== summary"
printf '%s' "$summary"
echo "motionbus: $passed passed, $failed failed"
exit "$status"
