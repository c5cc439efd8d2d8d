#!/usr/bin/env bash
# Starts a Modbus firmware image under QEMU with its UART on a pseudo-terminal and runs the
# back-to-back checks' sequence alone (tests/firmware/modbus_back_to_back.py): the runner of the
# deliberately broken interrupt-driven images, whose failure the checks must report.
# Usage: run_modbus_back_to_back.sh "QEMU -M BOARD [...]" IMAGE BAUD
set -euo pipefail
here="$(dirname "${BASH_SOURCE[0]}")"
# shellcheck source=qemu_board.sh
source "$here/qemu_board.sh"
qemu_start "$1" "$2" pty
qemu_pty
echo "== $2 on $pty"
/usr/bin/python3 "$here/modbus_back_to_back.py" "$pty" "$3" sequence
