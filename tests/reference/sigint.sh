#!/bin/sh
# Ctrl-C during `translucent pathtrace slab` stops the run cleanly and still writes the JSON with
# "partial": true. Usage: sigint.sh <translucent binary> <output directory>
#
# A background job of a non-interactive shell starts with SIGINT ignored, so the signal is sent
# only once the program has installed its handler (SigCgt in /proc/<pid>/status), however slowly
# it starts under load. Until the exec, $pid is a copy of this shell, whose own SIGINT handler
# shows in SigCgt too: the process must be translucent itself (comm) first.
set -u
exe=$1
out=$2/pathtrace_sigint.json
rm -f "$out"
"$exe" pathtrace slab --sigma-a 0.01 --sigma-s 10 --eta 1.3 --photons 1e15 --threads 2 \
  --json "$out" 2>/dev/null &
pid=$!
caught=0
for i in $(seq 1 600); do
  mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
  if [ -z "$mask" ]; then break; fi  # the program is gone
  if [ "$(cat "/proc/$pid/comm" 2>/dev/null)" != "translucent" ]; then sleep 0.1; continue; fi
  low=${mask#????????}  # the low 32 bits (hex) fit the shell's arithmetic
  if [ $(( 0x$low & 2 )) -ne 0 ]; then caught=1; break; fi  # SIGINT (2) is bit 1
  sleep 0.1
done
if [ "$caught" -ne 1 ]; then echo "the program never installed a SIGINT handler"; kill "$pid"; exit 1; fi
sleep 0.5  # let it trace a little
kill -INT "$pid"
wait "$pid"
rc=$?
if [ "$rc" -ne 0 ]; then echo "exit status $rc after SIGINT"; exit 1; fi
if [ ! -f "$out" ]; then echo "$out was not written"; exit 1; fi
grep -q '"partial": true' "$out" || { echo "no \"partial\": true in $out"; cat "$out"; exit 1; }
grep -q '"diffuse_reflectance_stderr"' "$out" || { echo "no estimates in $out"; exit 1; }
echo "ok: partial result written after SIGINT"
