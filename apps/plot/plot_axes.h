// SPDX-License-Identifier: GPL-3.0-or-later
// Axes of the plots without any drawing: which values a y scale can show, where curves break,
// and the ticks and tick labels of linear, logarithmic and square-root axes. Qt-free; the cairo
// writer (plot_file.cpp) draws from these, and the explorer's Qt Charts widget
// (profile_chart.cpp) uses the same value handling.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "plot/profile_plot.h"
#include "translucent/bssrdf/profile_curves.h"

namespace translucent::plot {

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = v < lo ? v : lo;
    hi = v > hi ? v : hi;
  }
  bool empty() const { return !(lo <= hi); }
};

// The value as plotted on the scale (sqrt: its root), or nothing when the scale cannot show it
// (non-finite; <= 0 on log; < 0 on sqrt). Log keeps the value: its axis maps values itself.
std::optional<double> plotted(double v, YScale s);
// Standard error of point i (0 when the curve has none or it is not a positive number).
double stderrAt(const analysis::Curve& c, std::size_t i);
// Indices of the maximal runs of points the scale can show: a curve is broken at a dropped point
// instead of being joined across it.
std::vector<std::vector<std::size_t>> visibleRuns(const analysis::Curve& c, YScale s);

// Everything a profile plot draws, in original units: the values with their error bars (so that
// the bars are not clipped; on log the lower end of a bar may go below the axis) and the largest r.
struct ProfileExtent {
  Range values;
  double r_max = 0.0;
};
ProfileExtent profileExtent(const std::vector<analysis::Curve>& curves, YScale scale);

// Top of a square-root axis: the smallest m·10^e >= v with m in {1, 2, 3, 4, 5, 6, 8}.
double ceilRound(double v);
// Ticks of a square-root axis in original units: about `intervals` steps evenly spaced in sqrt(y),
// each rounded to one significant digit so that the labels read well; 0 first, `top` last.
std::vector<double> sqrtTicks(double top, int intervals);

// A tick label: `text` followed by `exponent` as a superscript when that is not empty
// ("10" "−3" is 10⁻³; "2×10" "4" is 2×10⁴). Minus signs are U+2212, not hyphens.
struct TickLabel {
  std::string text, exponent;
  friend bool operator==(const TickLabel&, const TickLabel&) = default;
};
struct Tick {
  double value = 0.0;  // in original units
  bool major = true;   // majors are labelled and get a grid line
  TickLabel label;     // empty for minor ticks
};

enum class AxisKind { Linear, Log, Sqrt };
struct Axis {
  AxisKind kind = AxisKind::Linear;
  double lo = 0.0, hi = 1.0;  // ends in original units
  std::vector<Tick> ticks;    // ascending, within [lo, hi]
  // Position along the axis in [0, 1] (log: of log10 v; sqrt: of sqrt v); NaN when it cannot be
  // placed (v <= 0 on log, v < 0 on sqrt).
  double fraction(double v) const;
};

// Linear axis over [lo, hi] widened to whole steps of 1, 2, 2.5 or 5 × 10^k, about `target`
// labelled ticks, minor ticks between them. A degenerate range is widened around its value.
Axis linearAxis(double lo, double hi, int target = 6);
// Logarithmic axis. wholeDecades: the ends are powers of ten (profiles); otherwise the ends are
// lo and hi. Decades are labelled 10^k (every k-th decade beyond 8 labelled decades), with
// minor ticks at 2..9 × 10^k; a range with fewer than two decades inside also labels 2 and 5 ×
// 10^k (and then every minor tick when that is still fewer than two labels).
Axis logAxis(double lo, double hi, bool wholeDecades);
// Square-root axis from 0 to ceilRound(top), ticks from sqrtTicks labelled in original units.
Axis sqrtAxis(double top);
// The y axis of a profile plot for the values it draws.
Axis profileYAxis(YScale scale, const Range& values);

// Labels: a decade as 10^k, other values as plain decimals with `decimals` digits after the point
// (or m×10^k when they are very large or small).
TickLabel decadeLabel(int exponent);
TickLabel numberLabel(double v, int decimals);

// Axis titles of a profile plot: "distance from the beam r [mm]" and, e.g.,
// "diffuse reflectance R(r) [mm⁻²], luminance" (the channel when only one is shown).
std::string profileXTitle(const PlotOptions& options);
std::string profileYTitle(const PlotOptions& options, const std::vector<analysis::Curve>& curves);

}  // namespace translucent::plot
