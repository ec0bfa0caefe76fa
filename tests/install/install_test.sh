#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the build to a temporary prefix, moves the prefix, hides the source and build trees,
# and uses the installed package as a user would: the CLI renders a shipped scene (shaders found
# relative to the binary), and a separate CMake project finds Translucent and links
# Translucent::bssrdf.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR [PYTHON]
#   PYTHON: the interpreter of the build's Python module, when the build has one: the installed
#   package (lib/python3/dist-packages/translucent) is then imported from the moved prefix too.
set -euo pipefail
BUILD=$(realpath "$1")
SRC=$(realpath "$2")
PYTHON=${3:-}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"

fail() { echo "install_test: FAIL: $*" >&2; exit 1; }

cmake --install "$BUILD" --prefix "$T/prefix" >"$T/install.log" || { cat "$T/install.log"; fail "cmake --install"; }
# The installed layout.
for f in bin/translucent include/translucent/bssrdf/registry.h include/translucent/optics/presets.h \
         include/translucent/io/image_io.h lib/libtranslucent_bssrdf.a \
         lib/cmake/Translucent/TranslucentConfig.cmake lib/cmake/Translucent/TranslucentConfigVersion.cmake \
         lib/cmake/Translucent/TranslucentTargets.cmake share/translucent/shaders \
         share/translucent/data/bssrdf share/translucent/data/scenes/cube.json \
         share/doc/translucent/LICENSE lib/translucent/libtranslucent_oiio.so \
         lib/translucent/libtranslucent_openvdb.so; do
  [[ -e "$T/prefix/$f" ]] || fail "not installed: $f"
done
# No header outside include/translucent/<layer>/ and no source file among the headers.
if find "$T/prefix/include" -type f ! -path "*/include/translucent/*/*" | grep -q .; then
  fail "headers outside include/translucent/<layer>/: $(find "$T/prefix/include" -type f ! -path "*/include/translucent/*/*" | head -3)"
fi
find "$T/prefix/include" -name '*.cpp' | grep -q . && fail "source files installed among the headers"

# OpenImageIO and OpenVDB are loaded from the modules in lib/translucent on first use
# (translucent/io/plugins.h), never linked by the CLI: their ~260 libraries would be mapped into
# every run (~100 MiB of resident memory).
if ldd "$T/prefix/bin/translucent" | grep -E "libOpenImageIO|libopenvdb" >"$T/ldd.txt"; then
  fail "bin/translucent links $(tr '\n' ' ' <"$T/ldd.txt"): expected them only in lib/translucent's modules"
fi

# Move the prefix: nothing may depend on where it was installed.
mv "$T/prefix" "$T/moved"
P="$T/moved"

# Hide the source and build trees (a private mount namespace with empty folders over them),
# then run the installed CLI: its shaders and data must come from $P/share/translucent.
run_hidden() {
  local hide="mount -t tmpfs none '$SRC'"
  case "$BUILD/" in "$SRC"/*) ;; *) hide+=" && mount -t tmpfs none '$BUILD'" ;; esac
  unshare --mount --map-root-user sh -c "$hide && cd '$T' && $*"
}
run_hidden "'$P/bin/translucent' --version" >"$T/version.txt" || fail "translucent --version"
grep -q "0\.1\.0" "$T/version.txt" || fail "--version printed: $(cat "$T/version.txt")"
env -u TRANSLUCENT_SHARE_DIR -u TRANSLUCENT_SHADER_DIR -u TRANSLUCENT_BSSRDF_DIR \
  bash -c "$(declare -f run_hidden); T='$T' SRC='$SRC' BUILD='$BUILD'; run_hidden \"'$P/bin/translucent' render '$P/share/translucent/data/scenes/cube.json' --width 48 --height 36 --out '$T/cube.png'\"" \
  >"$T/render.log" 2>&1 || { cat "$T/render.log"; fail "the installed CLI could not render a shipped scene with the source and build trees hidden"; }
[[ $(head -c 8 "$T/cube.png" | od -An -tx1 | tr -d ' \n') == "89504e470d0a1a0a" ]] || fail "cube.png is not a PNG"
echo "install_test: the moved prefix renders data/scenes/cube.json with the source and build trees hidden (the PNG through the moved prefix's OpenImageIO module)"

# A user's CMake project against the moved prefix.
cmake -S "$SRC/tests/install/consumer" -B "$T/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$P" >"$T/consumer-configure.log" 2>&1 \
  || { cat "$T/consumer-configure.log"; fail "find_package(Translucent CONFIG REQUIRED) against the prefix"; }
cmake --build "$T/consumer" >"$T/consumer-build.log" 2>&1 || { cat "$T/consumer-build.log"; fail "building the consumer"; }
out=$(run_hidden "'$T/consumer/consumer'") || fail "running the consumer"
echo "consumer: $out"
# Rd of the classical dipole for Marble: each channel in (0, 1), red > blue (marble is whitish
# with more absorption in the blue, Jensen et al. 2001, Table 2).
python3 - "$out" <<'PY' || fail "the consumer's Rd is not a plausible reflectance: $out"
import re, sys
m = re.fullmatch(r"dipole Rd Marble: ([0-9.]+) ([0-9.]+) ([0-9.]+)", sys.argv[1].strip())
assert m, "unexpected output"
r, g, b = map(float, m.groups())
assert all(0.0 < x < 1.0 for x in (r, g, b)), (r, g, b)
assert r > b, (r, b)
PY
# The Python package of `cmake --install` (component python), from the moved prefix with the
# trees hidden: it imports, finds the shaders and data installed beside it, and computes.
if [[ -n "$PYTHON" ]]; then
  site="$P/lib/python3/dist-packages"
  [[ -f "$site/translucent/__init__.py" ]] || fail "the Python package is not installed under $site"
  py=$(run_hidden "PYTHONPATH='$site' '$PYTHON' -c 'import translucent; print(translucent.share_directory()); print(translucent.profile(\"dipole\", [1.0], preset=\"Marble\")[0][0])'") \
    || fail "importing the installed Python package with the source and build trees hidden"
  echo "python: $py"
  case "$(head -1 <<<"$py")" in "$site"/*|"$P"/*) ;; *) fail "the installed package reads its data from $(head -1 <<<"$py"), outside the prefix" ;; esac
fi
echo "install_test: PASS"
