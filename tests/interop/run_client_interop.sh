#!/usr/bin/env bash
# The library's client side (`motionbus read modbus`) against third-party Modbus servers
# (libmodbus, pymodbus) over a pseudo-terminal pair made by socat.
# Usage: run_client_interop.sh MOTIONBUS_CLI LIBMODBUS_SERVER
set -euo pipefail
cli="$1"
libmodbus_server="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
status=0

expect() {  # expect NAME EXPECTED-SUBSTRING ARGS...
  local name="$1" want="$2"
  shift 2
  local out
  out="$("$cli" read modbus "$@" --json 2>/dev/null || true)"
  if [[ "$out" == *"$want"* ]]; then
    echo "ok   $name"
  else
    echo "FAIL $name: $out"
    status=1
  fi
}

run_against() {  # run_against NAME PARITY COMMAND...
  local name="$1" parity="$2"
  shift 2
  local dir
  dir="$(mktemp -d)"
  socat pty,raw,echo=0,link="$dir/server" pty,raw,echo=0,link="$dir/client" 2>/dev/null &
  local socat_pid=$!
  for _ in $(seq 50); do [ -e "$dir/client" ] && break; sleep 0.1; done
  "$@" "$dir/server" "$parity" >/dev/null 2>&1 &
  local server_pid=$!
  sleep 1
  echo "== $name server"
  local dev=(--device "$dir/client" --slave 1 --parity "$parity")
  expect "FC03 registers" '"values":[0,3,6,9,12]' "${dev[@]}" --function 3 --address 0 --quantity 5
  expect "FC04 input registers" '"values":[1010,1011]' "${dev[@]}" --function 4 --address 10 --quantity 2
  expect "FC01 coils" '"values":[0,1,0,1,0,1,0,1,0,1]' "${dev[@]}" --function 1 --address 0 --quantity 10
  expect "FC02 inputs" '"values":[1,0,0,1]' "${dev[@]}" --function 2 --address 0 --quantity 4
  expect "FC06 write" '"function":6,"address":20,"value":777' "${dev[@]}" --function 6 --address 20 --values 777
  expect "FC03 reads it back" '"values":[777]' "${dev[@]}" --function 3 --address 20 --quantity 1
  expect "FC10 write" '"function":16,"address":30,"quantity":3' "${dev[@]}" --function 16 --address 30 --values 7,8,9
  expect "FC03 reads them back" '"values":[7,8,9]' "${dev[@]}" --function 3 --address 30 --quantity 3
  expect "FC0F write coils" '"function":15,"address":40,"quantity":3' "${dev[@]}" --function 15 --address 40 --values 1,1,0
  expect "FC01 reads them back" '"values":[1,1,0]' "${dev[@]}" --function 1 --address 40 --quantity 3
  expect "FC05 write coil" '"function":5,"address":41,"value":0' "${dev[@]}" --function 5 --address 41 --values 0
  expect "exception 02 beyond the map" '"exception":2' "${dev[@]}" --function 3 --address 99 --quantity 5
  kill "$server_pid" 2>/dev/null || true
  kill "$socat_pid" 2>/dev/null || true
  wait "$server_pid" "$socat_pid" 2>/dev/null || true
  rm -rf "$dir"
}

run_against libmodbus N "$libmodbus_server"
run_against pymodbus N /usr/bin/python3 "$here/pymodbus_server.py"
exit "$status"
