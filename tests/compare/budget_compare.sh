#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# `translucent compare --budget`: a technique that runs past its budget is stopped and listed as
# over budget in report.json and index.html while the others finish; the run exits 0 and prints
# each technique's progress with an ETA. shah with the largest irradiance buffer (8192², a
# full-screen splat per texel) cannot finish in the budget on any renderer; the point cloud at
# 32x24 finishes well within it. With a fourth argument `gpu` the reference is the physical one
# traced on the GPU in compare's own process first: the techniques' worker processes are fresh
# programs, so the budget holds then too (a forked child could not use the parent's GL driver).
# Usage: budget_compare.sh <translucent binary> <scene> <work dir> [gpu]
set -u
exe=$1
scene=$2
work=$3/compare_budget${4:+_$4}
rm -rf "$work"
mkdir -p "$work"
reference="--reference model --samples 2e3"
[ "${4:-}" = gpu ] && reference="--reference physical --photons 2e3 --reference-device gpu"
# shellcheck disable=SC2086
"$exe" compare "$scene" --techniques pointcloud,shah:irradiance_size=8192 --budget 20 \
  $reference --width 32 --height 24 --frames 1 --warmup 0 --threads 2 \
  --no-cache --out "$work/report" >"$work/log" 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then echo "exit status $rc, expected 0"; cat "$work/log"; exit 1; fi
json=$work/report/report.json
[ -f "$json" ] || { echo "$json was not written"; cat "$work/log"; exit 1; }
python3 - "$json" <<'PY' || { cat "$work/log"; exit 1; }
import json, sys
r = json.load(open(sys.argv[1]))
t = {x["name"]: x for x in r["techniques"]}
assert set(t) == {"pointcloud", "shah:irradiance_size=8192"}, list(t)
assert t["pointcloud"].get("status") != "failed" and "error" not in t["pointcloud"], t["pointcloud"]
over = t["shah:irradiance_size=8192"]
assert over["status"] == "over budget", over
assert over["error"].startswith("over budget: stopped after"), over["error"]
assert any(m["test"] == "pointcloud" for m in r["metrics"]), "no metrics of pointcloud"
assert not any(m["test"].startswith("shah") for m in r["metrics"]), "metrics of shah"
assert r["settings"]["budget"] == "20", r["settings"]
PY
grep -q "over budget" "$work/report/index.html" || { echo "index.html does not say over budget"; exit 1; }
grep -q "technique 2/2: shah:irradiance_size=8192 (elapsed .*, ETA " "$work/log" ||
  { echo "no progress line with an ETA"; cat "$work/log"; exit 1; }
echo "ok: shah over budget, pointcloud in the report"
