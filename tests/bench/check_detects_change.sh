#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# gen-benchmarks --check must fail when a JSON number changes: copies bench/results, doubles the
# CPU time of the first result of bench_models.json, and expects --check to exit 1 naming the
# changed line; the unchanged copy must pass.
set -euo pipefail
src=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
cp -r "$src/bench/results" "$work/results"
python3 "$src/scripts/gen-benchmarks" --check --results "$work/results" >/dev/null \
  || { echo "FAIL: the unchanged copy of bench/results does not match BENCHMARKS.md"; exit 1; }
python3 - "$work/results/bench_models.json" <<'PY'
import json, sys
p = sys.argv[1]
d = json.load(open(p))
d["benchmarks"][0]["cpu_time"] *= 2
d["benchmarks"][0]["real_time"] *= 2
json.dump(d, open(p, "w"))
PY
set +e
python3 "$src/scripts/gen-benchmarks" --check --results "$work/results" > "$work/diff.txt"
rc=$?
set -e
if [[ $rc != 1 ]]; then echo "FAIL: --check exited $rc after a changed number (expected 1)"; cat "$work/diff.txt"; exit 1; fi
grep -q '^[-+]| `evaluate/' "$work/diff.txt" || { echo "FAIL: the diff does not show the changed row"; cat "$work/diff.txt"; exit 1; }
echo "PASS: a changed number is detected"
