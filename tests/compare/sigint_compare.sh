#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Ctrl-C during the physical reference of `translucent compare` keeps what is done: the tracer
# stops, the techniques still render, and the report is written with the reference marked
# partial, which is not cached. Usage: sigint_compare.sh <translucent binary> <scene> <work dir>
set -u
. "$(dirname "$0")/../reference/interrupt.sh"
exe=$1
scene=$2
work=$3/compare_sigint
rm -rf "$work"
mkdir -p "$work"
TRANSLUCENT_CACHE_DIR="$work/technique-cache" "$exe" compare "$scene" --techniques pointcloud \
  --reference physical,model --photons 1e15 --width 24 --height 18 --frames 1 --warmup 0 \
  --threads 2 --cache "$work/cache" --out "$work/report" >"$work/log" 2>&1 &
pid=$!
interrupt "$pid" || exit 1
if [ "$rc" -ne 130 ]; then echo "exit status $rc after SIGINT, expected 130"; cat "$work/log"; exit 1; fi
json=$work/report/report.json
if [ ! -f "$json" ]; then echo "$json was not written"; cat "$work/log"; exit 1; fi
grep -q '"partial": true' "$json" || { echo "no \"partial\": true in $json"; exit 1; }
grep -q 'model reference skipped' "$json" || { echo "the model reference was not skipped"; exit 1; }
[ -f "$work/report/index.html" ] || { echo "no index.html"; exit 1; }
[ -f "$work/report/pointcloud.exr" ] || { echo "the technique was not rendered"; exit 1; }
if ls "$work/cache"/physical-*.json >/dev/null 2>&1; then echo "a partial reference was cached"; exit 1; fi
echo "ok: partial report written after SIGINT"
