#!/usr/bin/env bash
# The motionbus demo: installs what it needs, builds the CLI and the examples, and shows the
# shared core at work: the protocols' CRCs on real frames and a BiSS-style bit capture.
# (The protocol demos — T-format, Modbus and BiSS-C against their emulators — join as each
# protocol lands.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${MOTIONBUS_BUILD_DIR:-$root/build}/demo"
bash tools/scripts/ensure-packages.sh cmake ninja-build g++
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMOTIONBUS_BUILD_TESTS=OFF \
  -DMOTIONBUS_BUILD_BENCH=OFF -DMOTIONBUS_BUILD_FUZZ=OFF >/dev/null
cmake --build "$build" --target motionbus_cli motionbus_example_core_tour >/dev/null
cli="$build/tools/motionbus"

echo "== The shared core (examples/core_tour.cpp)"
"$build/examples/motionbus_example_core_tour"
echo
echo "== The motionbus CLI"
show() {
  local shown="\$ motionbus"
  for a in "$@"; do
    case "$a" in *" "*) shown+=" \"$a\"" ;; *) shown+=" $a" ;; esac
  done
  echo "$shown"
  "$cli" "$@" || true
}
show crc modbus "11 03 00 6B 00 03"
show crc modbus 313233343536373839
show crc tformat "1A 00 34 12 01 11 00 00 00 00"
show crc biss6 0001001000110100010101100111100011
show crc biss4 10010000001
echo "\$ printf '02 8A\\nzz\\n' | motionbus crc tformat -"
printf '02 8A\nzz\n' | "$cli" crc tformat - || true
