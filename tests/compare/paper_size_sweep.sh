#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# scripts/paper-experiment size-sweep at one small size and few photons: it runs compare, writes
# the figure, the page and the JSON, and every column of the table has a number.
# Usage: paper_size_sweep.sh <python> <script> <translucent binary> <work dir>
set -u
py=$1
script=$2
exe=$3
work=$4/paper_size_sweep
rm -rf "$work"
"$py" "$script" size-sweep --cli "$exe" --out "$work" --only 20 --photons 2e4 --samples 2e3 >"$work.log" 2>&1 ||
  { echo "the script failed"; cat "$work.log"; exit 1; }
for f in size-sweep.png size-sweep.md size-sweep.json size-sweep-20/report.json; do
  [ -s "$work/$f" ] || { echo "missing $f"; exit 1; }
done
"$py" - "$work/size-sweep.json" <<'PY' || exit 1
import json, sys
d = json.load(open(sys.argv[1]))
row = d["rel_rmse"]["20"]
want = [f"{t} vs {r}" for t in ("tsis", "tsis:mode=hybrid:samples=900", "pointcloud")
        for r in ("model", "physical")] + ["model vs physical"]
missing = [c for c in want if not (c in row and row[c] > 0)]
if missing:
    sys.exit(f"no number for {missing}")
print("ok:", {c: round(row[c], 4) for c in want})
PY
