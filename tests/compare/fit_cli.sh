#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# translucent fit end to end: the empirical shader fitted to the cube's model reference (cheap:
# 2e4 samples at 32x24) writes its files, never ends worse than it started, its fitted scene
# renders, a rerun replaces the previous fit, and a folder holding a user's file is refused with
# the file untouched; relative scene names work in fit's outputs and in compare's workers.
# Usage: fit_cli.sh TRANSLUCENT CUBE_SCENE WORK_DIR
set -eu
T=$1
SCENE=$2
W=$3/fit_cli
rm -rf "$W"
mkdir -p "$W"
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { "$T" fit empirical "$SCENE" --reference model --samples 2e4 --width 32 --height 24 \
          --no-cache --max-evaluations 60 --out "$W/out" 2>"$W/log"; }
run || { cat "$W/log"; fail "fit exited $?"; }
for f in fit.md fit.json cube.json cube-fitted.json; do
  [ -s "$W/out/$f" ] || fail "no $f"
done
python3 - "$W/out" <<'PY' || fail "fit.json"
import json, sys
d = sys.argv[1]
j = json.load(open(f"{d}/fit.json"))
assert j["generator"] == "translucent fit", j
row = j["scenes"][0]
assert row["scene"] == "cube" and row["after"] <= row["before"], row
s = json.load(open(f"{d}/cube.json"))
assert 0 < s["evaluations"] <= 60, s
assert set(s["parameters_after"]) == set(s["parameters_before"]), s
fitted = json.load(open(f"{d}/cube-fitted.json"))
assert fitted["technique"]["name"] == "empirical", fitted["technique"]
for k, v in s["parameters_after"].items():
    assert abs(fitted["technique"][k] - v) <= 1e-12 * max(1.0, abs(v)), (k, v)
PY
grep -q "| cube |" "$W/out/fit.md" || fail "fit.md has no row for the cube"
"$T" render "$W/out/cube-fitted.json" --out "$W/fitted.png" 2>"$W/render.log" ||
  { cat "$W/render.log"; fail "the fitted scene does not render"; }
# A rerun replaces the previous fit.
run || { cat "$W/log"; fail "a rerun into the previous fit's folder failed"; }
# A folder with a user's file is refused; the file stays.
mkdir -p "$W/mine"
echo keep > "$W/mine/notes.txt"
if "$T" fit empirical "$SCENE" --reference model --samples 2e4 --width 32 --height 24 --no-cache \
     --max-evaluations 5 --out "$W/mine" 2>"$W/mine.log"; then fail "a folder with a user's file was used"; fi
grep -q "not part of a previous fit" "$W/mine.log" || { cat "$W/mine.log"; fail "unclear refusal"; }
[ "$(cat "$W/mine/notes.txt")" = keep ] || fail "the user's file changed"
# Relative names (run from the scene's data folder): the fitted scene still finds its mesh from
# another folder, and compare's technique worker finds it too (it reads the scene compare
# resolved, relative to the working directory, not to its temporary file).
DATA=$(cd "$(dirname "$SCENE")/.." && pwd)
REL=scenes/$(basename "$SCENE")
(cd "$DATA" && "$T" fit empirical "$REL" --reference model --samples 2e4 --width 32 --height 24 \
   --no-cache --max-evaluations 5 --out "$W/rel" 2>"$W/rel.log") || { cat "$W/rel.log"; fail "fit with a relative scene name"; }
(cd / && "$T" render "$W/rel/cube-fitted.json" --out "$W/rel.png" 2>"$W/rel-render.log") ||
  { cat "$W/rel-render.log"; fail "the fitted scene of a relative name does not render from elsewhere"; }
(cd "$DATA" && "$T" compare "$REL" --techniques pointcloud --reference model --samples 2e3 \
   --width 16 --height 12 --frames 1 --warmup 0 --no-cache --out "$W/rel-compare" 2>"$W/rel-compare.log") ||
  { cat "$W/rel-compare.log"; fail "compare with a relative scene name"; }
echo ok
