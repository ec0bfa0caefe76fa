// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's Qt Charts plots (apps/plot, translucent::plot_qt): the chart honours each y scale
// (log drops non-positive values, sqrt plots roots with ticks labelled in original units), legends
// and colours name models and channels as the files do (plot_style.h), references get points with
// ±1 s.e. bands. Everything renders on Qt's offscreen platform. The files: test_plot_file.cpp.
#include <gtest/gtest.h>

#include <QApplication>
#include <QtCharts/QAreaSeries>
#include <QtCharts/QCategoryAxis>
#include <QtCharts/QChart>
#include <QtCharts/QLegend>
#include <QtCharts/QLegendMarker>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "translucent/bssrdf/profile_curves.h"
#include "plot/plot_style.h"
#include "plot/profile_chart.h"

namespace translucent::plot {
namespace {

namespace fs = std::filesystem;

// A profile-like curve: exp(-k r) / (r + 0.1) at r = 0.05, 0.10, ..., n * 0.05.
analysis::Curve synthetic(const std::string& model, const std::string& channel, double k,
                          int n = 100) {
  analysis::Curve c{model, channel, {}, {}, {}};
  for (int i = 1; i <= n; ++i) {
    const double r = 0.05 * i;
    c.r.push_back(r);
    c.value.push_back(std::exp(-k * r) / (r + 0.1));
  }
  return c;
}

template <class T>
std::vector<T*> seriesOf(const QChart& chart) {
  std::vector<T*> out;
  for (QAbstractSeries* s : chart.series())
    if (auto* t = qobject_cast<T*>(s)) out.push_back(t);
  return out;
}

// Names of the legend entries that are shown, in order (laid out as a widget would lay it out).
std::vector<std::string> legendNames(QChart& chart) {
  chart.resize(800, 500);
  QCoreApplication::sendPostedEvents();
  QCoreApplication::processEvents();
  std::vector<std::string> names;
  for (QLegendMarker* m : chart.legend()->markers())
    if (m->isVisible()) names.push_back(m->label().toStdString());
  return names;
}

QAbstractAxis* yAxisOf(const QChart& chart) {
  const auto axes = chart.axes(Qt::Vertical);
  return axes.isEmpty() ? nullptr : axes.front();
}

double parseNumber(const QString& s) {
  const std::string t = s.toStdString();
  double v = std::numeric_limits<double>::quiet_NaN();
  std::from_chars(t.data(), t.data() + t.size(), v);
  return v;
}

bool isPowerOfTen(double v) {
  const double e = std::log10(v);
  return std::abs(e - std::round(e)) < 1e-6;
}

TEST(PlotScale, ParsesNamesAndRejectsOthers) {
  EXPECT_EQ(parseYScale("lin"), YScale::Linear);
  EXPECT_EQ(parseYScale("linear"), YScale::Linear);
  EXPECT_EQ(parseYScale("log"), YScale::Log);
  EXPECT_EQ(parseYScale("sqrt"), YScale::Sqrt);
  for (YScale s : {YScale::Linear, YScale::Log, YScale::Sqrt})
    EXPECT_EQ(parseYScale(yScaleName(s)), s);
  try {
    parseYScale("cubic");
    FAIL() << "expected ParameterError";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("cubic"), std::string::npos) << e.what();
  }
}

TEST(PlotChart, LogScaleDropsNonPositiveValuesAndBreaksTheCurve) {
  GuiSession gui;
  auto c = synthetic("dipole", "luminance", 1.0, 20);
  // Two non-positive values and two non-finite ones: four points the log axis cannot show.
  c.value[5] = 0.0;
  c.value[6] = -1.0;
  c.value[12] = std::numeric_limits<double>::quiet_NaN();
  c.value[19] = std::numeric_limits<double>::infinity();
  PlotOptions o;
  o.y_scale = YScale::Log;
  const auto chart = makeProfileChart({c}, o);

  auto* axis = qobject_cast<QLogValueAxis*>(yAxisOf(*chart));
  ASSERT_NE(axis, nullptr) << "log scale must use a QLogValueAxis";
  const auto lines = seriesOf<QLineSeries>(*chart);
  // Runs [0,5), [7,12), [13,19): the curve is broken at dropped points, never joined across.
  ASSERT_EQ(lines.size(), 3u);
  size_t points = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (auto* s : lines)
    for (const QPointF& p : s->points()) {
      ++points;
      EXPECT_GT(p.y(), 0.0);
      lo = std::min(lo, p.y());
      hi = std::max(hi, p.y());
    }
  EXPECT_EQ(points, 20u - 4u);
  // Whole decades that contain every plotted value.
  EXPECT_LE(axis->min(), lo);
  EXPECT_GE(axis->max(), hi);
  EXPECT_TRUE(isPowerOfTen(axis->min())) << axis->min();
  EXPECT_TRUE(isPowerOfTen(axis->max())) << axis->max();
  EXPECT_GT(axis->min() * 10.0, lo * (1.0 - 1e-6));  // no empty decade below the data
  EXPECT_EQ(legendNames(*chart), std::vector<std::string>{"dipole"});
}

TEST(PlotChart, SqrtScalePlotsRootsWithTicksLabelledInOriginalUnits) {
  GuiSession gui;
  auto c = synthetic("dipole", "luminance", 1.0, 60);
  c.value[10] = -0.5;  // cannot be shown: dropped
  c.value[20] = 0.0;   // sqrt(0) = 0: kept
  PlotOptions o;
  o.y_scale = YScale::Sqrt;
  const auto chart = makeProfileChart({c}, o);

  auto* axis = qobject_cast<QCategoryAxis*>(yAxisOf(*chart));
  ASSERT_NE(axis, nullptr) << "sqrt scale must use a labelled QCategoryAxis";
  // Plotted values are square roots of the data.
  std::map<double, double> byR;
  for (size_t i = 0; i < c.r.size(); ++i) byR[c.r[i]] = c.value[i];
  size_t points = 0;
  for (auto* s : seriesOf<QLineSeries>(*chart))
    for (const QPointF& p : s->points()) {
      ++points;
      EXPECT_NEAR(p.y(), std::sqrt(byR.at(p.x())), 1e-12);
    }
  EXPECT_EQ(points, 59u);

  // Each label is a value in original units placed at its square root; labels increase, span
  // the data and are spread evenly in sqrt(y) (gaps within a factor 2 of the mean).
  const QStringList labels = axis->categoriesLabels();
  ASSERT_GE(labels.size(), 5);
  EXPECT_EQ(labels.front(), "0");
  std::vector<double> positions = {0.0};
  double previous = 0.0;
  for (qsizetype i = 1; i < labels.size(); ++i) {
    const double v = parseNumber(labels[i]);
    ASSERT_TRUE(std::isfinite(v)) << labels[i].toStdString();
    EXPECT_GT(v, previous);
    EXPECT_NEAR(axis->endValue(labels[i]), std::sqrt(v), 1e-12 * std::sqrt(v));
    positions.push_back(std::sqrt(v));
    previous = v;
  }
  const double maxValue = *std::max_element(c.value.begin(), c.value.end());
  EXPECT_GE(previous, maxValue);
  EXPECT_NEAR(axis->max(), std::sqrt(previous), 1e-12);
  const double mean = positions.back() / static_cast<double>(positions.size() - 1);
  for (size_t i = 1; i < positions.size(); ++i) {
    EXPECT_GT(positions[i] - positions[i - 1], 0.4 * mean) << labels[static_cast<int>(i)].toStdString();
    EXPECT_LT(positions[i] - positions[i - 1], 2.0 * mean) << labels[static_cast<int>(i)].toStdString();
  }
}

TEST(PlotChart, LinearScaleShowsZeroAndEveryValue) {
  GuiSession gui;
  auto c = synthetic("dipole", "luminance", 1.0, 30);
  c.value[3] = -0.25;  // linear axes show negative values (a noisy estimate can dip below 0)
  PlotOptions o;
  o.y_scale = YScale::Linear;
  const auto chart = makeProfileChart({c}, o);
  auto* axis = qobject_cast<QValueAxis*>(yAxisOf(*chart));
  ASSERT_NE(axis, nullptr);
  EXPECT_LE(axis->min(), -0.25);
  EXPECT_GE(axis->max(), *std::max_element(c.value.begin(), c.value.end()));
  const auto lines = seriesOf<QLineSeries>(*chart);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0]->count(), 30);
}

TEST(PlotChart, ReferenceIsDrawnAsPointsWithAStandardErrorBand) {
  GuiSession gui;
  auto ref = synthetic("reference", "luminance", 1.0, 12);
  for (double v : ref.value) ref.stderr_.push_back(0.1 * v);
  ref.stderr_[11] = 2.0 * ref.value[11];  // band reaches below zero: clamped on the log axis
  const auto model = synthetic("dipole", "luminance", 1.0, 12);
  for (YScale scale : {YScale::Linear, YScale::Log, YScale::Sqrt}) {
    SCOPED_TRACE(yScaleName(scale));
    PlotOptions o;
    o.y_scale = scale;
    const auto chart = makeProfileChart({model, ref}, o);
    const auto points = seriesOf<QScatterSeries>(*chart);
    ASSERT_EQ(points.size(), 1u);
    EXPECT_EQ(points[0]->count(), 12);
    const auto bands = seriesOf<QAreaSeries>(*chart);
    ASSERT_EQ(bands.size(), 1u);
    const auto upper = bands[0]->upperSeries()->points();
    const auto lower = bands[0]->lowerSeries()->points();
    ASSERT_EQ(upper.size(), 12);
    ASSERT_EQ(lower.size(), 12);
    for (int i = 0; i < 12; ++i) {
      const auto k = static_cast<size_t>(i);
      const double v = ref.value[k], e = ref.stderr_[k];
      const double up = scale == YScale::Sqrt ? std::sqrt(v + e) : v + e;
      EXPECT_NEAR(upper[i].y(), up, 1e-12 * up);
      EXPECT_LE(lower[i].y(), points[0]->at(i).y());
      // The lower edge is v - e, clamped to what the axis can show.
      if (scale == YScale::Linear) {
        EXPECT_NEAR(lower[i].y(), v - e, 1e-12);
      } else if (scale == YScale::Sqrt) {
        EXPECT_NEAR(lower[i].y(), std::sqrt(std::max(v - e, 0.0)), 1e-12);
      } else {
        const double floor = qobject_cast<QLogValueAxis*>(yAxisOf(*chart))->min();
        EXPECT_NEAR(lower[i].y(), std::max(v - e, floor), 1e-8 * floor);
      }
    }
    // The band is not a legend entry; the points are.
    EXPECT_EQ(legendNames(*chart), (std::vector<std::string>{"dipole", "reference ±1 s.e."}));
  }
}

TEST(PlotChart, LegendAndPensTellModelsAndChannelsApart) {
  GuiSession gui;
  // Channels of two models: colour is the channel, the dash the model.
  std::vector<analysis::Curve> rgb;
  for (const char* m : {"dipole", "better-dipole"})
    for (const char* ch : {"r", "g", "b"}) rgb.push_back(synthetic(m, ch, 1.0, 10));
  const auto chart = makeProfileChart(rgb, PlotOptions{});
  EXPECT_EQ(legendNames(*chart),
            (std::vector<std::string>{"dipole (red)", "dipole (green)", "dipole (blue)",
                                      "better-dipole (red)", "better-dipole (green)",
                                      "better-dipole (blue)"}));
  const auto lines = seriesOf<QLineSeries>(*chart);
  ASSERT_EQ(lines.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    const Colour want = channelColour(i % 3 == 0 ? "r" : i % 3 == 1 ? "g" : "b");
    EXPECT_EQ(lines[i]->pen().color(), QColor(want.r, want.g, want.b)) << lines[i]->name().toStdString();
  }
  EXPECT_EQ(lines[0]->pen().dashPattern(), lines[1]->pen().dashPattern());
  EXPECT_NE(lines[0]->pen().dashPattern(), lines[3]->pen().dashPattern());

  // One channel: the legend names models only, each in its own colour; the axis says the channel.
  std::vector<analysis::Curve> lum;
  for (const char* m : {"dipole", "better-dipole", "quantized-diffusion"})
    lum.push_back(synthetic(m, "luminance", 1.0, 10));
  const auto chart2 = makeProfileChart(lum, PlotOptions{});
  EXPECT_EQ(legendNames(*chart2),
            (std::vector<std::string>{"dipole", "better-dipole", "quantized-diffusion"}));
  std::set<QRgb> colours;
  for (auto* s : seriesOf<QLineSeries>(*chart2)) colours.insert(s->pen().color().rgb());
  EXPECT_EQ(colours.size(), 3u);
  EXPECT_NE(yAxisOf(*chart2)->titleText().indexOf("luminance"), -1);
}

TEST(PlotChart, AxisTitlesCarryQuantityAndUnits) {
  GuiSession gui;
  const auto c = synthetic("dipole", "luminance", 1.0, 10);
  PlotOptions o;
  const auto chart = makeProfileChart({c}, o);
  EXPECT_EQ(chart->axes(Qt::Horizontal).front()->titleText().toStdString(), "radial distance r [mm]");
  EXPECT_TRUE(yAxisOf(*chart)->titleText().startsWith("diffuse reflectance R(r) [mm⁻²]"));
  o.times_r = true;
  o.length_unit = "2.5 mm";
  o.y_scale = YScale::Sqrt;
  const auto chart2 = makeProfileChart({c}, o);
  EXPECT_EQ(chart2->axes(Qt::Horizontal).front()->titleText().toStdString(),
            "radial distance r [2.5 mm]");
  const QString y = yAxisOf(*chart2)->titleText();
  EXPECT_TRUE(y.startsWith("r·R(r) [(2.5 mm)⁻¹]")) << y.toStdString();
  EXPECT_NE(y.indexOf("square-root"), -1) << y.toStdString();
}

}  // namespace
}  // namespace translucent::plot

namespace translucent::plot {
namespace {

// The generic x-y chart of `translucent compare --sweep`: one line and one set of markers per
// series (markers out of the legend), log axes spanning exactly the positive points, which are
// the only ones drawn.
TEST(XyChart, LogAxesDropNonPositivePointsAndSpanTheRest) {
  GuiSession session;
  const std::vector<XySeries> series = {{"a vs model", {1.0, 2.0, 4.0, 0.0}, {10.0, 5.0, 2.5, 1.0}},
                                        {"b vs physical", {3.0, 6.0}, {-1.0, 20.0}}};
  XyPlotOptions o;
  o.x_label = "ms";
  o.y_label = "error [%]";
  o.log_x = o.log_y = true;
  auto chart = makeXyChart(series, o);
  const auto lines = seriesOf<QLineSeries>(*chart);
  std::vector<QLineSeries*> plain;
  for (auto* l : lines)
    if (!qobject_cast<QScatterSeries*>(l)) plain.push_back(l);
  ASSERT_EQ(plain.size(), 2u);
  EXPECT_EQ(plain[0]->count(), 3);  // (0, 1) has x = 0
  EXPECT_EQ(plain[1]->count(), 1);  // (3, -1) has y < 0
  EXPECT_EQ(legendNames(*chart), (std::vector<std::string>{"a vs model", "b vs physical"}));
  auto* x = qobject_cast<QLogValueAxis*>(chart->axes(Qt::Horizontal).front());
  auto* y = qobject_cast<QLogValueAxis*>(yAxisOf(*chart));
  ASSERT_NE(x, nullptr);
  ASSERT_NE(y, nullptr);
  EXPECT_LT(x->min(), 1.0);
  EXPECT_GT(x->max(), 6.0);
  EXPECT_LT(y->min(), 2.5);
  EXPECT_GT(y->max(), 20.0);
  EXPECT_EQ(x->titleText().toStdString(), "ms");

}

}  // namespace
}  // namespace translucent::plot
