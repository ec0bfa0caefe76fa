#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# SIGTERM (what kill, timeout and Slurm send) and SIGINT (Ctrl-C) stop long work cleanly: the
# partial outputs must exist and be valid, with the exit status 143 (SIGTERM) or 130 (SIGINT).
# Usage: signals.sh <translucent binary> <work folder> <case>, case one of slab-TERM, slab-INT,
# sphere-TERM, integrate-TERM, render-frames-TERM.
set -u
exe=$1
work=$2/$3
case=$3
rm -rf "$work"
mkdir -p "$work"
signal=${case##*-}
expected=143
signo=15
[ "$signal" = INT ] && expected=130 && signo=2

# A JSON file that parses, says "partial": true and counts more than 0 of `key` (unless "").
check_json() {
  python3 - "$1" "$2" <<'PY' || exit 1
import json, sys
path, key = sys.argv[1], sys.argv[2]
with open(path) as f:
    j = json.load(f)
if j.get("partial") is not True:
    sys.exit(f"{path}: \"partial\" is {j.get('partial')!r}, expected true")
if key:
    n = j.get(key)
    if not isinstance(n, (int, float)) or n <= 0:
        sys.exit(f"{path}: {key} is {n!r}, expected > 0")
print(f"{path}: partial")
PY
}

# run SECONDS ARGS...: the command, sent the signal SECONDS after it began to catch it (bit
# signo-1 of SigCgt: the handler of the first long work; a signal before that ends the program at
# once, with nothing to keep). As `timeout --preserve-status -s SIGNAL` would, but not counting a
# slow start on a loaded machine. Sets $rc and checks it.
run() {
  seconds=$1
  shift
  "$exe" "$@" >"$work/log" 2>&1 &
  pid=$!
  bit=$((1 << (${signo} - 1)))
  i=0
  while [ "$i" -lt 600 ]; do
    caught=""
    [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = translucent ] &&
      caught=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
    [ -n "$caught" ] && [ $((0x$caught & bit)) -ne 0 ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
    i=$((i + 1))
  done
  sleep "$seconds"
  kill -s "$signal" "$pid"
  wait "$pid"
  rc=$?
  if [ "$rc" -ne "$expected" ]; then
    echo "exit status $rc after SIG$signal, expected $expected"
    cat "$work/log"
    exit 1
  fi
}

case $case in
  slab-*)
    # Signalled a second after its handler is installed (run): under `timeout 3` a loaded machine
    # sometimes had not begun the work yet, and a signal before the work ends the program at once
    # with the same status 143/130 and nothing written.
    run 1 pathtrace slab --sigma-a 0.01 --sigma-s 10 --eta 1.3 --photons 1e15 --threads 2 \
      --json "$work/slab.json"
    check_json "$work/slab.json" photons
    grep -q "stopped early by " "$work/log" || { echo "no 'stopped early by' in the log"; cat "$work/log"; exit 1; }
    ;;
  sphere-*)
    run 1 pathtrace sphere --material Marble --width 16 --height 16 --photons 1e15 --threads 2 \
      --device cpu --exr "$work/sphere.exr" --json "$work/sphere.json"
    [ -s "$work/sphere.exr" ] || { echo "no EXR"; exit 1; }
    check_json "$work/sphere.json" photons_per_channel
    ;;
  integrate-*)
    run 1 integrate sphere --material Marble --width 16 --height 16 --samples 1e9 --threads 2 \
      --exr "$work/integrate.exr" --json "$work/integrate.json"
    [ -s "$work/integrate.exr" ] || { echo "no EXR"; exit 1; }
    check_json "$work/integrate.json" ""
    ;;
  render-frames-*)
    # The frames rendered before the signal are written (numbered from 0), the rest are not.
    run 2 render --technique pointcloud --width 32 --height 24 --frames 100000 \
      --out "$work/frame_%06d.png"
    [ -s "$work/frame_000000.png" ] || { echo "no frame written"; cat "$work/log"; exit 1; }
    [ -e "$work/frame_099999.png" ] && { echo "the last frame exists"; exit 1; }
    ls "$work"/.*tmp* >/dev/null 2>&1 && { echo "temporary files left"; exit 1; }
    ;;
  *) echo "unknown case $case"; exit 1 ;;
esac
echo "ok: $case: partial outputs written, exit status $rc"
