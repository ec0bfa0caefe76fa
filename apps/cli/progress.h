// SPDX-License-Identifier: GPL-3.0-or-later
// Progress reporting and Ctrl-C handling for long-running subcommands (the same bar and Ctrl-C
// behaviour as `pathtrace slab`): a bar redrawn at 10 Hz on a terminal with rate, elapsed time and
// ETA, a plain line every 10 s when stderr is not a terminal; an optional time limit; and a
// guard so that Ctrl-C (SIGINT) or SIGTERM (kill, timeout, Slurm) asks the computation to stop
// (it then returns what it has, marked partial) while a second signal ends the program at once.
#pragma once

#include <optional>
#include <string>

#include "translucent/reference/slab.h"

namespace translucent::cli {

// SIGINT and SIGTERM, one mechanism. Until a command starts long work that can stop early and
// write what it has (the path tracers, integrate, compare, render --frames, atlas), a signal ends
// the program as it would without a handler (status 128 + the signal: nothing is lost). The first
// InterruptGuard catches both for the rest of the run (installStopSignals). While a guard is
// alive the first signal only asks the work to stop: interrupted() turns true, the command writes
// its partial outputs, and main() then exits with stopExitStatus(): 130 after SIGINT, 143 after
// SIGTERM. A second signal, or one while no guard is alive, ends the program at once.
void installStopSignals();
// The signal that asked the run to stop (SIGINT, SIGTERM), or 0.
int stopSignal();
// 128 + stopSignal() once a signal asked the run to stop, else 0.
int stopExitStatus();
// "Ctrl-C" or "SIGTERM": for messages ("stopped by SIGTERM").
const char* stopSignalName();

// "" for a complete run, else "stopped early, partial result: " naming the signal that stopped it
// ("stopped early by SIGTERM, partial result: ").
std::string stoppedEarly(bool partial);

// Marks long work that stops cleanly on SIGINT/SIGTERM for its lifetime (see above); guards nest.
// Once a signal asked the run to stop, interrupted() stays true (a later guard of the same run,
// e.g. the next channel or scene, stops after its first step).
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  static bool interrupted();
};

// Runs that would take days are refused rather than left to run (issue 15, "legal numbers that
// lead nowhere"): once a run without a time limit has gone kCostCheckSeconds, a projected total
// over kMaxProjectedSeconds stops it, and end() throws ParameterError with the measured rate and
// the projection (the command then writes nothing). A run with --time-limit is the user's
// explicit choice and is never refused.
inline constexpr double kCostCheckSeconds = 5.0;
inline constexpr double kMaxProjectedSeconds = 24.0 * 3600.0;

class ProgressBar {
 public:
  // `label` starts plain lines ("pathtrace: ..."), `unit` names what is counted ("photons").
  ProgressBar(std::string label, std::string unit, std::optional<double> time_limit = {});
  // Reports done of total after `seconds`; false when the run should stop (Ctrl-C, time limit).
  bool update(uint64_t done, uint64_t total, double seconds);
  bool operator()(const reference::TraceProgress& p) {
    return update(p.photons_done, p.photons_total, p.seconds);
  }
  // Ends the bar's line (call once when done); throws ParameterError when the run was refused
  // for its projected cost.
  void end();

 private:
  std::string label_, unit_;
  bool tty_, drawn_ = false;
  double nextLine_ = 10.0;
  std::optional<double> limit_;
  std::string refused_;  // why the run was stopped for its cost ("" if it was not)
};

// "mm:ss" or "h:mm:ss"; "--:--" for unknown.
std::string clockText(double seconds);

}  // namespace translucent::cli
