# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by the Ctrl-C tests (tests/reference/sigint*.sh, tests/compare/sigint_*.sh):
#   interrupt PID   sends SIGINT to the background job PID once the program has installed its
#                   SIGINT handler, waits for it and sets $rc to its exit status; returns 1 (rc
#                   unset) if the handler never appeared within 60 s.
# Why wait: a background job of a non-interactive shell starts with SIGINT ignored, so a signal
# sent before the program installs its handler (bit 2 of SigCgt in /proc; SIGINT is signal 2) is
# lost and the run would go on for its 1e15 photons. Until the exec, PID is a copy of the calling
# shell, whose own SIGINT handler shows in SigCgt too: the process must be translucent itself
# (comm) first.
interrupt() {
  _pid=$1
  _i=0
  while [ "$_i" -lt 600 ]; do
    _caught=""
    if [ "$(cat "/proc/$_pid/comm" 2>/dev/null)" = "translucent" ]; then
      _caught=$(awk '/^SigCgt:/ {print $2}' "/proc/$_pid/status" 2>/dev/null)
    fi
    _last=${_caught#"${_caught%?}"}
    if [ -n "$_last" ] && [ $((0x$_last & 2)) -ne 0 ]; then break; fi
    if ! kill -0 "$_pid" 2>/dev/null; then break; fi  # the program is gone
    sleep 0.1
    _i=$((_i + 1))
  done
  if [ -z "$_last" ] || [ $((0x$_last & 2)) -eq 0 ]; then
    echo "the program never installed a SIGINT handler"
    kill "$_pid" 2>/dev/null
    wait "$_pid"
    return 1
  fi
  sleep 0.5  # let it work a little
  kill -INT "$_pid"
  wait "$_pid"
  rc=$?
  return 0
}
