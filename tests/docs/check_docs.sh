#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the documentation site with scripts/build-docs against the CLI given, checks that every
# internal link and image of build/docs/html resolves, and takes a screenshot of index.html with
# headless Chromium that must not be blank.  Usage: check_docs.sh TRANSLUCENT_BINARY SCREENSHOT_DIR
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CLI=$1
SHOT_DIR=$2
PYTHON=/usr/bin/python3
[[ -x "$PYTHON" ]] || PYTHON=python3

if ! "$PYTHON" -c "import sphinx, myst_parser, furo, jsonschema" 2>/dev/null; then
  echo "check_docs: FAIL: Sphinx, MyST, Furo or jsonschema missing (run scripts/install-deps)" >&2; exit 1
fi
CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
[[ -n "$CHROMIUM" ]] || { echo "check_docs: FAIL: no chromium (run scripts/install-deps)" >&2; exit 1; }

"$ROOT/scripts/build-docs" "$CLI"
HTML=$ROOT/build/docs/html
"$PYTHON" "$ROOT/tests/docs/check_links.py" "$HTML"
if [[ -n "${TRANSLUCENT_DOCS_REQUIRE_PYTHON:-}" ]]; then
  # The API page documents the module's functions from their docstrings.
  for name in translucent.profile translucent.pathtrace_slab translucent.Scene; do
    grep -q "id=\"$name\"" "$HTML/reference/python.html" || { echo "check_docs: FAIL: $name is not on the Python API page" >&2; exit 1; }
  done
fi

mkdir -p "$SHOT_DIR"
SHOT=$SHOT_DIR/index.png
PROFILE=$(mktemp -d)
trap 'rm -rf "$PROFILE"' EXIT
rm -f "$SHOT"
timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --hide-scrollbars \
  --user-data-dir="$PROFILE" --screenshot="$SHOT" --window-size=1280,900 "file://$HTML/index.html" \
  >/dev/null 2>&1 || true
"$PYTHON" - "$SHOT" <<'PY'
import os, sys
path = sys.argv[1]
if not os.path.exists(path):
    sys.exit(f"check_docs: no screenshot at {path}")
size = os.path.getsize(path)
try:
    from PIL import Image
except ImportError:  # no PIL: a blank 1280x900 PNG compresses to a few kB
    if size < 20000:
        sys.exit(f"check_docs: screenshot {path} is {size} bytes: blank?")
    print(f"check_docs: screenshot {path}: {size} bytes")
    sys.exit(0)
img = Image.open(path).convert("RGB")
if img.size != (1280, 900):
    sys.exit(f"check_docs: screenshot is {img.size}, expected (1280, 900)")
colors = img.getcolors(maxcolors=1 << 20) or []
extrema = img.convert("L").getextrema()
if len(colors) < 50 or extrema[1] - extrema[0] < 100:
    sys.exit(f"check_docs: screenshot {path} looks blank ({len(colors)} colours, grey range {extrema})")
print(f"check_docs: screenshot {path}: {img.size[0]}x{img.size[1]}, {len(colors)} colours, {size} bytes")
PY
