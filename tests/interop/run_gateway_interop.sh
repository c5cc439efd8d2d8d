#!/usr/bin/env bash
# libmodbus's and pymodbus's TCP clients through `motionbus gateway` to `motionbus serve
# sm-unit`, over a pseudo-terminal pair made by socat: every served function and its
# exceptions, 0A and 0B, 8 concurrent clients, bad MBAP input (the gateway told the SM unit's
# FC11 layout, --fc11 sm); then the gateway again with
# --read-only --units 1 --functions 3,4,6, and with --rtu-over-tcp (pymodbus's RTU framer);
# then `serve modbus --units 1-4` behind it, and alone with --tcp-listen.
# Usage: run_gateway_interop.sh MOTIONBUS_CLI LIBMODBUS_TCP_CLIENT
set -euo pipefail
cli="$1"
libmodbus_client="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
dir="$(mktemp -d)"
socat pty,raw,echo=0,link="$dir/unit" pty,raw,echo=0,link="$dir/master" 2>/dev/null &
socat_pid=$!
serve_pid=""
gateway_pid=""
cleanup() {
  [ -n "$gateway_pid" ] && kill "$gateway_pid" 2>/dev/null || true
  [ -n "$serve_pid" ] && kill "$serve_pid" 2>/dev/null || true
  kill "$socat_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
for _ in $(seq 50); do [ -e "$dir/master" ] && break; sleep 0.1; done
"$cli" serve sm-unit --device "$dir/unit" >/dev/null 2>&1 &
serve_pid=$!
timeout_ms=400
idle_ms=700
port=""
# gateway ARGS...: starts the gateway on a free port of 127.0.0.1; sets $port from its first
# line ({"listening":"127.0.0.1:PORT",...}).
gateway() {
  [ -n "$gateway_pid" ] && kill "$gateway_pid" 2>/dev/null && wait "$gateway_pid" 2>/dev/null
  : >"$dir/gateway.log"
  "$cli" gateway --listen 127.0.0.1:0 --device "$dir/master" --timeout-ms "$timeout_ms" \
    --idle-timeout-ms "$idle_ms" --json "$@" >"$dir/gateway.log" 2>&1 &
  gateway_pid=$!
  port=""
  for _ in $(seq 50); do
    port="$(sed -n 's/^{"listening":"127\.0\.0\.1:\([0-9]*\)".*/\1/p' "$dir/gateway.log")"
    [ -n "$port" ] && break
    sleep 0.1
  done
  [ -n "$port" ] || { echo "FAIL the gateway did not start"; cat "$dir/gateway.log"; exit 1; }
}
status=0
gateway --fc11 sm
echo "== pymodbus TCP client and raw MBAP sockets (port $port)"
/usr/bin/python3 "$here/pymodbus_gateway.py" full "$port" "$timeout_ms" "$idle_ms" || status=1
echo "== libmodbus TCP client"
"$libmodbus_client" "$port" "$timeout_ms" || status=1
echo "== motionbus read modbus --tcp"
out="$("$cli" read modbus --tcp "127.0.0.1:$port" --function 4 --slave 1 --address 100 \
  --quantity 9 --json 2>&1 || true)"
echo "$out"
case "$out" in
  *'"ok":true'*) ;;
  *) echo "FAIL read modbus --tcp"; status=1 ;;
esac
out="$("$cli" read modbus --tcp "127.0.0.1:$port" --function 3 --slave 5 --address 36 --json \
  2>&1 || true)"
echo "$out"
case "$out" in
  *'"ok":false'*'gateway_target_failed'*) ;;
  *) echo "FAIL read modbus --tcp of a silent unit: 0B"; status=1 ;;
esac
if grep -q '"transaction"' "$dir/gateway.log" && grep -q '"reason":"idle_timeout"' "$dir/gateway.log"; then
  echo "ok   the gateway logged the transactions and the idle timeout"
else
  echo "FAIL the gateway's log"; status=1
fi
gateway --read-only --units 1 --functions 3,4,6
echo "== the gateway's allow-lists (port $port)"
/usr/bin/python3 "$here/pymodbus_gateway.py" policy "$port" || status=1
gateway --rtu-over-tcp
echo "== RTU over TCP (port $port)"
/usr/bin/python3 "$here/pymodbus_gateway.py" rtu "$port" || status=1
echo "== serve modbus --units 1-4 behind the gateway"
kill "$serve_pid" 2>/dev/null; wait "$serve_pid" 2>/dev/null || true
"$cli" serve modbus --device "$dir/unit" --units 1-4 >/dev/null 2>&1 &
serve_pid=$!
gateway
/usr/bin/python3 "$here/pymodbus_gateway.py" generic "$port" gateway || status=1
echo "== serve modbus --tcp-listen --units 1-4"
kill "$gateway_pid" 2>/dev/null; wait "$gateway_pid" 2>/dev/null || true
gateway_pid=""
"$cli" serve modbus --tcp-listen 127.0.0.1:0 --units 1-4 --json >"$dir/serve.log" 2>&1 &
tcp_serve_pid=$!
port=""
for _ in $(seq 50); do
  port="$(sed -n 's/^{"listening":"127\.0\.0\.1:\([0-9]*\)".*/\1/p' "$dir/serve.log")"
  [ -n "$port" ] && break
  sleep 0.1
done
/usr/bin/python3 "$here/pymodbus_gateway.py" generic "$port" || status=1
kill "$tcp_serve_pid" 2>/dev/null || true
exit "$status"
