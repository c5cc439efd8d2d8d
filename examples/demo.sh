#!/usr/bin/env bash
# The motionbus demo: installs what it needs, builds the CLI and the examples, and runs
#  - T-format: the CLI master reading the encoder emulator over a pseudo-terminal pair that
#    the demo creates (socat), as a servo drive reads a Tamagawa encoder over RS-485;
#  - Modbus-RTU: the CLI client reading the Tsubaki SM unit emulator over another pty pair;
#  - BiSS-C: a master reading position, identity and the EDS from the AMO ABSYS emulator over
#    an in-memory bit stream, and the CLI decoding a captured frame;
#  - the shared core: the protocols' CRCs on real frames and a BiSS-style bit capture.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${MOTIONBUS_BUILD_DIR:-$root/build}/demo"
bash tools/scripts/ensure-packages.sh cmake ninja-build g++ socat pkg-config libcli11-dev libasio-dev \
  nlohmann-json3-dev libserialport-dev libzip-dev
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMOTIONBUS_BUILD_TESTS=OFF \
  -DMOTIONBUS_BUILD_BENCH=OFF -DMOTIONBUS_BUILD_FUZZ=OFF >/dev/null
cmake --build "$build" --target motionbus_cli motionbus_example_core_tour \
  motionbus_example_biss_demo >/dev/null
cli="$build/tools/motionbus"

echo "== T-format: master <-> encoder emulator over a pseudo-terminal pair"
pty_dir="$(mktemp -d)"
socat pty,raw,echo=0,link="$pty_dir/drive" pty,raw,echo=0,link="$pty_dir/encoder" &
socat_pid=$!
serve_pid=""
cleanup() {
  [ -n "$serve_pid" ] && kill "$serve_pid" 2>/dev/null || true
  kill "$socat_pid" 2>/dev/null || true
  rm -rf "$pty_dir"
}
trap cleanup EXIT
for _ in $(seq 50); do [ -e "$pty_dir/encoder" ] && break; sleep 0.1; done
"$cli" serve tformat-encoder --device "$pty_dir/encoder" >/dev/null 2>&1 &
serve_pid=$!
sleep 0.3
for i in 1 2 3; do
  echo "  ID3 read $i: $("$cli" read tformat --device "$pty_dir/drive" --id 3 2>/dev/null || true)"
  sleep 0.2
done
echo "  EEPROM write page 0 address 10 <- 0x5A: $("$cli" read tformat --device "$pty_dir/drive" --id 6 --address 10 --data 90 2>/dev/null)"
sleep 0.05
echo "  EEPROM read  page 0 address 10:         $("$cli" read tformat --device "$pty_dir/drive" --id D --address 10 2>/dev/null)"
echo "  decode a captured ID3 response:"
echo "    \$ motionbus decode tformat response 1a2045230111341200c0aa"
echo "    $("$cli" decode tformat response 1a2045230111341200c0aa)"
echo

echo "== Modbus RTU: client <-> Tsubaki SM unit emulator over a pseudo-terminal pair (9600 8E1)"
socat pty,raw,echo=0,link="$pty_dir/unit" pty,raw,echo=0,link="$pty_dir/master" &
socat2_pid=$!
for _ in $(seq 50); do [ -e "$pty_dir/master" ] && break; sleep 0.1; done
"$cli" serve sm-unit --device "$pty_dir/unit" >/dev/null 2>&1 &
sm_pid=$!
sleep 0.3
for i in 1 2; do
  echo "  instantaneous data $i: $("$cli" read sm-unit --device "$pty_dir/master" 2>/dev/null)"
  sleep 0.5
done
echo "  overheat limit (holding 36, 0.1 degC): $("$cli" read modbus --device "$pty_dir/master" --slave 1 --function 3 --address 36 --quantity 1 2>/dev/null)"
echo "  write 201 % to a torque limit (max 200): $("$cli" read modbus --device "$pty_dir/master" --slave 1 --function 6 --address 0 --values 201 2>/dev/null)"
echo "  read one address of the password block: $("$cli" read modbus --device "$pty_dir/master" --slave 1 --function 3 --address 200 --quantity 1 2>/dev/null)"
kill "$sm_pid" "$socat2_pid" 2>/dev/null || true
echo

echo "== BiSS-C: master <-> AMO ABSYS emulator over an in-memory bit stream (examples/biss_demo.cpp)"
"$build/examples/motionbus_example_biss_demo"
frame="$("$cli" encode biss csd --position 123456 --ack 3 --cds 1 --line-delay 2 --json |
  sed -E 's/.*"bits":"([01]*)".*/\1/')"
echo "  a frame as a logic analyzer samples it, decoded by the CLI:"
echo "    \$ motionbus decode biss csd $frame"
echo "    $("$cli" decode biss csd "$frame")"
echo

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
