#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Ctrl-C during `translucent pathtrace slab` stops the run cleanly and still writes the JSON with
# "partial": true. Usage: sigint.sh <translucent binary> <output directory>
# The signal is sent once the program has installed its handler (interrupt.sh says why).
set -u
. "$(dirname "$0")/interrupt.sh"
exe=$1
out=$2/pathtrace_sigint.json
rm -f "$out"
"$exe" pathtrace slab --sigma-a 0.01 --sigma-s 10 --eta 1.3 --photons 1e15 --threads 2 \
  --json "$out" 2>/dev/null &
pid=$!
interrupt "$pid" || exit 1
if [ "$rc" -ne 130 ]; then echo "exit status $rc after SIGINT, expected 130"; exit 1; fi
if [ ! -f "$out" ]; then echo "$out was not written"; exit 1; fi
grep -q '"partial": true' "$out" || { echo "no \"partial\": true in $out"; cat "$out"; exit 1; }
grep -q '"diffuse_reflectance_stderr"' "$out" || { echo "no estimates in $out"; exit 1; }
echo "ok: partial result written after SIGINT"
