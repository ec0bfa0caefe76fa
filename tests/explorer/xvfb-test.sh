#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# xvfb-test.sh XVFB_RUN COMMAND [ARGS...]: runs COMMAND under a fresh X server (xvfb-run -a,
# a 1600x1000x24 screen) and exits with COMMAND's status.
#
# The X authority file lives in a folder of our own (-f): without it xvfb-run makes a temporary
# folder for it and, when removing that folder fails, exits 5 in place of the command's status
# ("xvfb-run: error: problem while cleaning up temporary directory": a GUI test failed in CI so,
# every check in it having passed). Removing our folder cannot change the status.
set -u
xvfb_run=$1
shift
dir=$(mktemp -d "${TMPDIR:-/tmp}/translucent-xvfb.XXXXXX") || exit 1
: > "$dir/Xauthority"
"$xvfb_run" -a -f "$dir/Xauthority" -s "-screen 0 1600x1000x24" "$@"
rc=$?
rm -rf "$dir" 2>/dev/null
exit $rc
