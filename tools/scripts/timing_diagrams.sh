#!/usr/bin/env bash
# The timing diagrams of docs/timing/ (docs/tformat.md, modbus.md, biss.md): WaveJSON from the
# library's encoders through the Python package, rendered to SVG by WaveDrom's wavedrom-cli.
#
#   bash tools/scripts/timing_diagrams.sh
#
# Needs the package importable by /usr/bin/python3 (docs/python.md: the installed package, or
# PYTHONPATH=<build>/python) and npm (Debian's `npm`): wavedrom-cli is installed from the npm
# registry into tools/wavedrom/node_modules (not committed) at the versions of
# tools/wavedrom/package-lock.json, without install scripts (only the SVG output is used).
# Each SVG starts with a comment holding the SHA-256 of the WaveJSON it was made from; the
# pytest suite checks the WaveJSON against the encoders and the SVGs against the WaveJSON.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="$root/docs/timing"
tools="$root/tools/wavedrom"
python=${PYTHON:-/usr/bin/python3}

if [ ! -x "$tools/node_modules/.bin/wavedrom-cli" ]; then
  (cd "$tools" && npm ci --ignore-scripts --no-audit --no-fund)
fi

mkdir -p "$out"
rm -f "$out"/*.json "$out"/*.svg
names=$("$python" "$root/tools/scripts/timing_diagrams.py" --write "$out")
for name in $names; do
  json="$out/$name.json"
  svg="$out/$name.svg"
  tmp="$(mktemp --suffix=.svg)"
  "$tools/node_modules/.bin/wavedrom-cli" -i "$json" -s "$tmp"
  sum="$(sha256sum "$json" | cut -d' ' -f1)"
  { printf '<!-- WaveDrom rendering of %s.json, sha256 %s (tools/scripts/timing_diagrams.sh) -->\n' "$name" "$sum"
    cat "$tmp"; } >"$svg"
  rm -f "$tmp"
  echo "$svg"
done
