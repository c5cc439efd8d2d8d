#!/usr/bin/env bash
# The PulseView pictures of docs/sigrok.md and docs/python.md: Debian's pulseview, under Xvfb,
# showing the `tformat` decoder (stacked on `uart`) on examples/captures/tformat.sr and the
# `biss` decoder on examples/captures/biss.sr.
#
#   bash tools/scripts/pulseview_screenshot.sh [OUT_DIR]      (default docs/images)
#
# Needs the motionbus package importable by the interpreter libsigrokdecode embeds (Debian's
# python3.11: the installed package, docs/python.md, or PYTHONPATH=<build>/python) and the
# Debian packages below (installed through ensure-packages.sh when missing). PulseView runs
# with a throw-away HOME (no saved settings), one capture at a time, with a session setup file
# (.pvs, written here) that adds the decoders, their options and channels and the zoom; once
# the decoders have run, the root window is captured with ImageMagick's `import`.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/docs/images}"
bash "$root/tools/scripts/ensure-packages.sh" pulseview xvfb xauth xdotool imagemagick

if ! /usr/bin/python3 -c 'import motionbus' 2>/dev/null; then
  echo "pulseview_screenshot: the motionbus package is not importable by /usr/bin/python3 (docs/python.md)" >&2
  exit 1
fi

work="$(mktemp -d)"
xvfb_pid=""
pv_pid=""
cleanup() {
  if [ -n "$pv_pid" ]; then kill "$pv_pid" 2>/dev/null || true; fi
  if [ -n "$xvfb_pid" ]; then kill "$xvfb_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

width=1600
height=600
display=":$((90 + RANDOM % 100))"
Xvfb "$display" -screen 0 "${width}x${height}x24" -nolisten tcp >"$work/xvfb.log" 2>&1 &
xvfb_pid=$!
for _ in $(seq 50); do
  DISPLAY=$display xdotool getdisplaygeometry >/dev/null 2>&1 && break
  sleep 0.1
done

# A QSettings byte array of a GVariant int64 (the uart decoder's baud rate): \xHH each byte.
int64_bytes() {
  /usr/bin/python3 -c 'import struct,sys; print("".join("\\x%x" % b for b in struct.pack("<q", int(sys.argv[1]))))' "$1"
}

# shot NAME CAPTURE HEIGHT PAN: PulseView on CAPTURE with $work/NAME.pvs (its zoom), a window
# HEIGHT pixels high, the view dragged PAN pixels to the left (later in time).
shot() {
  local name="$1" capture="$2" h="$3" pan="$4"
  mkdir -p "$work/home-$name"
  HOME="$work/home-$name" XDG_CONFIG_HOME="$work/home-$name/.config" \
    XDG_RUNTIME_DIR="$work/home-$name" DISPLAY=$display \
    SIGROKDECODE_DIR="$root/sigrok/decoders" \
    pulseview -c -D -i "$capture" -s "$work/$name.pvs" >"$work/$name.log" 2>&1 &
  pv_pid=$!
  local wid=""
  for _ in $(seq 100); do
    wid="$(DISPLAY=$display xdotool search --onlyvisible --name 'PulseView' 2>/dev/null | head -n 1 || true)"
    [ -n "$wid" ] && break
    sleep 0.2
  done
  if [ -z "$wid" ]; then
    cat "$work/$name.log" >&2
    echo "pulseview_screenshot: no PulseView window" >&2
    exit 1
  fi
  DISPLAY=$display xdotool windowmove "$wid" 0 0 windowsize "$wid" "$width" "$h"
  sleep "${SETTLE:-6}"                        # loading, decoding, drawing
  # Pan by dragging the traces with the mouse, in steps of at most 700 pixels.
  local left=$pan step
  while [ "$left" -gt 0 ]; do
    step=$((left > 700 ? 700 : left))
    DISPLAY=$display xdotool mousemove --sync 800 "$((h - 60))" mousedown 1
    for i in $(seq 1 10); do
      DISPLAY=$display xdotool mousemove --sync "$((800 - step * i / 10))" "$((h - 60))"
    done
    DISPLAY=$display xdotool mouseup 1
    left=$((left - step))
  done
  DISPLAY=$display xdotool mousemove 0 "$((h - 1))"  # no hover marker on the traces
  sleep 1
  DISPLAY=$display import -window root -crop "${width}x${h}+0+0" "$work/$name.png"
  kill "$pv_pid"
  wait "$pv_pid" 2>/dev/null || true
  pv_pid=""
  if grep -q -E 'Traceback|ImportError|[Ff]ailed to' "$work/$name.log"; then
    cat "$work/$name.log" >&2
    echo "pulseview_screenshot: PulseView reported an error" >&2
    exit 1
  fi
  mkdir -p "$out"
  # 64 colours: the picture stays small (and legible).
  convert "$work/$name.png" -colors 64 -strip "$out/pulseview_$name.png"
  echo "$out/pulseview_$name.png"
}

# pvs NAME SIGNAL_NAME SCALE: $work/NAME.pvs, a PulseView session setup (QSettings ini) with
# one decode signal whose decoder stack and channel mapping come on stdin, and the view's zoom
# (SCALE seconds a pixel).
pvs() {
  { printf '[General]\ndecode_signals=1\nviews=1\n\n[decode_signal0]\nname=%s\n' "$2"
    cat
    printf '\n[view0]\nscale=%s\n' "$3"; } >"$work/$1.pvs"
}

pvs tformat T-format 4.5e-8 <<EOF
decoders=2
decoder0\\id=uart
decoder0\\visible=true
decoder0\\options=1
decoder0\\option0\\name=baudrate
decoder0\\option0\\type=x
decoder0\\option0\\value=@ByteArray($(int64_bytes 2500000))
decoder0\\row0\\visible=false
decoder1\\id=tformat
decoder1\\visible=true
decoder1\\options=0
channels=2
channel0\\name=RX
channel0\\assigned_signal_name=line
channel1\\name=TX
EOF

pvs biss BiSS-C 3.6e-8 <<EOF
decoders=1
decoder0\\id=biss
decoder0\\visible=true
decoder0\\options=0
channels=2
channel0\\name=MA
channel0\\assigned_signal_name=MA
channel1\\name=SLO
channel1\\assigned_signal_name=SLO
EOF

# tformat.sr: the ID3 exchange (81 to 132 us) at 45 ns a pixel, after a pan of 72 us.
shot tformat "$root/examples/captures/tformat.sr" 330 1600
# biss.sr: the first frame (5 to 50 us) and the start of the timeout, from the capture's start.
shot biss "$root/examples/captures/biss.sr" 300 0
