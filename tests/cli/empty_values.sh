#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# An empty value ('') of any option or argument that takes one is refused naming the option, with
# the usage status 2: CLI11 read '' as 0 (--points), as absent (--thickness: a semi-infinite slab;
# --layers: then an error about the medium) or as an empty name. Usage: empty_values.sh <binary>.
set -u
exe=$1
failed=0
# expect "<text the first line must contain>" command...
expect() {
  want=$1
  shift
  out=$("$exe" "$@" 2>&1 >/dev/null)
  rc=$?
  first=$(printf '%s\n' "$out" | head -n 1)
  case "$first" in
    *"$want"*) [ $rc -eq 2 ] || { echo "FAIL (exit $rc, expected 2): $*"; failed=1; } ;;
    *) echo "FAIL: $*: first line '$first', expected '$want'"; failed=1 ;;
  esac
}
expect "--points: empty value '': expected a number" profile --model dipole --points ''
expect "--thickness: empty value '': expected a number" pathtrace slab --material Marble --channel r --thickness ''
expect "--layers: empty value '': expected a value" pathtrace slab --layers '' --eta 1.3
expect "--shard: empty value '': expected a value" pathtrace slab --material Marble --channel r --shard '' --partial p.tpart
expect "--photons: empty value '': expected a value" pathtrace slab --material Marble --channel r --photons ''
expect "--out: empty path: expected a file name" profile --model dipole --out ''
expect "scene: empty value '': expected a value" render ''
expect "parts: empty value '': expected a value" merge ''
exit $failed
