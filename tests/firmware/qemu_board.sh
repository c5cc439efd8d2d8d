# Sourced by the firmware runners: starts an image under QEMU in the background and cleans up
# when the runner exits. Sets `dir` (a scratch directory), `qemu_pid` and, for a UART on a
# pseudo-terminal, `pty`; the QEMU log (and the semihosting console) is "$dir/qemu.log".
#   qemu_start "QEMU -M BOARD [...]" IMAGE SERIAL [OPTIONS...]   SERIAL: pty, or file:PATH
#   qemu_pty                     waits for the terminal QEMU made, then holds it open
dir="$(mktemp -d)"
qemu_pid=""
peer_pid=""
qemu_cleanup() {
  [ -n "$peer_pid" ] && kill "$peer_pid" 2>/dev/null || true
  [ -n "$qemu_pid" ] && kill "$qemu_pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap qemu_cleanup EXIT

qemu_start() {
  local qemu="$1" image="$2" serial="$3"
  shift 3
  # shellcheck disable=SC2086  # the QEMU command and its machine options are words
  $qemu -nographic -monitor none "$@" -serial "$serial" -kernel "$image" >"$dir/qemu.log" 2>&1 &
  qemu_pid=$!
}

qemu_pty() {
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
  # Hold the terminal open for the whole run: QEMU notices a reader only once a second, and
  # drops what the image sends while none is connected.
  exec 3<>"$pty"
}
