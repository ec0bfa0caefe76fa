// SPDX-License-Identifier: GPL-3.0-or-later
#include "progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>

#include "safe_print.h"

namespace translucent::cli {
namespace {
volatile std::sig_atomic_t gInterrupted = 0;
extern "C" void translucentCliOnSigint(int) {
  gInterrupted = 1;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the program at once
}
}  // namespace

InterruptGuard::InterruptGuard() {
  gInterrupted = 0;
  previous_ = std::signal(SIGINT, translucentCliOnSigint);
}
InterruptGuard::~InterruptGuard() { std::signal(SIGINT, previous_); }
bool InterruptGuard::interrupted() { return gInterrupted != 0; }

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
