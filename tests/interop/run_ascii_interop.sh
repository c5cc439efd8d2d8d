#!/usr/bin/env bash
# `motionbus read modbus --ascii` against pymodbus's ASCII server (ModbusAsciiFramer), then
# pymodbus's ASCII client against `motionbus serve modbus --ascii --units 1-4`, on a
# pseudo-terminal pair made by socat. Usage: run_ascii_interop.sh MOTIONBUS_CLI
set -euo pipefail
cli="$1"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
dir="$(mktemp -d)"
socat pty,raw,echo=0,link="$dir/server" pty,raw,echo=0,link="$dir/client" 2>/dev/null &
socat_pid=$!
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null || true
  kill "$socat_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
for _ in $(seq 50); do [ -e "$dir/client" ] && break; sleep 0.1; done
/usr/bin/python3 "$here/pymodbus_ascii_server.py" "$dir/server" >/dev/null 2>&1 &
server_pid=$!
sleep 1
status=0
# expect NAME PATTERN ARGS...: read modbus --ascii with ARGS, its JSON output matching PATTERN
expect() {
  local name="$1" pattern="$2"
  shift 2
  local out
  out="$("$cli" read modbus --device "$dir/client" --ascii --parity N --json "$@" 2>&1 || true)"
  case "$out" in
    $pattern) echo "ok   $name" ;;
    *) echo "FAIL $name: $out"; status=1 ;;
  esac
}
expect "FC03 three registers" '*"ok":true*"values":\[6,9,12\]*' \
  --function 3 --slave 1 --address 2 --quantity 3
expect "FC04 input registers" '*"ok":true*"values":\[1005,1006\]*' \
  --function 4 --slave 1 --address 5 --quantity 2
expect "FC06 a write, then FC03 reads it" '*"ok":true*' \
  --function 6 --slave 1 --address 7 --values 4660
expect "FC03 reads it back" '*"ok":true*"values":\[4660\]*' \
  --function 3 --slave 1 --address 7 --quantity 1
expect "FC03 past the data: exception 02" '*"ok":false,"error":"exception"*"exception":2*' \
  --function 3 --slave 1 --address 99 --quantity 5
expect "slave 9 does not answer: timeout" '*"ok":false,"error":"timeout"*' \
  --function 3 --slave 9 --address 0 --quantity 1 --timeout-ms 300
kill "$server_pid" 2>/dev/null; wait "$server_pid" 2>/dev/null || true
"$cli" serve modbus --device "$dir/server" --ascii --parity N --units 1-4 >/dev/null 2>&1 &
server_pid=$!
sleep 0.3
/usr/bin/python3 "$here/pymodbus_ascii_client.py" "$dir/client" || status=1
exit "$status"
