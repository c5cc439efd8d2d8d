#!/usr/bin/env bash
# Starts a Modbus firmware image under QEMU with its UART on a pseudo-terminal, then checks it
# from the host: raw bytes (broadcast, other slave, unknown function, garbage, bad CRC), then
# pymodbus and libmodbus masters (the interop clients), in that order on one power-up.
# Usage: run_modbus_image.sh "QEMU -M BOARD [...]" IMAGE FIRMWARE_TESTS_DIR PYMODBUS_SCRIPT
#        LIBMODBUS_CLIENT [DEVICE_CHECKS]
# DEVICE_CHECKS: a further raw-byte check script for the image's device (the SM unit's login).
set -euo pipefail
qemu="$1"
image="$2"
here="$3"
pymodbus_script="$4"
libmodbus_client="$5"
device_checks="${6:-}"
dir="$(mktemp -d)"
qemu_pid=""
cleanup() {
  [ -n "$qemu_pid" ] && kill "$qemu_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
# shellcheck disable=SC2086  # the QEMU command and its machine options are words
$qemu -nographic -monitor none -serial pty -kernel "$image" >"$dir/qemu.log" 2>&1 &
qemu_pid=$!
pty=""
for _ in $(seq 100); do
  pty="$(grep -o '/dev/pts/[0-9]*' "$dir/qemu.log" | head -n 1 || true)"
  [ -n "$pty" ] && break
  sleep 0.1
done
if [ -z "$pty" ]; then
  echo "FAIL: QEMU gave no pseudo-terminal"
  cat "$dir/qemu.log"
  exit 1
fi
# Hold the terminal open for the whole run: QEMU notices a reader only once a second, and drops
# what the image sends while none is connected.
exec 3<>"$pty"
echo "== $image on $pty"
status=0
echo "== raw bytes"
/usr/bin/python3 "$here/modbus_raw_checks.py" "$pty" 1 || status=1
if [ -n "$device_checks" ]; then
  echo "== the device's own rules"
  /usr/bin/python3 "$device_checks" "$pty" || status=1
fi
echo "== pymodbus"
/usr/bin/python3 "$pymodbus_script" "$pty" || status=1
echo "== libmodbus"
"$libmodbus_client" "$pty" || status=1
exit "$status"
