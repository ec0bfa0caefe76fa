// SPDX-License-Identifier: GPL-3.0-or-later
// Pencil plots: radial reflectance profiles R(r) of several models on a semi-infinite slab lit by
// a pencil beam, written as PNG, SVG or PDF files; and generic x-y plots (`translucent compare
// --sweep`). Drawn with cairo (one drawing code for its image, SVG and PDF surfaces), so the
// command line needs no GUI toolkit. The explorer's interactive widget draws the same curves with
// Qt Charts (plot/profile_chart.h, target translucent::plot_qt) in the same styles
// (plot/plot_style.h).
//
// Y scales: linear; logarithmic (accurate far from the source, where values are small); square
// root (compresses the peak less than log, so errors near the source, which dominate light
// transport, stay visible), with ticks labelled in the original units.
//
// Values that a scale cannot show (non-finite; <= 0 on log; < 0 on sqrt) are dropped and the curve
// is broken there rather than joined across the gap. Curves with a non-empty `stderr_` (a Monte
// Carlo reference) are drawn as markers with ±1 standard-error bars, above the model curves.
//
// Units: r in `length_unit` (scene units; with scale 1 the presets are in mm), R(r) per area
// [length_unit⁻²], r·R(r) [length_unit⁻¹].
#pragma once

#include <string>
#include <vector>

#include "translucent/bssrdf/profile_curves.h"

namespace translucent::plot {

enum class YScale { Linear, Log, Sqrt };
// "lin"/"linear", "log", "sqrt"; anything else throws ParameterError naming the value.
YScale parseYScale(const std::string& s);
const char* yScaleName(YScale s);  // "lin", "log", "sqrt"

struct PlotOptions {
  std::string title;                // empty: no title
  YScale y_scale = YScale::Log;
  bool times_r = false;             // curves hold r·R(r) (axis label "r·R(r)")
  std::string length_unit = "mm";   // unit of r, e.g. "mm", "cm", "2.5 mm"
  int width = 1600;                 // output size in pixels (files only; a widget sizes itself)
  int height = 1000;
};

// Writes the plot to `path`: PNG, SVG or PDF chosen by the extension (case-insensitive). PNG and
// SVG are width x height pixels. The layout is made for 800 x 500 units and scaled up by
// s = max(1, min(width / 800, height / 500)), so text and lines keep their proportions at any
// resolution; a PDF page is that layout in points, width/s x height/s (800 x 500 pt for the
// default 1600 x 1000). Throws ParameterError for another extension or a size outside
// [64, 16384] pixels, std::runtime_error naming the file when it cannot be written. Never throws
// for bad values; they are dropped.
void writeProfilePlot(const std::string& path, const std::vector<analysis::Curve>& curves,
                      const PlotOptions& options);
// The checks writeProfilePlot makes of the file name and the size (ParameterError), made before
// the curves are computed (a path-traced reference can take minutes).
void checkPlotOutput(const std::string& path, int width, int height);

// Generic x-y plots (e.g. `translucent compare --sweep`: error against GPU time): one line with
// point markers per series, optionally logarithmic axes (points a log axis cannot show are
// dropped). Same files and sizes as writeProfilePlot.
struct XySeries {
  std::string label;
  std::vector<double> x, y;
};
struct XyPlotOptions {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  int width = 1600, height = 1000;
};
void writeXyPlot(const std::string& path, const std::vector<XySeries>& series,
                 const XyPlotOptions& options);

}  // namespace translucent::plot

// The explorer's sources include this header for the Qt Charts functions too: targets that link
// translucent::plot_qt get them here (that target defines TRANSLUCENT_PLOT_QT); nothing else sees
// a Qt type.
#ifdef TRANSLUCENT_PLOT_QT
#include "plot/profile_chart.h"  // IWYU pragma: export
#endif
