// SPDX-License-Identifier: GPL-3.0-or-later
#include "progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <signal.h>

#include "safe_print.h"

namespace translucent::cli {
namespace {
volatile std::sig_atomic_t gStopSignal = 0;  // the first SIGINT/SIGTERM (0: none)
volatile std::sig_atomic_t gGuards = 0;      // InterruptGuards alive

extern "C" void translucentCliOnStopSignal(int signo) {
  // Only async-signal-safe calls here: signal() and raise().
  if (gGuards == 0 || gStopSignal != 0) {
    // Nothing to keep (no long work under way), or the second signal: end at once, as without
    // a handler (the shell sees 128 + signo).
    std::signal(signo, SIG_DFL);
    std::raise(signo);
    return;
  }
  gStopSignal = signo;
}
}  // namespace

void installStopSignals() {
  struct sigaction action {};
  action.sa_handler = translucentCliOnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  // Both, even where the shell started us with SIGINT ignored (a background job): Ctrl-C and
  // kill -INT ask the work to stop.
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int stopSignal() { return gStopSignal; }
int stopExitStatus() { return gStopSignal != 0 ? 128 + gStopSignal : 0; }
const char* stopSignalName() { return gStopSignal == SIGTERM ? "SIGTERM" : "Ctrl-C"; }

std::string stoppedEarly(bool partial) {
  if (!partial) return {};
  return fmt::format("stopped early{}, partial result: ",
                     gStopSignal != 0 ? fmt::format(" by {}", stopSignalName()) : std::string());
}

InterruptGuard::InterruptGuard() {
  static const bool installed = (installStopSignals(), true);
  (void)installed;
  gGuards = gGuards + 1;
}
InterruptGuard::~InterruptGuard() { gGuards = gGuards - 1; }
bool InterruptGuard::interrupted() { return gStopSignal != 0; }

std::string clockText(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "--:--";
  const auto s = static_cast<long long>(seconds + 0.5);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
                   : fmt::format("{:02}:{:02}", s / 60, s % 60);
}

ProgressBar::ProgressBar(std::string label, std::string unit, std::optional<double> time_limit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      tty_(isatty(STDERR_FILENO) != 0),
      limit_(time_limit) {}

bool ProgressBar::update(uint64_t done, uint64_t total, double seconds) {
  const double frac = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
  const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
  const double eta = rate > 0.0 ? static_cast<double>(total - done) / rate : -1.0;
  const std::string text = fmt::format("{:5.1f}%  {:.3g} {}/s  elapsed {}  ETA {}", 100.0 * frac,
                                       rate, unit_, clockText(seconds), clockText(eta));
  if (tty_) {
    const int width = 30, filled = static_cast<int>(std::clamp(frac, 0.0, 1.0) * width);
    printStderr("\r[{}{}] {}   ", std::string(static_cast<size_t>(filled), '#'),
               std::string(static_cast<size_t>(width - filled), '.'), text);
    drawn_ = true;
  } else if (seconds >= nextLine_) {
    printStderr("{}: {}\n", label_, text);
    nextLine_ = seconds + 10.0;
  }
  if (limit_ && seconds >= *limit_) return false;
  if (!limit_ && seconds >= kCostCheckSeconds && done > 0 && done < total) {
    const double projected = seconds * static_cast<double>(total) / static_cast<double>(done);
    if (projected > kMaxProjectedSeconds) {
      refused_ = fmt::format(
          "{}: refused: {} {} at the measured {:.3g} {}/s would take about {:.1f} days (more than "
          "{:.0f} hours); lower the count, or give --time-limit (where the command has it) to stop "
          "early with partial results", label_, total, unit_, rate, unit_, projected / 86400.0,
          kMaxProjectedSeconds / 3600.0);
      return false;
    }
  }
  return !InterruptGuard::interrupted();
}

void ProgressBar::end() {
  if (drawn_) printStderr("\n");
  drawn_ = false;
  if (!refused_.empty()) throw ParameterError(refused_);
}

}  // namespace translucent::cli
