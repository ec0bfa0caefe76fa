// SPDX-License-Identifier: GPL-3.0-or-later
// Pencil plots (bssrdf-explorer seed 3.6.3): radial reflectance profiles R(r) of several models on a
// semi-infinite slab lit by a pencil beam, drawn with Qt Charts.
//
// One code path serves two front ends: makeProfileChart() builds a QChart that the explorer's
// pencil-plot widget shows in a QChartView, and writeProfilePlot() renders the same chart offscreen
// into a PNG (raster, QImage) or SVG (vector, QSvgGenerator) for the command line.
//
// Y scales (seed 3.6.3): linear; logarithmic (accurate far from the source, where values are small);
// square root (compresses the peak less than log, so errors near the source, which dominate light
// transport, stay visible). Qt Charts has no square-root axis, so the chart plots sqrt(y) on a
// linear axis and labels its ticks in the original units.
//
// Values that a scale cannot show (non-finite; <= 0 on log; < 0 on sqrt) are dropped and the curve
// is broken there rather than joined across the gap. Curves with a non-empty `stderr_` (a Monte
// Carlo reference) are drawn as points with a shaded ±1 standard error band.
//
// Units: r in `length_unit` (scene units; with scale 1 the presets are in mm), R(r) per area
// [length_unit⁻²], r·R(r) [length_unit⁻¹].
#pragma once

#include <QtCore/qglobal.h>

#include <memory>
#include <string>
#include <vector>

#include "translucent/bssrdf/profile_curves.h"

QT_BEGIN_NAMESPACE
class QApplication;
class QChart;
QT_END_NAMESPACE

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

// The chart for `curves` (ownership passes to the caller; QChartView::setChart takes it over).
// Needs a QApplication (see GuiSession). Never throws for bad values; they are dropped.
std::unique_ptr<QChart> makeProfileChart(const std::vector<analysis::Curve>& curves,
                                         const PlotOptions& options);

// Writes the chart to `path`: PNG or SVG chosen by the extension (case-insensitive). Throws
// ParameterError for another extension or a size outside [64, 16384] pixels, std::runtime_error
// naming the file when it cannot be written. Creates an offscreen QApplication when none exists.
void writeProfilePlot(const std::string& path, const std::vector<analysis::Curve>& curves,
                      const PlotOptions& options);

// Generic x-y charts (e.g. `translucent compare --sweep`: error against GPU time): one line with
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
std::unique_ptr<QChart> makeXyChart(const std::vector<XySeries>& series, const XyPlotOptions& options);
void writeXyPlot(const std::string& path, const std::vector<XySeries>& series,
                 const XyPlotOptions& options);

// Ensures a QApplication exists while it lives. When none does, it creates one on the offscreen
// platform (file output never needs a window, and batch runs have no display); an existing
// QApplication (the explorer's) is used as is. Throws std::runtime_error when a non-widget
// QCoreApplication/QGuiApplication already exists, since charts need widgets.
class GuiSession {
 public:
  GuiSession();
  ~GuiSession();
  GuiSession(const GuiSession&) = delete;
  GuiSession& operator=(const GuiSession&) = delete;

 private:
  std::unique_ptr<QApplication> owned_;
};

}  // namespace translucent::plot
