#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# `translucent compare` of a scene lit by an environment map, with a reference cache: the parent
# process writes (first run) and reads (second run) the reference's EXR before it forks the
# process that renders the techniques, which reads the environment map's EXR. OpenEXR's worker
# threads do not survive a fork: with a thread pool the child waited for them forever. Both runs
# must finish, within the ctest timeout, with the technique in the report.
# Usage: environment_compare.sh <translucent binary> <cube scene> <work dir>
set -u
exe=$1
scene=$2
work=$3/compare_environment
rm -rf "$work"
mkdir -p "$work"
# An environment map: any small EXR image (the cube rendered by the path tracer, 16x8).
"$exe" pathtrace mesh --scene "$scene" --photons 2e4 --threads 2 --exr "$work/env.exr" \
  >"$work/log-env" 2>&1 || { echo "could not make the map"; cat "$work/log-env"; exit 1; }
mesh=$(cd "$(dirname "$scene")/../meshes" && pwd)/cube.obj
cat >"$work/scene.json" <<JSON
{
  "mesh": {"file": "$mesh"},
  "material": {"preset": "Marble", "scale": 10.0},
  "lights": [{"type": "environment", "file": "$work/env.exr", "intensity": 1.0, "occlusion": true}],
  "camera": {"type": "pinhole", "position": [1.8, 1.4, 2.4], "look_at": [0, 0, 0],
             "up": [0, 1, 0], "fov": 40, "width": 24, "height": 18}
}
JSON
for run in 1 2; do
  TRANSLUCENT_CACHE_DIR="$work/technique-cache" "$exe" compare "$work/scene.json" \
    --techniques pointcloud:points=2000:ibl_samples=4 --reference physical --photons 2e4 \
    --frames 1 --warmup 0 --threads 2 --cache "$work/cache" --force --out "$work/report" \
    >"$work/log$run" 2>&1
  rc=$?
  if [ "$rc" -ne 0 ]; then echo "run $run: exit status $rc"; cat "$work/log$run"; exit 1; fi
  grep -q '"test": *"pointcloud' "$work/report/report.json" ||
    { echo "run $run: no pointcloud metrics"; cat "$work/log$run"; exit 1; }
done
grep -q "reused from the cache" "$work/log2" || { echo "run 2 did not reuse the reference"; exit 1; }
echo "ok: both runs finished"
