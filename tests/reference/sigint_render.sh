#!/bin/sh
# Ctrl-C during `translucent pathtrace sphere` stops the pass cleanly and still writes the EXR and
# the JSON with "partial": true. Usage: sigint_render.sh <translucent binary> <output directory>
set -u
exe=$1
exr=$2/render_sigint.exr
json=$2/render_sigint.json
rm -f "$exr" "$json"
"$exe" pathtrace sphere --preset Marble --width 16 --height 16 --photons 1e15 --threads 2 \
  --exr "$exr" --json "$json" 2>/dev/null &
pid=$!
# Wait until the program has installed its SIGINT handler (bit 2 of SigCgt in /proc; SIGINT is
# signal 2), so that a slow start under load does not turn the test into a plain kill. Until the
# exec, $pid is a copy of this shell, whose own SIGINT handler shows in SigCgt too; after the exec
# a background job starts with SIGINT ignored, so a signal sent then would be lost and the run
# would go on for 1e15 photons. Hence: the process must be translucent itself (comm) first.
i=0
while [ "$i" -lt 300 ]; do
  caught=""
  if [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "translucent" ]; then
    caught=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
  fi
  last=${caught#"${caught%?}"}
  if [ -n "$last" ] && [ $((0x$last & 2)) -ne 0 ]; then break; fi
  sleep 0.1
  i=$((i + 1))
done
sleep 0.5
kill -INT "$pid"
wait "$pid"
rc=$?
if [ "$rc" -ne 0 ]; then echo "exit status $rc after SIGINT"; exit 1; fi
if [ ! -f "$exr" ]; then echo "$exr was not written"; exit 1; fi
if [ ! -f "$json" ]; then echo "$json was not written"; exit 1; fi
grep -q '"partial": true' "$json" || { echo "no \"partial\": true in $json"; cat "$json"; exit 1; }
echo "ok: partial images written after SIGINT"
