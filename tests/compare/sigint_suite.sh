#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Ctrl-C during the first scene of `translucent compare --suite` stops the suite: that scene's
# report is written partial (as a single compare's), the scenes after it are not run, and the
# leaderboard of what is done is written, marked partial.
# Usage: sigint_suite.sh <translucent binary> <cube scene> <work dir>
set -u
. "$(dirname "$0")/../reference/interrupt.sh"
exe=$1
scene=$2
work=$3/compare_suite_sigint
rm -rf "$work"
mkdir -p "$work/suite"
mesh=$(cd "$(dirname "$scene")/../meshes" && pwd)/cube.obj
for n in a-first b-second; do
  sed "s|\"../meshes/cube.obj\"|\"$mesh\"|" "$scene" >"$work/suite/$n.json"
done
TRANSLUCENT_CACHE_DIR="$work/technique-cache" "$exe" compare --suite "$work/suite" \
  --techniques empirical --photons 1e15 --width 24 --height 18 --frames 1 --warmup 0 \
  --threads 2 --cache "$work/cache" --out "$work/out" >"$work/log" 2>&1 &
pid=$!
interrupt "$pid" || exit 1
if [ "$rc" -ne 130 ]; then echo "exit status $rc after SIGINT, expected 130"; cat "$work/log"; exit 1; fi
json=$work/out/leaderboard.json
if [ ! -f "$json" ]; then echo "$json was not written"; cat "$work/log"; exit 1; fi
grep -q '"partial": true' "$json" || { echo "no \"partial\": true in $json"; exit 1; }
grep -q '"status": "partial"' "$json" || { echo "the first scene is not marked partial"; exit 1; }
grep -q 'not run (Ctrl-C)' "$json" || { echo "the second scene is not marked not run"; exit 1; }
grep -q 'Partial' "$work/out/leaderboard.md" || { echo "leaderboard.md not marked partial"; exit 1; }
[ -f "$work/out/a-first/index.html" ] || { echo "no report of the first scene"; exit 1; }
[ -e "$work/out/b-second" ] && { echo "the second scene was run"; exit 1; }
echo "ok: partial leaderboard written after SIGINT"
