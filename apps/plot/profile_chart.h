// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's pencil-plot and x-y charts with Qt Charts (target translucent::plot_qt, built
// with TRANSLUCENT_GUI only): the same curves, scales, styles and legend names as the files of
// plot/profile_plot.h, as a QChart that a QChartView shows and the user can resize. Files are
// written by plot/profile_plot.h (cairo), never from here, so the command line needs no Qt.
//
// Qt Charts has no square-root axis: the sqrt chart plots sqrt(y) on a QCategoryAxis whose labels
// are the original values. References are points with a shaded ±1 standard-error band.
#pragma once

#include <QtCore/qglobal.h>

#include <memory>
#include <vector>

#include "plot/profile_plot.h"

QT_BEGIN_NAMESPACE
class QApplication;
class QChart;
QT_END_NAMESPACE

namespace translucent::plot {

// The chart for `curves` (ownership passes to the caller; QChartView::setChart takes it over).
// Needs a QApplication (see GuiSession). Never throws for bad values; they are dropped.
std::unique_ptr<QChart> makeProfileChart(const std::vector<analysis::Curve>& curves,
                                         const PlotOptions& options);

// A logarithmic y axis made by makeProfileChart labels every k-th decade, k the smallest that
// leaves each label its text height (Qt Charts divides the axis height by the number of labels
// and elides a label taller than its share: a 150 px chart showed "…" for every tick). Call when
// the chart's plot area changes.
void fitLogAxisLabels(QChart& chart);

// One line with point markers per series, optionally logarithmic axes (points a log axis cannot
// show are dropped).
std::unique_ptr<QChart> makeXyChart(const std::vector<XySeries>& series, const XyPlotOptions& options);

// Ensures a QApplication exists while it lives. When none does, it creates one on the offscreen
// platform (tests have no display); an existing QApplication (the explorer's) is used as is.
// Throws std::runtime_error when a non-widget QCoreApplication/QGuiApplication already exists,
// since charts need widgets.
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
