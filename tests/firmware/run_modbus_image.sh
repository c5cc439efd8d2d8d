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
# shellcheck source=qemu_board.sh
source "$here/qemu_board.sh"
qemu_start "$qemu" "$image" pty
qemu_pty
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
