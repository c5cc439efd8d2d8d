#!/usr/bin/env bash
# Starts a Modbus firmware image under QEMU with its UART on a pseudo-terminal, then checks it
# through `motionbus gateway` (Modbus TCP on 127.0.0.1 to the image's RTU line): each PEER is
# run with the argument tcp:PORT. PEERs written pty:PEER are run first, on the pty itself,
# before the gateway opens it. A PEER ending in .py runs with Debian's python3.
# Usage: run_modbus_image_gateway.sh "QEMU -M BOARD [...]" IMAGE FIRMWARE_TESTS_DIR
#        MOTIONBUS_CLI PEER...
set -euo pipefail
qemu="$1"
image="$2"
here="$3"
cli="$4"
shift 4
# shellcheck source=qemu_board.sh
source "$here/qemu_board.sh"
qemu_start "$qemu" "$image" pty
qemu_pty
echo "== $image on $pty"
# QEMU reads the terminal only once it has noticed a reader, which it looks for once a second:
# a request sent before then waits up to a second, beyond the gateway's response timeout. One
# read on the pty (5 s allowed) before anything is timed; no answer fails the run.
"$cli" read modbus --device "$pty" --slave 1 --function 3 --address 0 --quantity 1 \
  --timeout-ms 5000 >"$dir/ready.log" 2>&1 ||
  { echo "FAIL the image did not answer on $pty"; cat "$dir/ready.log"; exit 1; }
status=0
run_peer() {
  case "$1" in
    *.py) /usr/bin/python3 "$1" "$2" ;;
    *) "$1" "$2" ;;
  esac
}
for peer in "$@"; do
  case "$peer" in
    pty:*)
      echo "== ${peer#pty:} on the pty"
      run_peer "${peer#pty:}" "$pty" || status=1
      ;;
  esac
done
# The gateway's response timeout is below the clients' (3 s): a silent unit is its 0B.
: >"$dir/gateway.log"  # there before the loop below reads it
"$cli" gateway --listen 127.0.0.1:0 --device "$pty" --timeout-ms 800 --json \
  >"$dir/gateway.log" 2>&1 &
peer_pid=$!
port=""
for _ in $(seq 50); do
  port="$(sed -n 's/^{"listening":"127\.0\.0\.1:\([0-9]*\)".*/\1/p' "$dir/gateway.log")"
  [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$port" ] || { echo "FAIL the gateway did not start"; cat "$dir/gateway.log"; exit 1; }
for peer in "$@"; do
  case "$peer" in
    pty:*) ;;
    *)
      echo "== $peer through the gateway (port $port)"
      run_peer "$peer" "tcp:$port" || status=1
      ;;
  esac
done
exit "$status"
