// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's charts with Qt Charts; see profile_chart.h. Value handling, styles and titles
// come from plot_axes.h and plot_style.h, shared with the cairo files.
#include "plot/profile_chart.h"

#include "plot/chart_legend.h"

#include <fmt/format.h>

#include <QApplication>
#include <QPen>
#include <QtCharts/QAreaSeries>
#include <QtCharts/QCategoryAxis>
#include <QtCharts/QChart>
#include <QtCharts/QLegend>
#include <QtCharts/QLegendMarker>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtGui/QFontMetricsF>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "plot/plot_axes.h"
#include "plot/plot_style.h"

namespace translucent::plot {

namespace {

constexpr double kPenWidth = 2.0;

QColor qcolour(Colour c) { return QColor(c.r, c.g, c.b); }

// The shared dash pattern in units of the pen width, as QPen::setDashPattern wants it.
QPen curvePen(const LineStyle& style) {
  QPen pen(qcolour(style.colour), kPenWidth, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin);
  const std::vector<double> d = dashPattern(style.dash, 1.0);
  if (!d.empty()) {
    QList<qreal> pattern;
    // A zero-length dash is a dot with round caps; Qt draws nothing for exactly 0.
    for (double v : d) pattern.append(std::max(v, 0.01));
    pen.setDashPattern(pattern);
  }
  return pen;
}

QScatterSeries::MarkerShape markerShape(Marker m) {
  switch (m) {
    case Marker::Circle: return QScatterSeries::MarkerShapeCircle;
    case Marker::Square: return QScatterSeries::MarkerShapeRectangle;
    case Marker::Triangle: return QScatterSeries::MarkerShapeTriangle;
    case Marker::Diamond: return QScatterSeries::MarkerShapePentagon;  // Qt Charts has no diamond
  }
  return QScatterSeries::MarkerShapeCircle;
}

std::string tickLabel(double v) { return fmt::format("{:g}", v); }

QFont sized(double points, bool bold = false) {
  QFont f = QApplication::font();
  f.setPointSizeF(points);
  f.setBold(bold);
  return f;
}

void styleAxis(QAbstractAxis* axis, const std::string& title) {
  axis->setTitleText(QString::fromStdString(title));
  axis->setTitleFont(sized(10.0));
  axis->setLabelsFont(sized(9.0));
  axis->setGridLineColor(QColor(0xD8, 0xD8, 0xD8));
  axis->setMinorGridLineColor(QColor(0xEE, 0xEE, 0xEE));
  axis->setLinePenColor(QColor(0x60, 0x60, 0x60));
}

// Vertical axis for the scale and the range of plotted (untransformed) values.
// The decades and the decades per label a log axis was built with (fitLogAxisLabels).
constexpr char kBuiltDecades[] = "translucent_decades", kBuiltStep[] = "translucent_decades_per_label";

QAbstractAxis* makeYAxis(YScale scale, const Range& values, double* logFloor) {
  switch (scale) {
    case YScale::Linear: {
      auto* axis = new QValueAxis;
      double lo = values.empty() ? 0.0 : std::min(0.0, values.lo);
      double hi = values.empty() ? 1.0 : values.hi;
      if (!(hi > lo)) hi = lo + 1.0;
      axis->setRange(lo, hi);
      axis->applyNiceNumbers();
      axis->setLabelFormat("%g");
      return axis;
    }
    case YScale::Log: {
      auto* axis = new QLogValueAxis;
      // Whole decades; beyond 12 decades labels every k decades keep the axis readable.
      int e0 = values.empty() ? -3 : static_cast<int>(std::floor(std::log10(values.lo)));
      int e1 = values.empty() ? 0 : static_cast<int>(std::ceil(std::log10(values.hi)));
      if (e1 <= e0) e1 = e0 + 1;
      const int k = std::max(1, (e1 - e0 + 11) / 12);
      e0 = k * static_cast<int>(std::floor(static_cast<double>(e0) / k));
      e1 = k * static_cast<int>(std::ceil(static_cast<double>(e1) / k));
      axis->setBase(std::pow(10.0, k));
      axis->setProperty(kBuiltDecades, QPoint(e0, e1));  // for fitLogAxisLabels
      axis->setProperty(kBuiltStep, k);
      // Qt places labels at base^ceil(log(min)/log(base)); widen by a hair so that rounding of
      // log(10^e)/log(10) never drops the label at either end.
      axis->setRange(std::pow(10.0, e0) * (1.0 - 1e-9), std::pow(10.0, e1) * (1.0 + 1e-9));
      axis->setMinorTickCount(k == 1 ? 8 : 0);  // 2..9 × 10^e
      axis->setMinorGridLineVisible(e1 - e0 <= 6);  // more decades: minor lines only clutter
      axis->setLabelFormat(e0 >= -4 && e1 <= 5 ? "%g" : "%.0e");
      *logFloor = std::pow(10.0, e0);
      return axis;
    }
    case YScale::Sqrt: {
      // A linear axis over sqrt(y) whose labels are the original values at their sqrt positions.
      auto* axis = new QCategoryAxis;
      const double top = values.empty() || !(values.hi > 0.0) ? 1.0 : ceilRound(values.hi);
      const auto ticks = sqrtTicks(top, 6);
      axis->setStartValue(0.0);
      axis->setRange(0.0, std::sqrt(top));
      // Labels sit at category ends; a vanishing first category puts "0" at the origin.
      axis->append("0", 1e-9 * std::sqrt(top));
      for (size_t i = 1; i < ticks.size(); ++i) {
        // Position from the printed label, so that label and position agree exactly
        // (from_chars: independent of the locale that QApplication installs).
        const std::string label = tickLabel(ticks[i]);
        double shown = ticks[i];
        std::from_chars(label.data(), label.data() + label.size(), shown);
        axis->append(QString::fromStdString(label), std::sqrt(shown));
      }
      axis->setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
      return axis;
    }
  }
  return nullptr;
}

void hideFromLegend(QChart& chart, QAbstractSeries* series) {
  for (QLegendMarker* m : chart.legend()->markers(series)) m->setVisible(false);
  series->setProperty(kHiddenFromLegend, true);  // for a ChartLegend
}

}  // namespace

// Qt idiom: series, axes and their helpers are created with `new` and owned by the chart
// (addSeries/addAxis) or by their QObject parent; the chart itself is returned in a unique_ptr.
std::unique_ptr<QChart> makeProfileChart(const std::vector<analysis::Curve>& curves,
                                         const PlotOptions& options) {
  const YScale scale = options.y_scale;
  auto chart = std::make_unique<QChart>();
  chart->setBackgroundRoundness(0.0);
  chart->setMargins(QMargins(4, 4, 12, 4));
  if (!options.title.empty()) {
    chart->setTitle(QString::fromStdString(options.title));
    chart->setTitleFont(sized(12.0, true));
  }

  // Colours, dashes, markers and legend names as in the files (plot_style.h).
  const std::vector<CurveLook> looks = profileLooks(curves);
  auto lookOf = [&](const analysis::Curve& c) -> const CurveLook& {
    return looks[static_cast<size_t>(&c - curves.data())];
  };

  // Range of everything drawn, in original units (error bands included, so they are not clipped).
  const ProfileExtent extent = profileExtent(curves, scale);
  const Range& values = extent.values;
  const double rMax = extent.r_max;

  // Axes.
  auto* xAxis = new QValueAxis;
  xAxis->setRange(0.0, rMax > 0.0 ? rMax : 1.0);
  xAxis->applyNiceNumbers();
  xAxis->setLabelFormat("%g");
  styleAxis(xAxis, profileXTitle(options));
  double logFloor = 0.0;
  QAbstractAxis* yAxis = makeYAxis(scale, values, &logFloor);
  styleAxis(yAxis, profileYTitle(options, curves));
  chart->addAxis(xAxis, Qt::AlignBottom);
  chart->addAxis(yAxis, Qt::AlignLeft);

  auto attach = [&](QAbstractSeries* s) {
    chart->addSeries(s);
    s->attachAxis(xAxis);
    s->attachAxis(yAxis);
  };
  auto y = [&](double v) { return *plotted(v, scale); };

  // Step 1: ±1 standard-error bands under everything else (hidden from the legend).
  for (const auto& c : curves) {
    if (c.stderr_.size() != c.value.size() || c.stderr_.empty()) continue;
    QColor fill = qcolour(lookOf(c).line.colour);
    fill.setAlpha(60);
    for (const auto& run : visibleRuns(c, scale)) {
      auto* upper = new QLineSeries(chart.get());
      auto* lower = new QLineSeries(chart.get());
      for (size_t i : run) {
        const double e = stderrAt(c, i), v = c.value[i];
        upper->append(c.r[i], y(v + e));
        // The band's lower edge cannot go below what the axis shows (log) or below 0 (sqrt).
        double low = v - e;
        if (scale == YScale::Log) low = std::max(low, logFloor);
        if (scale == YScale::Sqrt) low = std::max(low, 0.0);
        lower->append(c.r[i], y(low));
      }
      auto* band = new QAreaSeries(upper, lower);
      attach(band);
      band->setPen(Qt::NoPen);
      band->setBrush(fill);
      hideFromLegend(*chart, band);
    }
  }

  // Step 2: model curves as lines, references as points, in the order given.
  for (const auto& c : curves) {
    const CurveLook& look = lookOf(c);
    const QColor colour = qcolour(look.line.colour);
    const QString name = QString::fromStdString(look.name);
    const auto runs = visibleRuns(c, scale);
    if (!c.stderr_.empty()) {
      auto* points = new QScatterSeries;
      points->setName(name);
      for (const auto& run : runs)
        for (size_t i : run) points->append(c.r[i], y(c.value[i]));
      attach(points);
      points->setMarkerShape(markerShape(look.marker));
      points->setMarkerSize(5.0);
      points->setColor(colour);
      points->setBorderColor(colour);
      continue;
    }
    const QPen pen = curvePen(look.line);
    for (size_t k = 0; k < runs.size(); ++k) {
      auto* line = new QLineSeries;
      line->setName(name);
      for (size_t i : runs[k]) line->append(c.r[i], y(c.value[i]));
      attach(line);
      line->setPen(pen);
      if (k > 0) hideFromLegend(*chart, line);  // one legend entry per curve
    }
  }

  // The legend sits beside the plot area (never over the curves).
  QLegend* legend = chart->legend();
  legend->setAlignment(Qt::AlignRight);
  legend->setMarkerShape(QLegend::MarkerShapeFromSeries);
  legend->setFont(sized(9.0));
  legend->setVisible(!curves.empty());
  return chart;
}

namespace {

int argcStore = 1;
char appName[] = "translucent";
char* argvStore[] = {appName, nullptr};

}  // namespace

GuiSession::GuiSession() {
  if (QCoreApplication* app = QCoreApplication::instance()) {
    if (!qobject_cast<QApplication*>(app))
      throw std::runtime_error(
          "plots need a QApplication, but a QCoreApplication/QGuiApplication already exists");
    return;
  }
  // File output never shows a window: render on the offscreen platform whatever the environment
  // says, then restore the environment for anything the process starts later.
  const bool had = qEnvironmentVariableIsSet("QT_QPA_PLATFORM");
  const QByteArray previous = qgetenv("QT_QPA_PLATFORM");
  qputenv("QT_QPA_PLATFORM", "offscreen");
  // Headless sessions (CI, ssh) often have no XDG_RUNTIME_DIR; Qt then warns on every run. A
  // private per-user directory is what it would fall back to anyway, so give it one quietly.
  if (!qEnvironmentVariableIsSet("XDG_RUNTIME_DIR")) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("translucent-runtime-" + std::to_string(::getuid()));
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    std::filesystem::permissions(dir, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::replace, ec);
    if (!ec) qputenv("XDG_RUNTIME_DIR", QByteArray::fromStdString(dir.string()));
  }
  owned_ = std::make_unique<QApplication>(argcStore, argvStore);
  if (had)
    qputenv("QT_QPA_PLATFORM", previous);
  else
    qunsetenv("QT_QPA_PLATFORM");
}

GuiSession::~GuiSession() = default;

void fitLogAxisLabels(QChart& chart) {
  const double height = chart.plotArea().height();
  if (!(height > 0.0)) return;
  for (QAbstractAxis* a : chart.axes(Qt::Vertical)) {
    auto* axis = qobject_cast<QLogValueAxis*>(a);
    const QVariant built = axis != nullptr ? axis->property(kBuiltDecades) : QVariant();
    if (!built.isValid()) continue;  // not a log axis of makeProfileChart
    const int e0 = built.toPoint().x(), e1 = built.toPoint().y();
    const double text = QFontMetricsF(axis->labelsFont()).height() + 4.0;  // + Qt's padding
    // Labels at the multiples of k from lo to hi (the range widened to them).
    auto lower = [e0](int k) { return k * static_cast<int>(std::floor(static_cast<double>(e0) / k)); };
    auto upper = [e1](int k) { return k * static_cast<int>(std::ceil(static_cast<double>(e1) / k)); };
    int k = std::max(1, axis->property(kBuiltStep).toInt());
    while (k < e1 - e0 && height / ((upper(k) - lower(k)) / k + 1) < text) ++k;
    if (std::abs(axis->base() - std::pow(10.0, k)) <= 1e-9 * axis->base()) continue;
    const int lo = lower(k), hi = upper(k);
    axis->setBase(std::pow(10.0, k));
    axis->setRange(std::pow(10.0, lo) * (1.0 - 1e-9), std::pow(10.0, hi) * (1.0 + 1e-9));
    axis->setMinorTickCount(k == 1 ? 8 : 0);
  }
}

std::unique_ptr<QChart> makeXyChart(const std::vector<XySeries>& series,
                                    const XyPlotOptions& options) {
  auto chart = std::make_unique<QChart>();
  if (!options.title.empty()) {
    chart->setTitle(QString::fromStdString(options.title));
    chart->setTitleFont(sized(11.0, true));
  }
  chart->legend()->setFont(sized(9.0));
  chart->legend()->setAlignment(Qt::AlignBottom);
  // Axes over the points a scale can show (log: > 0), with a margin.
  auto usable = [](double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); };
  Range xr, yr;
  for (const XySeries& s : series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], options.log_x) && usable(s.y[i], options.log_y)) {
        xr.add(s.x[i]);
        yr.add(s.y[i]);
      }
  auto axis = [](bool log, const Range& r, const std::string& title) -> QAbstractAxis* {
    QAbstractAxis* a = nullptr;
    if (log) {
      auto* l = new QLogValueAxis;
      l->setBase(10.0);
      l->setLabelFormat("%g");
      l->setMinorTickCount(-1);
      const double lo = r.empty() ? 0.1 : r.lo, hi = r.empty() ? 1.0 : r.hi;
      l->setRange(lo / 1.5, hi * 1.5);
      a = l;
    } else {
      auto* v = new QValueAxis;
      const double lo = r.empty() ? 0.0 : r.lo, hi = r.empty() ? 1.0 : r.hi;
      const double pad = hi > lo ? 0.05 * (hi - lo) : std::max(1e-12, 0.05 * std::abs(hi));
      v->setRange(lo - pad, hi + pad);
      v->setLabelFormat("%g");
      a = v;
    }
    styleAxis(a, title);
    return a;
  };
  QAbstractAxis* ax = axis(options.log_x, xr, options.x_label);
  QAbstractAxis* ay = axis(options.log_y, yr, options.y_label);
  chart->addAxis(ax, Qt::AlignBottom);
  chart->addAxis(ay, Qt::AlignLeft);
  for (size_t k = 0; k < series.size(); ++k) {
    const XySeries& s = series[k];
    const LineStyle style = lineStyle(k);
    const QColor colour = qcolour(style.colour);
    auto* line = new QLineSeries;
    auto* dots = new QScatterSeries;
    line->setName(QString::fromStdString(s.label));
    line->setPen(curvePen(style));
    dots->setColor(colour);
    dots->setBorderColor(colour);
    dots->setMarkerSize(7.0);
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], options.log_x) && usable(s.y[i], options.log_y)) {
        line->append(s.x[i], s.y[i]);
        dots->append(s.x[i], s.y[i]);
      }
    chart->addSeries(line);
    chart->addSeries(dots);
    for (QAbstractSeries* q : {static_cast<QAbstractSeries*>(line), static_cast<QAbstractSeries*>(dots)}) {
      q->attachAxis(ax);
      q->attachAxis(ay);
    }
    hideFromLegend(*chart, dots);
  }
  return chart;
}

}  // namespace translucent::plot
