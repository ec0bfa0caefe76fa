#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# SIGTERM while `translucent compare` renders its techniques: the technique running is stopped,
# the run exits 143 and the report (written after each technique) is valid JSON with the
# techniques finished before the signal. Usage: sigterm_compare.sh <translucent binary> <scene>
# <work dir>
set -u
exe=$1
scene=$2
work=$3/compare_sigterm
rm -rf "$work"
mkdir -p "$work"
"$exe" compare "$scene" --techniques pointcloud,shah:irradiance_size=8192,splatting --budget 0 \
  --reference model --samples 2e3 --width 32 --height 24 --frames 1 --warmup 0 --threads 2 \
  --no-cache --out "$work/report" >"$work/log" 2>&1 &
pid=$!
i=0
# Until the point cloud is done and shah has started (the report then holds the point cloud).
until grep -q "technique 2/3: shah" "$work/log" 2>/dev/null; do
  if ! kill -0 "$pid" 2>/dev/null; then echo "compare ended before shah started"; cat "$work/log"; exit 1; fi
  i=$((i + 1))
  if [ "$i" -gt 1200 ]; then echo "shah never started"; kill -9 "$pid"; cat "$work/log"; exit 1; fi
  sleep 0.1
done
sleep 1
kill -TERM "$pid"
wait "$pid"
rc=$?
if [ "$rc" -ne 143 ]; then echo "exit status $rc after SIGTERM, expected 143"; cat "$work/log"; exit 1; fi
python3 - "$work/report/report.json" <<'PY' || { cat "$work/log"; exit 1; }
import json, sys
r = json.load(open(sys.argv[1]))
names = [x["name"] for x in r["techniques"]]
assert names == ["pointcloud"], names
assert r["techniques"][0].get("status") != "failed", r["techniques"][0]
assert r["partial"] is True, "not partial"
notes = " ".join(r["notes"])
assert "shah:irradiance_size=8192 stopped by SIGTERM" in notes, notes
assert "splatting not run" in notes, notes
assert any(m["test"] == "pointcloud" for m in r["metrics"]), "no metrics of pointcloud"
PY
[ -f "$work/report/index.html" ] || { echo "no index.html"; exit 1; }
[ -f "$work/report/pointcloud.exr" ] || { echo "no pointcloud.exr"; exit 1; }
echo "ok: SIGTERM kept the finished technique"
