#!/usr/bin/env bash
# Third-party Modbus masters (pymodbus, libmodbus) against `motionbus serve sm-unit`, over a
# pseudo-terminal pair made by socat. Usage: run_interop.sh MOTIONBUS_CLI LIBMODBUS_CLIENT
set -euo pipefail
cli="$1"
libmodbus_client="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
dir="$(mktemp -d)"
socat pty,raw,echo=0,link="$dir/unit" pty,raw,echo=0,link="$dir/master" 2>/dev/null &
socat_pid=$!
serve_pid=""
cleanup() {
  [ -n "$serve_pid" ] && kill "$serve_pid" 2>/dev/null || true
  kill "$socat_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
for _ in $(seq 50); do [ -e "$dir/master" ] && break; sleep 0.1; done
"$cli" serve sm-unit --device "$dir/unit" 2>/dev/null &
serve_pid=$!
sleep 0.3
status=0
echo "== pymodbus"
/usr/bin/python3 "$here/pymodbus_client.py" "$dir/master" || status=1
sleep 0.2
echo "== libmodbus"
"$libmodbus_client" "$dir/master" || status=1
sleep 0.2
echo "== motionbus read sm-unit (no login needed: libmodbus left the unit logged out)"
out="$("$cli" read sm-unit --device "$dir/master" --json 2>/dev/null || true)"
echo "$out"
case "$out" in
  *'"ok":true,"slave":1,"version":"1.0.0","voltage":{"value":'*) ;;
  *) echo "FAIL read sm-unit"; status=1 ;;
esac
echo "== motionbus read sm-unit --read password (logs in for the read, then out again)"
out="$("$cli" read sm-unit --device "$dir/master" --read password --json 2>/dev/null || true)"
echo "$out"
case "$out" in
  *'"logged_in":false,"logged_in_by_read":true,"login_restored":true,"password":"password"}'*) ;;
  *) echo "FAIL read sm-unit --read password"; status=1 ;;
esac
exit "$status"
