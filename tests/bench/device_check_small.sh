#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# scripts/device-check --small on this machine's OpenGL (llvmpipe without a GPU): it must finish,
# write one JSON file per GPU benchmark program with results and no errors, and print the tables.
set -euo pipefail
src=$1
build=$2
out=$3
rm -rf "$out"
start=$(date +%s)
bash "$src/scripts/device-check" --small --build "$build" --out "$out" > "$out.log" 2>&1 \
  || { tail -40 "$out.log"; echo "FAIL: device-check --small failed"; exit 1; }
elapsed=$(( $(date +%s) - start ))
programs=$(python3 "$src/scripts/bench" --list --gpu-only --small | sed 's|.*/bin/\([a-z_]*\).*|\1|')
for p in $programs; do
  python3 - "$out/$p.json" <<'PY' || { echo "FAIL: $p"; exit 1; }
import json, sys
d = json.load(open(sys.argv[1]))
rows = d["benchmarks"]
assert rows, "no results"
bad = [b["name"] for b in rows if b.get("error_occurred")]
assert not bad, f"errors in {bad}"
t = d["translucent"]
assert t["mode"] == "small" and t["wall_s"] > 0 and t["machine"]["cores"] > 0
PY
done
grep -q "^## bench_techniques" "$out.log" || { echo "FAIL: no summary printed"; exit 1; }
echo "PASS: device-check --small wrote $(echo $programs | wc -w) result files in ${elapsed} s"
