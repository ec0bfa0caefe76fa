#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Ctrl-C during `translucent pathtrace sphere` stops the pass cleanly and still writes the EXR and
# the JSON with "partial": true. Usage: sigint_render.sh <translucent binary> <output directory>
set -u
. "$(dirname "$0")/interrupt.sh"
exe=$1
exr=$2/render_sigint.exr
json=$2/render_sigint.json
rm -f "$exr" "$json"
"$exe" pathtrace sphere --material Marble --width 16 --height 16 --photons 1e15 --threads 2 \
  --exr "$exr" --json "$json" 2>/dev/null &
pid=$!
interrupt "$pid" || exit 1
if [ "$rc" -ne 130 ]; then echo "exit status $rc after SIGINT, expected 130"; exit 1; fi
if [ ! -f "$exr" ]; then echo "$exr was not written"; exit 1; fi
if [ ! -f "$json" ]; then echo "$json was not written"; exit 1; fi
grep -q '"partial": true' "$json" || { echo "no \"partial\": true in $json"; cat "$json"; exit 1; }
echo "ok: partial images written after SIGINT"
