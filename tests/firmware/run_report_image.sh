#!/usr/bin/env bash
# Starts a firmware image that reports what it decoded as lines of text on its UART, under QEMU
# with the UART written to a file, until it prints "done" (30 s at most), then compares the
# lines with EXPECTED ('#' lines there are comments).
# Usage: run_report_image.sh "QEMU -M BOARD [...]" IMAGE EXPECTED
set -euo pipefail
qemu="$1"
image="$2"
expected="$3"
# shellcheck source=qemu_board.sh
source "$(dirname "${BASH_SOURCE[0]}")/qemu_board.sh"
qemu_start "$qemu" "$image" "file:$dir/uart.txt"
for _ in $(seq 300); do
  grep -q '^done$' "$dir/uart.txt" 2>/dev/null && break
  sleep 0.1
done
echo "== $image reported:"
cat "$dir/uart.txt" || true
grep -v '^#' "$expected" >"$dir/want.txt"
if diff -u "$dir/want.txt" "$dir/uart.txt"; then
  echo "ok   every line as expected"
else
  echo "FAIL the report differs (above)"
  exit 1
fi
