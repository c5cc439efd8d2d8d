#!/usr/bin/env bash
# Starts the T-format encoder image under QEMU with its UART on a pseudo-terminal, then reads it
# with the motionbus CLI and raw bytes (tformat_encoder_checks.py).
# Usage: run_tformat_image.sh "QEMU -M BOARD [...]" IMAGE FIRMWARE_TESTS_DIR MOTIONBUS_CLI
set -euo pipefail
qemu="$1"
image="$2"
here="$3"
cli="$4"
# shellcheck source=qemu_board.sh
source "$here/qemu_board.sh"
qemu_start "$qemu" "$image" pty
qemu_pty
echo "== $image on $pty"
/usr/bin/python3 "$here/tformat_encoder_checks.py" "$pty" "$cli"
