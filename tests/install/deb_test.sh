#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the .deb with CPack, checks its control fields (Depends: from dpkg-shlibdeps), extracts it
# into a temporary root with dpkg -x (no installation) and runs the packaged CLI from there.
# Usage: deb_test.sh BUILD_DIR
set -euo pipefail
BUILD=$(realpath "$1")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "deb_test: FAIL: $*" >&2; exit 1; }

(cd "$T" && cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$T/pkg") >"$T/cpack.log" 2>&1 \
  || { cat "$T/cpack.log"; fail "cpack -G DEB"; }
deb=$(find "$T/pkg" -maxdepth 1 -name 'translucent_*.deb' | head -1)
[[ -n "$deb" ]] || { cat "$T/cpack.log"; fail "no .deb written"; }
echo "deb: $(basename "$deb") $(du -h "$deb" | cut -f1) ($(stat -c %s "$deb") bytes)"
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for lib in libc6 libstdc++6 libopenimageio libembree libtbb libassimp libepoxy libegl1; do
  grep -q "$lib" <<<"$depends" || fail "Depends: does not name $lib"
done
# The listing to a file first: `grep -q` closing a pipe early would fail the pipeline (pipefail).
dpkg-deb -c "$deb" >"$T/listing.txt"
grep -q '\./usr/bin/translucent$' "$T/listing.txt" || fail "no /usr/bin/translucent in the package"
grep -q '\./usr/share/translucent/shaders/' "$T/listing.txt" || fail "no shaders in the package"
# The modules that bring OpenImageIO and OpenVDB (dlopen'ed on first use; their libraries reach
# Depends: through dpkg-shlibdeps on the modules).
for m in oiio openvdb; do
  grep -q "\./usr/lib/translucent/libtranslucent_$m\.so\$" "$T/listing.txt" || fail "no libtranslucent_$m.so in the package"
done
grep -q '\./usr/share/doc/translucent/LICENSE$' "$T/listing.txt" || fail "no LICENSE in the package"
grep -q '\./usr/lib/cmake/Translucent/TranslucentConfig.cmake$' "$T/listing.txt" || fail "no CMake package"
dpkg -x "$deb" "$T/root"
# The packaged CLI, run from the extracted root: it finds ../share/translucent beside itself.
env -u TRANSLUCENT_SHARE_DIR "$T/root/usr/bin/translucent" --version | grep -q "0\.1\.0" || fail "--version"
env -u TRANSLUCENT_SHARE_DIR "$T/root/usr/bin/translucent" profile --material Marble --model dipole \
    --out "$T/profile.csv" >"$T/profile.log" 2>&1 || { cat "$T/profile.log"; fail "profile"; }
[[ $(wc -l <"$T/profile.csv") -gt 10 ]] || fail "profile.csv has $(wc -l <"$T/profile.csv") lines"
echo "deb_test: PASS"
