#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `pathtrace slab|sphere|mesh --shard I/N --partial FILE` and `translucent merge` through the real
# binary (issue 17): the merged outputs equal the unsharded run's bit for bit (the JSON up to its
# timing keys, the CSV and EXR files byte for byte), and bad sets of parts are clear errors.
#   shard_merge.sh TRANSLUCENT SCENES_DIR WORK_DIR
set -euo pipefail
T=$1
SCENES=$2
W=$3
rm -rf "$W"
mkdir -p "$W"
cd "$W"

fail() {
  echo "FAIL: $*" >&2
  exit 1
}
# The unsharded runs name --device cpu: shards take auto as cpu, an unsharded auto would take a
# real GPU where there is one.
# The JSON without the lines of the keys that may differ (timings, thread counts, and the device:
# a GPU run names its renderer, a merge of GPU shards says "gpu", checked on its own below).
numbers() { grep -vE '"(seconds|photons_per_second|threads|device)":' "$1"; }
same_json() { diff <(numbers "$1") <(numbers "$2") >/dev/null || { diff <(numbers "$1") <(numbers "$2") | head -20; fail "$1 and $2 differ"; }; }
# Two EXR files hold the same image, attributes and layers: byte for byte after their first
# attribute, the capture date OpenEXR stamps on every file ("capDate", string of 19 characters:
# 46 bytes with the magic number and version).
same_exr() {
  for f in "$1" "$2"; do
    [ "$(head -c 23 "$f" | tail -c 15 | tr -d '\0')" = "capDatestring" ] &&
      [ "$(od -An -tu4 -j23 -N4 "$f" | tr -d ' ')" = 19 ] || fail "$f: no capDate attribute first"
  done
  cmp -i 46 "$1" "$2" || fail "$1 and $2 differ"
}
expect_error() {  # expect_error PATTERN COMMAND...: fails, and stderr matches PATTERN
  local pattern=$1
  shift
  if "$@" 2>err.txt >/dev/null; then fail "expected an error from: $*"; fi
  grep -qE -e "$pattern" err.txt || { cat err.txt; fail "the error does not match '$pattern': $*"; }
  ! grep -qE "terminate called|Segmentation|Aborted" err.txt || fail "crashed: $*"
}

# ---- slab: 4 shards, one of them traced with 1 thread, merged in a shuffled order -------------
SLAB=(pathtrace slab --material Skimmilk --channel g --photons 50000 --radial-bins 30
      --radial-max 4 --angle-bins 5 --thickness 3 --seed 7)
"$T" "${SLAB[@]}" --device cpu --json one.json --csv one.csv 2>/dev/null
for i in 0 1 2 3; do
  "$T" "${SLAB[@]}" --threads $((i % 2 + 1)) --shard $i/4 --partial slab-$i.tpart 2>/dev/null
done
"$T" merge slab-2.tpart slab-0.tpart slab-3.tpart slab-1.tpart --json merged.json --csv merged.csv \
  2>merge.txt
grep -q "merge: 4 shards" merge.txt || fail "merge did not say what it merged"
same_json one.json merged.json
cmp one.csv merged.csv || fail "slab CSV differs"
grep -q '"photons": 50000' merged.json || fail "merged photons"

# Errors: a missing shard, a shard twice, parts of different runs, a damaged part, a bad --shard,
# outputs with --shard, an incomplete shard.
expect_error "3 of 4 shards given; missing shard 1" "$T" merge slab-0.tpart slab-2.tpart slab-3.tpart --json x.json
expect_error "shard 2/4 given twice: 'slab-2.tpart' and 'slab-2.tpart'" "$T" merge slab-0.tpart slab-1.tpart slab-2.tpart slab-2.tpart slab-3.tpart --json x.json
OTHER=("${SLAB[@]}")
OTHER[${#OTHER[@]}-1]=8  # another seed
"$T" "${OTHER[@]}" --shard 1/4 --partial other-1.tpart 2>/dev/null
expect_error "are parts of different runs" "$T" merge slab-0.tpart other-1.tpart slab-2.tpart slab-3.tpart --json x.json
cp slab-3.tpart damaged.tpart
printf '\x01' | dd of=damaged.tpart bs=1 seek=$(( $(stat -c %s damaged.tpart) - 5 )) conv=notrunc 2>/dev/null
expect_error "part 'damaged.tpart': the content hash does not match" "$T" merge slab-0.tpart slab-1.tpart slab-2.tpart damaged.tpart --json x.json
expect_error "not a partial file" "$T" merge one.json --json x.json
expect_error "expected 0 <= I < N" "$T" "${SLAB[@]}" --shard 4/4 --partial x.tpart
expect_error "expected I/N" "$T" "${SLAB[@]}" --shard 2 --partial x.tpart
expect_error "give --partial FILE" "$T" "${SLAB[@]}" --shard 0/2
expect_error "a shard writes only its --partial file" "$T" "${SLAB[@]}" --shard 0/2 --partial x.tpart --json x.json
# Without --json (or --csv) a run prints its result to stdout and writes nothing.
"$T" "${SLAB[@]}" 2>/dev/null | grep -q "^pathtrace: 50000 photons" || fail "pathtrace slab without --json: no result on stdout"
# The parts are inputs of the merge: an output naming one, or a hard or symbolic link to one, is
# refused before anything is written, and the part is unchanged byte for byte.
cp slab-0.tpart kept.tpart
ln -f slab-0.tpart hard-link.tpart
ln -sf slab-0.tpart soft-link.tpart
for out in slab-0.tpart hard-link.tpart soft-link.tpart; do
  for option in --json --csv; do
    expect_error "$option '$out': is a partial file of this run \('slab-0.tpart'\)" \
      "$T" merge slab-0.tpart slab-1.tpart slab-2.tpart slab-3.tpart "$option" "$out"
    cmp slab-0.tpart kept.tpart || fail "merge $option $out changed the part slab-0.tpart"
  done
done
rm -f kept.tpart hard-link.tpart soft-link.tpart
"$T" "${SLAB[@]/50000/1e12}" --shard 0/2 --partial slow.tpart --time-limit 0.5 2>/dev/null
expect_error "'slow.tpart' \(shard 0/2\) was stopped before it traced all its blocks" "$T" merge slow.tpart slab-1.tpart --json x.json
[ ! -e x.json ] || fail "a failed merge wrote x.json"

# ---- slab: a shard stopped by SIGTERM resumes from its partial file ---------------------------
# Shard 1/2 (one thread) is stopped by SIGTERM twice once it has traced a while, then run to the
# end; each run resumes from the blocks the previous one finished (its partial file); the merge
# equals the uninterrupted run bit for bit.
RES=(pathtrace slab --material Skimmilk --channel g --photons 4e7 --radial-bins 30
     --radial-max 4 --angle-bins 5 --thickness 3 --seed 9)
"$T" "${RES[@]}" --device cpu --json res-one.json --csv res-one.csv 2>/dev/null
"$T" "${RES[@]}" --shard 0/2 --partial res-0.tpart 2>/dev/null
blocks_done() { sed -n 2p "$1" | grep -o '"blocks_done":[0-9]*' | cut -d: -f2; }
# Waits until process $1 catches SIGTERM (bit 15 of SigCgt, 0x4000), then $2 seconds more (it
# has traced a little).
wait_for_term_handler() {
  for _ in $(seq 300); do
    caught=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null || true)
    [ "$(cat "/proc/$1/comm" 2>/dev/null)" = translucent ] && [ -n "$caught" ] &&
      [ $((0x$caught & 0x4000)) -ne 0 ] && break
    sleep 0.05
  done
  sleep "$2"
}
stops=0 done_before=0
for attempt in 1 2 3; do
  "$T" "${RES[@]}" --threads 1 --shard 1/2 --partial res-1.tpart 2>res-run.txt &
  pid=$!
  wait_for_term_handler "$pid" 0.7
  [ "$attempt" -eq 3 ] || kill -TERM "$pid" 2>/dev/null || true
  rc=0
  wait "$pid" || rc=$?
  if [ "$rc" -eq 0 ]; then break; fi
  [ "$rc" -eq 143 ] || { cat res-run.txt; fail "shard 1/2 stopped by SIGTERM exited $rc, expected 143"; }
  grep -q "INCOMPLETE" res-run.txt || { cat res-run.txt; fail "the stopped shard did not say INCOMPLETE"; }
  now_done=$(blocks_done res-1.tpart)
  [ -n "$now_done" ] && [ "$now_done" -ge "$done_before" ] ||
    fail "attempt $attempt: blocks_done '$now_done' after $done_before"
  if [ "$done_before" -gt 0 ]; then
    grep -q "resuming shard 1/2 after its $done_before of" res-run.txt ||
      { cat res-run.txt; fail "attempt $attempt did not resume from $done_before blocks"; }
  fi
  done_before=$now_done
  stops=$((stops + 1))
done
[ "$rc" -eq 0 ] || fail "shard 1/2 did not complete"
[ "$stops" -eq 2 ] || fail "shard 1/2 was stopped $stops times, expected 2 (it finished before SIGTERM: raise --photons)"
[ "$done_before" -gt 0 ] || fail "the last stop of shard 1/2 left no finished block"
grep -q "resuming shard 1/2 after its $done_before of" res-run.txt ||
  { cat res-run.txt; fail "the last run did not resume from $done_before blocks"; }
"$T" merge res-0.tpart res-1.tpart --json res-merged.json --csv res-merged.csv 2>/dev/null
same_json res-one.json res-merged.json
cmp res-one.csv res-merged.csv || fail "the CSV of the resumed shards differs"
# A partial file of another shard is not resumed: the shard starts over.
"$T" "${RES[@]}" --shard 0/2 --partial res-1.tpart 2>res-other.txt
grep -q "not resumed (it is another shard" res-other.txt || { cat res-other.txt; fail "another shard's file was resumed"; }

# ---- sphere: 2 passes unsharded vs 3 shards of its blocks --------------------------------------
SPHERE=(pathtrace sphere --photons 20000 --passes 2 --width 24 --height 20 --seed 3
        --light-dir 0.3,1,0.8)
mkdir -p one merged
# (Each output run in its own folder: the JSON records the output file names.)
(cd one && "$T" "${SPHERE[@]}" --device cpu --exr sphere.exr --json sphere.json --png sphere.png 2>/dev/null)
for i in 0 1 2; do
  "$T" "${SPHERE[@]}" --shard $i/3 --partial sphere-$i.tpart 2>/dev/null
done
(cd merged && "$T" merge ../sphere-0.tpart ../sphere-1.tpart ../sphere-2.tpart --exr sphere.exr \
  --json sphere.json --png sphere.png 2>/dev/null)
same_exr one/sphere.exr merged/sphere.exr
cmp one/sphere.png merged/sphere.png || fail "sphere PNG differs"
same_json one/sphere.json merged/sphere.json

# ---- sphere: a shard stopped by SIGTERM resumes from its partial file ------------------------
# As the slab above, for the image tracers (sphere and mesh share the code): shard 1/2 on one
# thread is stopped by SIGTERM once, then run again: it resumes after the blocks it finished (the
# CPU merges blocks in order), and the merge equals the uninterrupted run bit for bit.
SRES=(pathtrace sphere --photons 4e6 --width 24 --height 20 --seed 4 --light-dir 0.3,1,0.8)
mkdir -p sres-one sres-merged
(cd sres-one && "$T" "${SRES[@]}" --device cpu --exr s.exr --json s.json 2>/dev/null)
"$T" "${SRES[@]}" --shard 0/2 --partial sres-0.tpart 2>/dev/null
"$T" "${SRES[@]}" --threads 1 --shard 1/2 --partial sres-1.tpart 2>sres-run.txt &
pid=$!
wait_for_term_handler "$pid" 1
kill -TERM "$pid" 2>/dev/null || true
rc=0
wait "$pid" || rc=$?
[ "$rc" -eq 143 ] || { cat sres-run.txt; fail "the sphere shard stopped by SIGTERM exited $rc, expected 143 (it finished first: raise --photons)"; }
sdone=$(blocks_done sres-1.tpart)
[ -n "$sdone" ] && [ "$sdone" -gt 0 ] || { cat sres-run.txt; fail "the stopped sphere shard recorded '$sdone' finished blocks"; }
"$T" "${SRES[@]}" --shard 1/2 --partial sres-1.tpart 2>sres-run.txt
grep -q "resuming shard 1/2 after its $sdone of" sres-run.txt ||
  { cat sres-run.txt; fail "the sphere shard did not resume from its $sdone blocks"; }
(cd sres-merged && "$T" merge ../sres-0.tpart ../sres-1.tpart --exr s.exr --json s.json 2>/dev/null)
same_exr sres-one/s.exr sres-merged/s.exr
same_json sres-one/s.json sres-merged/s.json

# ---- the sphere on the GPU (issue 16): GPU shards merge into the GPU run bit for bit ----------
mkdir -p one-gpu merged-gpu
(cd one-gpu && "$T" "${SPHERE[@]}" --device gpu --exr sphere.exr --json sphere.json 2>/dev/null)
for i in 0 1 2; do
  "$T" "${SPHERE[@]}" --device gpu --shard $i/3 --partial sphere-gpu-$i.tpart 2>/dev/null
done
(cd merged-gpu && "$T" merge ../sphere-gpu-2.tpart ../sphere-gpu-0.tpart ../sphere-gpu-1.tpart \
  --exr sphere.exr --json sphere.json 2>/dev/null)
same_exr one-gpu/sphere.exr merged-gpu/sphere.exr
same_json one-gpu/sphere.json merged-gpu/sphere.json
grep -q '"device": "gpu (' one-gpu/sphere.json || fail "the GPU run does not name its renderer"
grep -q '"device": "gpu"' merged-gpu/sphere.json || fail "the merged GPU shards do not say gpu"
grep -q '"device": "cpu"' one/sphere.json || fail "the CPU run does not say cpu"
! cmp -s -i 46 one/sphere.exr one-gpu/sphere.exr || fail "the GPU and CPU runs are the same file"

# ---- mesh: the cube scene (a copy, edited afterwards: merge must notice) -----------------------
cp "$SCENES/cube.json" cube.json
sed -i "s#\"../meshes/cube.obj\"#\"$SCENES/../meshes/cube.obj\"#" cube.json
MESH=(pathtrace mesh --scene "$PWD/cube.json" --photons 30000 --seed 5)
(cd one && "$T" "${MESH[@]}" --device cpu --exr mesh.exr --json mesh.json 2>/dev/null)
for i in 0 1; do
  "$T" "${MESH[@]}" --shard $i/2 --partial mesh-$i.tpart 2>/dev/null
done
(cd merged && "$T" merge ../mesh-0.tpart ../mesh-1.tpart --exr mesh.exr --json mesh.json 2>/dev/null)
same_exr one/mesh.exr merged/mesh.exr
same_json one/mesh.json merged/mesh.json
grep -q '"reference_key"' merged/mesh.json || fail "no reference key in the mesh JSON"
sed -i 's/"irradiance": 1.0/"irradiance": 2.0/' cube.json
expect_error "the inputs of the run have changed since the shards were traced" "$T" merge mesh-0.tpart mesh-1.tpart --exr x.exr
[ ! -e x.exr ] || fail "a failed merge wrote x.exr"
echo "shard/merge: all checks passed"
