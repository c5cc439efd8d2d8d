#!/usr/bin/env bash
# Starts the T-format master image under QEMU (semihosting console to a file, UART on a
# pseudo-terminal), serves it the TS5700N8500 emulator from the host (`motionbus serve
# tformat-encoder` on the terminal), and checks what the image reports it decoded: every
# transaction answered and checked against its request, the fields of each layout, ENID 0x11,
# no alarm, single-turn values below 2^17 (the emulator's shaft turns as time passes, so the
# positions are checked for range, not value).
# Usage: run_tformat_master.sh "QEMU -M BOARD [...]" IMAGE MOTIONBUS_CLI [IMAGE_LINE]
# IMAGE_LINE: a further line the report must hold (a regular expression): the interrupt-driven
# image's back-to-back counts.
set -euo pipefail
qemu="$1"
image="$2"
cli="$3"
image_line="${4:-}"
# shellcheck source=qemu_board.sh
source "$(dirname "${BASH_SOURCE[0]}")/qemu_board.sh"
qemu_start "$qemu" "$image" pty -semihosting
qemu_pty
"$cli" serve tformat-encoder --device "$pty" 2>/dev/null &
peer_pid=$!
for _ in $(seq 300); do
  grep -q '^done$' "$dir/qemu.log" && break
  sleep 0.1
done
echo "== $image reported:"
grep -v 'char device' "$dir/qemu.log" || true
status=0
expect() {  # NAME REGEX: one line of the report matches
  if grep -Eq "$2" "$dir/qemu.log"; then echo "ok   $1"; else echo "FAIL $1"; status=1; fi
}
range='(1[0-2][0-9]{4}|13[01][0-9]{3}|[0-9]{1,5})'  # 0..131999, then checked below 2^17
expect "ID3: answered, SF 0, ABS, ABM, ENID 17, no alarm" \
  "^id 3 ok sf 0 abs $range abm [0-9]+ enid 17 almc 0$"
expect "ID0: answered, ABS" "^id 0 ok sf 0 abs $range$"
expect "ID1: answered, ABM" "^id 1 ok sf 0 abm [0-9]+$"
expect "ID2: answered, ENID 17" "^id 2 ok sf 0 enid 17$"
expect "IDD: the EEPROM byte at address 5" "^id 13 ok sf 0 address 5 edf [0-9]+$"
expect "the report ends" "^done$"
if [ -n "$image_line" ]; then
  expect "the image's line: $image_line" "$image_line"
fi
if grep -Eo 'abs [0-9]+' "$dir/qemu.log" | awk '$2 >= 131072 {bad=1} END {exit bad}'; then
  echo "ok   single-turn values below 2^17"
else
  echo "FAIL a single-turn value of 2^17 or more"
  status=1
fi
exit "$status"
