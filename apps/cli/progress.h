// SPDX-License-Identifier: GPL-3.0-or-later
// Progress reporting and Ctrl-C handling for long-running subcommands (the same bar and Ctrl-C
// behaviour as `pathtrace slab`): a bar redrawn at 10 Hz on a terminal with rate, elapsed time and
// ETA, a plain line every 10 s when stderr is not a terminal; an optional time limit; and a
// SIGINT guard so that Ctrl-C asks the computation to stop (it then returns what it has, marked
// partial) while a second Ctrl-C ends the program at once.
#pragma once

#include <optional>
#include <string>

#include "translucent/reference/slab.h"

namespace translucent::cli {

// Installs the SIGINT handler for its lifetime (restoring the previous one after).
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  static bool interrupted();

 private:
  void (*previous_)(int);
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
