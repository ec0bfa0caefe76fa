// SPDX-License-Identifier: GPL-3.0-or-later
// Pencil plots with Qt Charts (seed 3.6.3); see profile_plot.h for what is drawn and why.
#include "plot/profile_plot.h"

#include <fmt/format.h>

#include <QApplication>
#include <QFile>
#include <QGraphicsScene>
#include <QImage>
#include <QImageWriter>
#include <QPainter>
#include <QSvgGenerator>
#include <QtCharts/QAreaSeries>
#include <QtCharts/QCategoryAxis>
#include <QtCharts/QChart>
#include <QtCharts/QLegend>
#include <QtCharts/QLegendMarker>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace translucent::plot {

YScale parseYScale(const std::string& s) {
  if (s == "lin" || s == "linear") return YScale::Linear;
  if (s == "log") return YScale::Log;
  if (s == "sqrt") return YScale::Sqrt;
  throw ParameterError(fmt::format("y scale '{}': expected lin, log or sqrt", s));
}

const char* yScaleName(YScale s) {
  switch (s) {
    case YScale::Linear: return "lin";
    case YScale::Log: return "log";
    case YScale::Sqrt: return "sqrt";
  }
  return "?";
}

namespace {

// The chart is laid out at about this logical size and scaled up to the requested pixels, so fonts,
// pens and markers keep their proportions at any output resolution (default 1600x1000 = 2x).
constexpr double kLogicalWidth = 800.0;
constexpr double kLogicalHeight = 500.0;
constexpr double kPenWidth = 2.0;
constexpr int kMinPixels = 64, kMaxPixels = 16384;

// Okabe-Ito palette (distinguishable with colour-vision deficiencies), one colour per model.
const std::array<QColor, 7> kModelColours = {QColor(0x00, 0x72, 0xB2), QColor(0xD5, 0x5E, 0x00),
                                             QColor(0x00, 0x9E, 0x73), QColor(0xCC, 0x79, 0xA7),
                                             QColor(0xE6, 0x9F, 0x00), QColor(0x56, 0xB4, 0xE9),
                                             QColor(0x44, 0x44, 0x44)};
// The dash pattern says the model as well: when channels are compared colour says the channel,
// and with one channel models that nearly coincide stay visible (and tell apart in grey print).
const std::array<Qt::PenStyle, 5> kModelDashes = {Qt::SolidLine, Qt::DashLine, Qt::DotLine,
                                                  Qt::DashDotLine, Qt::DashDotDotLine};

QColor channelColour(const std::string& ch) {
  if (ch == "r") return QColor(0xD6, 0x27, 0x28);
  if (ch == "g") return QColor(0x2C, 0xA0, 0x2C);
  if (ch == "b") return QColor(0x1F, 0x77, 0xB4);
  return QColor(0x33, 0x33, 0x33);
}

std::string channelWords(const std::string& ch) {
  if (ch == "r") return "red";
  if (ch == "g") return "green";
  if (ch == "b") return "blue";
  return ch;
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The value as plotted on this scale, or nothing when the scale cannot show it. The log axis maps
// values itself; the sqrt "axis" is a linear axis over sqrt(y).
std::optional<double> plotted(double v, YScale s) {
  if (!std::isfinite(v)) return std::nullopt;
  switch (s) {
    case YScale::Linear: return v;
    case YScale::Log: return v > 0.0 ? std::optional<double>(v) : std::nullopt;
    case YScale::Sqrt: return v >= 0.0 ? std::optional<double>(std::sqrt(v)) : std::nullopt;
  }
  return std::nullopt;
}

double stderrAt(const analysis::Curve& c, size_t i) {
  if (c.stderr_.size() != c.value.size()) return 0.0;
  const double e = c.stderr_[i];
  return std::isfinite(e) && e > 0.0 ? e : 0.0;
}

// Indices of maximal runs of points that the scale can show; a curve is broken at dropped points
// instead of being joined across them.
std::vector<std::vector<size_t>> visibleRuns(const analysis::Curve& c, YScale s) {
  std::vector<std::vector<size_t>> runs;
  std::vector<size_t> run;
  const size_t n = std::min(c.r.size(), c.value.size());
  for (size_t i = 0; i < n; ++i) {
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

// Top of the sqrt axis: the smallest m·10^e >= v with m in {1, 2, 3, 4, 5, 6, 8} (6.4 -> 8).
double ceilRound(double v) {
  static constexpr std::array<double, 8> kTops = {1, 2, 3, 4, 5, 6, 8, 10};
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : kTops)
    if (m * p >= v * (1.0 - 1e-9)) return m * p;
  return 10.0 * p;
}

// The label value m·10^e, m in {1, 2, 3, 5}, nearest to v on the sqrt axis (0.56 -> 0.5,
// 1.25 -> 1): the labels a reader expects, placed as evenly as the scale allows.
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

// Ticks of the square-root axis, in original units: about `intervals` steps evenly spaced in
// sqrt(y), each rounded to one significant digit so that the labels read well.
std::vector<double> sqrtTicks(double top, int intervals) {
  std::vector<double> ticks = {0.0};
  for (int k = 1; k <= intervals; ++k) {
    const double f = static_cast<double>(k) / intervals;
    const double t = k == intervals ? top : nearestRound(top * f * f);
    if (t > ticks.back() * (1.0 + 1e-9) && t <= top * (1.0 + 1e-9)) ticks.push_back(t);
  }
  return ticks;
}

std::string tickLabel(double v) { return fmt::format("{:g}", v); }

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
};

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

std::string unitPower(const std::string& unit, const char* power) {
  const bool compound = unit.find(' ') != std::string::npos;
  return compound ? fmt::format("({}){}", unit, power) : unit + power;
}

// Vertical axis for the scale and the range of plotted (untransformed) values.
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

  // Legend names and styles: colour by channel when several channels are shown (r/g/b of one
  // model get red/green/blue pens), else one colour per model; the dash always tells models apart.
  std::vector<std::string> models, channels;
  for (const auto& c : curves) {
    if (std::find(models.begin(), models.end(), c.model) == models.end()) models.push_back(c.model);
    if (std::find(channels.begin(), channels.end(), c.channel) == channels.end())
      channels.push_back(c.channel);
  }
  const bool byChannel = channels.size() > 1;
  auto modelIndex = [&](const std::string& m) {
    return static_cast<size_t>(std::find(models.begin(), models.end(), m) - models.begin());
  };
  // References (curves with errors): the first black, set apart from the models; further ones
  // (a reference's parts by scattering order) in dark greys and browns of their own.
  std::vector<std::string> references;
  for (const auto& c : curves)
    if (!c.stderr_.empty() && std::find(references.begin(), references.end(), c.model) == references.end())
      references.push_back(c.model);
  auto colourOf = [&](const analysis::Curve& c) {
    if (byChannel) return channelColour(c.channel);
    if (!c.stderr_.empty()) {
      static const QColor kReferenceColours[] = {QColor(Qt::black), QColor(150, 75, 0),
                                                 QColor(0, 110, 110), QColor(110, 110, 110)};
      const auto k = static_cast<size_t>(std::find(references.begin(), references.end(), c.model) -
                                         references.begin());
      return kReferenceColours[k % std::size(kReferenceColours)];
    }
    return kModelColours[modelIndex(c.model) % kModelColours.size()];
  };
  auto nameOf = [&](const analysis::Curve& c) {
    std::string name = byChannel ? fmt::format("{} ({})", c.model, channelWords(c.channel)) : c.model;
    if (!c.stderr_.empty()) name += " ±1 s.e.";
    return name;
  };

  // Range of everything drawn, in original units (error bands included, so they are not clipped).
  Range values;
  double rMax = 0.0;
  for (const auto& c : curves)
    for (const auto& run : visibleRuns(c, scale))
      for (size_t i : run) {
        values.add(c.value[i]);
        const double e = stderrAt(c, i);
        if (e > 0.0) {
          values.add(c.value[i] + e);
          if (scale == YScale::Linear) values.add(c.value[i] - e);
        }
        rMax = std::max(rMax, c.r[i]);
      }

  // Axes.
  auto* xAxis = new QValueAxis;
  xAxis->setRange(0.0, rMax > 0.0 ? rMax : 1.0);
  xAxis->applyNiceNumbers();
  xAxis->setLabelFormat("%g");
  styleAxis(xAxis, fmt::format("r [{}]", options.length_unit));
  double logFloor = 0.0;
  QAbstractAxis* yAxis = makeYAxis(scale, values, &logFloor);
  std::string yTitle = options.times_r
                           ? fmt::format("r·R(r) [{}]", unitPower(options.length_unit, "⁻¹"))
                           : fmt::format("R(r) [{}]", unitPower(options.length_unit, "⁻²"));
  if (channels.size() == 1)
    yTitle += channels[0] == "luminance" ? ", luminance" : fmt::format(", {} channel",
                                                                     channelWords(channels[0]));
  if (scale == YScale::Sqrt) yTitle += ", square-root scale";
  styleAxis(yAxis, yTitle);
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
    QColor fill = colourOf(c);
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
    const QColor colour = colourOf(c);
    const QString name = QString::fromStdString(nameOf(c));
    const auto runs = visibleRuns(c, scale);
    if (!c.stderr_.empty()) {
      auto* points = new QScatterSeries;
      points->setName(name);
      for (const auto& run : runs)
        for (size_t i : run) points->append(c.r[i], y(c.value[i]));
      attach(points);
      points->setMarkerShape(QScatterSeries::MarkerShapeCircle);
      points->setMarkerSize(5.0);
      points->setColor(colour);
      points->setBorderColor(colour);
      continue;
    }
    QPen pen(colour, kPenWidth, kModelDashes[modelIndex(c.model) % kModelDashes.size()]);
    pen.setCapStyle(Qt::FlatCap);
    pen.setJoinStyle(Qt::RoundJoin);
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

// Lays the chart out at its logical size and paints it scaled onto `device` (w x h pixels).
void renderChart(std::unique_ptr<QChart> chart, QPaintDevice& device, int w, int h,
                 const std::string& path) {
  const double ratio = std::max(1.0, std::min(w / kLogicalWidth, h / kLogicalHeight));
  const QRectF logical(0.0, 0.0, w / ratio, h / ratio);
  QGraphicsScene scene;
  QChart* c = chart.release();
  scene.addItem(c);  // the scene owns the chart from here on
  c->setGeometry(logical);
  // Charts lay out on posted LayoutRequest events; deliver them before painting.
  QCoreApplication::sendPostedEvents();
  QCoreApplication::processEvents();
  QPainter painter;
  if (!painter.begin(&device)) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  painter.setRenderHints(QPainter::Antialiasing | QPainter::TextAntialiasing |
                         QPainter::SmoothPixmapTransform);
  scene.render(&painter, QRectF(0.0, 0.0, w, h), logical, Qt::IgnoreAspectRatio);
  painter.end();
}

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

namespace {

// PNG (raster) or SVG (vector) by the extension; ParameterError for another one or a bad size.
void writeChartFile(const std::string& path, std::unique_ptr<QChart> chart, int w, int h,
                    const std::string& title, const std::string& description) {
  const QString file = QString::fromStdString(path);
  if (lowerExtension(path) == ".png") {
    QImage image(w, h, QImage::Format_ARGB32_Premultiplied);
    image.fill(Qt::white);
    renderChart(std::move(chart), image, w, h, path);
    QImageWriter writer(file, "png");
    if (!writer.write(image.convertToFormat(QImage::Format_RGB32)))
      throw std::runtime_error(
          fmt::format("cannot write '{}': {}", path, writer.errorString().toStdString()));
    return;
  }

  QFile out(file);
  if (!out.open(QIODevice::WriteOnly | QIODevice::Truncate))
    throw std::runtime_error(
        fmt::format("cannot write '{}': {}", path, out.errorString().toStdString()));
  QSvgGenerator svg;
  svg.setOutputDevice(&out);
  svg.setSize(QSize(w, h));
  svg.setViewBox(QRect(0, 0, w, h));
  svg.setResolution(96);  // the screen resolution fonts were laid out for
  svg.setTitle(QString::fromStdString(title));
  svg.setDescription(QString::fromStdString(description));
  renderChart(std::move(chart), svg, w, h, path);
  out.close();
  if (out.error() != QFileDevice::NoError)
    throw std::runtime_error(
        fmt::format("cannot write '{}': {}", path, out.errorString().toStdString()));
}

void checkPlotFile(const std::string& path, int w, int h) {
  const std::string ext = lowerExtension(path);
  if (ext != ".png" && ext != ".svg")
    throw ParameterError(fmt::format("plot file '{}': expected a name ending in .png or .svg", path));
  if (w < kMinPixels || w > kMaxPixels || h < kMinPixels || h > kMaxPixels)
    throw ParameterError(fmt::format("plot size {}x{}: expected width and height in [{}, {}] pixels",
                                     w, h, kMinPixels, kMaxPixels));
}

}  // namespace

void writeProfilePlot(const std::string& path, const std::vector<analysis::Curve>& curves,
                      const PlotOptions& options) {
  checkPlotFile(path, options.width, options.height);
  GuiSession session;
  writeChartFile(path, makeProfileChart(curves, options), options.width, options.height,
                 options.title.empty() ? "Radial profiles" : options.title,
                 "Pencil-beam radial reflectance profiles (translucent profile)");
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
    const QColor colour = kModelColours[k % kModelColours.size()];
    auto* line = new QLineSeries;
    auto* dots = new QScatterSeries;
    line->setName(QString::fromStdString(s.label));
    QPen pen(colour);
    pen.setWidthF(kPenWidth);
    pen.setStyle(kModelDashes[k % kModelDashes.size()]);
    line->setPen(pen);
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

void writeXyPlot(const std::string& path, const std::vector<XySeries>& series,
                 const XyPlotOptions& options) {
  checkPlotFile(path, options.width, options.height);
  GuiSession session;
  writeChartFile(path, makeXyChart(series, options), options.width, options.height,
                 options.title.empty() ? "x-y plot" : options.title, options.title);
}

}  // namespace translucent::plot
