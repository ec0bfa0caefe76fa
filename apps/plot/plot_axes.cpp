// SPDX-License-Identifier: GPL-3.0-or-later
// Axes, ticks and labels of the plots; see plot_axes.h.
#include "plot/plot_axes.h"

#include "plot/plot_style.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

namespace translucent::plot {

namespace {

constexpr const char* kMinus = "\u2212";  // typographic minus: a hyphen is too short beside digits
constexpr const char* kTimes = "\u00d7";

// Integer exponent of a power of ten, robust to log10's rounding (log10(1e-3) may be -2.9999…).
int exponentOf(double v) { return static_cast<int>(std::floor(std::log10(v) + 1e-9)); }

std::string withMinus(std::string s) {
  if (!s.empty() && s[0] == '-') s.replace(0, 1, kMinus);
  return s;
}

bool within(double v, double lo, double hi) {
  const double tol = 1e-9 * std::max(std::abs(lo), std::abs(hi));
  return v >= lo - tol && v <= hi + tol;
}

}  // namespace

std::optional<double> plotted(double v, YScale s) {
  if (!std::isfinite(v)) return std::nullopt;
  switch (s) {
    case YScale::Linear: return v;
    case YScale::Log: return v > 0.0 ? std::optional<double>(v) : std::nullopt;
    case YScale::Sqrt: return v >= 0.0 ? std::optional<double>(std::sqrt(v)) : std::nullopt;
  }
  return std::nullopt;
}

double stderrAt(const analysis::Curve& c, std::size_t i) {
  if (c.stderr_.size() != c.value.size()) return 0.0;
  const double e = c.stderr_[i];
  return std::isfinite(e) && e > 0.0 ? e : 0.0;
}

std::vector<std::vector<std::size_t>> visibleRuns(const analysis::Curve& c, YScale s) {
  std::vector<std::vector<std::size_t>> runs;
  std::vector<std::size_t> run;
  const std::size_t n = std::min(c.r.size(), c.value.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isfinite(c.r[i]) && plotted(c.value[i], s)) {
      run.push_back(i);
    } else if (!run.empty()) {
      runs.push_back(std::move(run));
      run.clear();
    }
  }
  if (!run.empty()) runs.push_back(std::move(run));
  return runs;
}

ProfileExtent profileExtent(const std::vector<analysis::Curve>& curves, YScale scale) {
  ProfileExtent x;
  for (const auto& c : curves)
    for (const auto& run : visibleRuns(c, scale))
      for (std::size_t i : run) {
        x.values.add(c.value[i]);
        const double e = stderrAt(c, i);
        if (e > 0.0) {
          x.values.add(c.value[i] + e);
          // Log and sqrt clamp a bar's lower end at the axis instead of widening the axis.
          if (scale == YScale::Linear) x.values.add(c.value[i] - e);
        }
        x.r_max = std::max(x.r_max, c.r[i]);
      }
  return x;
}

double ceilRound(double v) {
  static constexpr std::array<double, 8> kTops = {1, 2, 3, 4, 5, 6, 8, 10};
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : kTops)
    if (m * p >= v * (1.0 - 1e-9)) return m * p;
  return 10.0 * p;
}

namespace {

// The value m·10^e, m in {1, 2, 3, 5}, nearest to v in sqrt(y) (0.56 -> 0.5, 1.25 -> 1).
double nearestRound(double v) {
  static constexpr std::array<double, 4> kMantissas = {1, 2, 3, 5};
  const double e = std::floor(std::log10(v));
  double best = 0.0, bestDistance = std::numeric_limits<double>::infinity();
  for (double de : {-1.0, 0.0, 1.0})
    for (double m : kMantissas) {
      const double c = m * std::pow(10.0, e + de);
      const double d = std::abs(std::sqrt(c) - std::sqrt(v));
      if (d < bestDistance) {
        best = c;
        bestDistance = d;
      }
    }
  return best;
}

// Digits after the decimal point that a value with one significant digit needs (0.05 -> 2).
int decimalsOf(double v) { return v > 0.0 ? std::max(0, -exponentOf(v)) : 0; }

}  // namespace

std::vector<double> sqrtTicks(double top, int intervals) {
  std::vector<double> ticks = {0.0};
  for (int k = 1; k <= intervals; ++k) {
    const double f = static_cast<double>(k) / intervals;
    const double t = k == intervals ? top : nearestRound(top * f * f);
    if (t > ticks.back() * (1.0 + 1e-9) && t <= top * (1.0 + 1e-9)) ticks.push_back(t);
  }
  return ticks;
}

TickLabel decadeLabel(int exponent) {
  return {"10", exponent < 0 ? fmt::format("{}{}", kMinus, -exponent) : fmt::format("{}", exponent)};
}

TickLabel numberLabel(double v, int decimals) {
  if (v == 0.0) return {"0", ""};
  const double a = std::abs(v);
  if (a >= 1e5 || a < 1e-3) {
    const int e = exponentOf(a);
    const double m = v / std::pow(10.0, e);
    TickLabel l = decadeLabel(e);
    if (std::abs(std::abs(m) - 1.0) > 1e-9)
      l.text = withMinus(fmt::format("{:.3g}", m)) + kTimes + l.text;
    else if (m < 0.0)
      l.text = kMinus + l.text;
    return l;
  }
  return {withMinus(fmt::format("{:.{}f}", v, std::max(0, decimals))), ""};
}

double Axis::fraction(double v) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  switch (kind) {
    case AxisKind::Linear: return (v - lo) / (hi - lo);
    case AxisKind::Log:
      return v > 0.0 ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : nan;
    case AxisKind::Sqrt:
      return v >= 0.0 ? (std::sqrt(v) - std::sqrt(lo)) / (std::sqrt(hi) - std::sqrt(lo)) : nan;
  }
  return nan;
}

Axis linearAxis(double lo, double hi, int target) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = 0.0;
    hi = 1.0;
  }
  if (!(hi > lo)) {
    const double pad = lo == 0.0 ? 1.0 : 0.5 * std::abs(lo);
    lo -= lo == 0.0 ? 0.0 : pad;
    hi += pad;
  }
  const double raw = (hi - lo) / std::max(1, target);
  const int k = exponentOf(raw);
  const double p = std::pow(10.0, k);
  static constexpr std::array<double, 5> kSteps = {1.0, 2.0, 2.5, 5.0, 10.0};
  double m = 10.0;
  for (double s : kSteps)
    if (s * p >= raw * (1.0 - 1e-9)) {
      m = s;
      break;
    }
  const double step = m * p;
  // Digits the labels need: a step of 2.5·10^k one more than its exponent says.
  const int decimals = std::max(0, -k + (m == 2.5 ? 1 : 0) - (m == 10.0 ? 1 : 0));
  const int minorPerStep = m == 2.0 ? 4 : 5;

  Axis a;
  a.kind = AxisKind::Linear;
  const double first = std::floor(lo / step + 1e-9), last = std::ceil(hi / step - 1e-9);
  a.lo = first * step;
  a.hi = last * step;
  for (double i = first; i <= last + 0.5; i += 1.0) {
    double v = i * step;
    if (std::abs(v) < 1e-9 * step) v = 0.0;  // no "-0.0" from rounding
    a.ticks.push_back({v, true, numberLabel(v, decimals)});
    if (i + 0.5 < last)
      for (int j = 1; j < minorPerStep; ++j)
        a.ticks.push_back({v + step * j / minorPerStep, false, {}});
  }
  return a;
}

Axis logAxis(double lo, double hi, bool wholeDecades) {
  if (!(lo > 0.0) || !std::isfinite(lo) || !(hi > 0.0) || !std::isfinite(hi)) {
    lo = 1e-3;
    hi = 1.0;
  }
  if (!(hi > lo)) {
    lo /= 2.0;
    hi *= 2.0;
  }
  Axis a;
  a.kind = AxisKind::Log;
  if (wholeDecades) {
    const int e0 = exponentOf(lo);
    int e1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
    if (e1 <= e0) e1 = e0 + 1;
    a.lo = std::pow(10.0, e0);
    a.hi = std::pow(10.0, e1);
  } else {
    // A margin of 4% of the span (at least 0.05 decades) so that markers at the ends show whole.
    const double l0 = std::log10(lo), l1 = std::log10(hi);
    const double pad = std::max(0.05, 0.04 * (l1 - l0));
    a.lo = std::pow(10.0, l0 - pad);
    a.hi = std::pow(10.0, l1 + pad);
  }
  const int d0 = static_cast<int>(std::floor(std::log10(a.lo) - 1e-9));
  const int d1 = static_cast<int>(std::ceil(std::log10(a.hi) + 1e-9));
  // More than 8 labelled decades crowd the axis: label every k-th (and skip the minor ticks).
  int decadesInside = 0;
  for (int e = d0; e <= d1; ++e) decadesInside += within(std::pow(10.0, e), a.lo, a.hi) ? 1 : 0;
  const int every = std::max(1, (decadesInside + 7) / 8);
  int labelled = 0;
  for (int e = d0; e <= d1; ++e) {
    const double decade = std::pow(10.0, e);
    if (within(decade, a.lo, a.hi)) {
      const bool major = ((e % every) + every) % every == 0;
      a.ticks.push_back({decade, major, major ? decadeLabel(e) : TickLabel{}});
      labelled += major ? 1 : 0;
    }
    if (every == 1)
      for (int m = 2; m <= 9; ++m)
        if (within(m * decade, a.lo, a.hi)) a.ticks.push_back({m * decade, false, {}});
  }
  // Less than two decades inside (a narrow range): label 2 and 5 too, then every minor tick.
  for (const std::array<int, 2>& mantissas : {std::array<int, 2>{2, 5}, std::array<int, 2>{0, 0}}) {
    if (labelled >= 2 || every != 1) break;
    for (auto& t : a.ticks) {
      if (t.major) continue;
      const int m = static_cast<int>(std::lround(t.value / std::pow(10.0, exponentOf(t.value))));
      if (mantissas[0] != 0 && m != mantissas[0] && m != mantissas[1]) continue;
      t.major = true;
      t.label = numberLabel(t.value, decimalsOf(t.value));
      ++labelled;
    }
  }
  std::sort(a.ticks.begin(), a.ticks.end(),
            [](const Tick& x, const Tick& y) { return x.value < y.value; });
  // A narrow range labels its decades as plain numbers like the 2s and 5s beside them ("1", "2",
  // "5", "10" rather than 10⁰ beside 2), as long as the numbers stay short.
  const bool plain = std::log10(a.hi / a.lo) <= 3.0 && a.lo >= 1e-3 && a.hi <= 1e4;
  if (plain)
    for (auto& t : a.ticks)
      if (t.major) t.label = numberLabel(t.value, decimalsOf(t.value));
  return a;
}

Axis sqrtAxis(double top) {
  Axis a;
  a.kind = AxisKind::Sqrt;
  a.lo = 0.0;
  a.hi = top > 0.0 && std::isfinite(top) ? ceilRound(top) : 1.0;
  for (double t : sqrtTicks(a.hi, 6)) a.ticks.push_back({t, true, numberLabel(t, decimalsOf(t))});
  return a;
}

Axis profileYAxis(YScale scale, const Range& values) {
  switch (scale) {
    case YScale::Linear:
      // Zero is always shown: profiles are compared by their height above it.
      return values.empty() ? linearAxis(0.0, 1.0) : linearAxis(std::min(0.0, values.lo), values.hi);
    case YScale::Log:
      return values.empty() ? logAxis(1e-3, 1.0, true) : logAxis(values.lo, values.hi, true);
    case YScale::Sqrt: return sqrtAxis(values.empty() ? 1.0 : values.hi);
  }
  return linearAxis(0.0, 1.0);
}

namespace {

std::string unitPower(const std::string& unit, const char* power) {
  const bool compound = unit.find(' ') != std::string::npos;
  return compound ? fmt::format("({}){}", unit, power) : unit + power;
}

}  // namespace

std::string profileXTitle(const PlotOptions& options) {
  return fmt::format("radial distance r [{}]", options.length_unit);
}

std::string profileYTitle(const PlotOptions& options, const std::vector<analysis::Curve>& curves) {
  std::string title = options.times_r
                          ? fmt::format("r·R(r) [{}]", unitPower(options.length_unit, "⁻¹"))
                          : fmt::format("diffuse reflectance R(r) [{}]",
                                        unitPower(options.length_unit, "⁻²"));
  std::vector<std::string> channels;
  for (const auto& c : curves)
    if (std::find(channels.begin(), channels.end(), c.channel) == channels.end())
      channels.push_back(c.channel);
  if (channels.size() == 1)
    title += channels[0] == "luminance" ? std::string(", luminance")
                                        : fmt::format(", {} channel", channelWords(channels[0]));
  if (options.y_scale == YScale::Sqrt) title += ", square-root scale";
  return title;
}

}  // namespace translucent::plot
