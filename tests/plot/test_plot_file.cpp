// SPDX-License-Identifier: GPL-3.0-or-later
// The file plots (apps/plot, cairo): curve styles stay distinct (colour and dash) for 12 and more
// curves, log axes carry 10^k labels with minor ticks, and the PNG, SVG and PDF files are what
// their names say at the requested size. The all-models plot of the CLI is checked stroke by
// stroke in its SVG. No Qt: this runs in every configuration.
#include <cairo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include <unistd.h>

#include "plot/plot_axes.h"
#include "plot/plot_style.h"
#include "plot/profile_plot.h"
#include "translucent/bssrdf/profile_curves.h"
#include "translucent/bssrdf/registry.h"

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

std::vector<analysis::Curve> models(int n) {
  std::vector<analysis::Curve> curves;
  for (int i = 0; i < n; ++i)
    curves.push_back(synthetic("model " + std::to_string(i), "luminance", 0.8 + 0.2 * i));
  return curves;
}

// Per-process names: several builds may run the suite at once.
fs::path tempFile(const std::string& name) {
  return fs::path(::testing::TempDir()) /
         ("translucent_plotfile_" + std::to_string(::getpid()) + "_" + name);
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---- Styles.

TEST(PlotStyle, TwelveAndMoreCurvesNeverShareColourAndDash) {
  ASSERT_GE(kDistinctLineStyles, 12u);
  std::set<std::pair<std::string, Dash>> seen;
  for (size_t i = 0; i < kDistinctLineStyles; ++i) {
    const LineStyle s = lineStyle(i);
    EXPECT_TRUE(seen.insert({hexName(s.colour), s.dash}).second) << "curve " << i;
    // Neighbours differ in both, so that two adjacent legend entries never differ by hue alone.
    if (i > 0) {
      EXPECT_NE(lineStyle(i - 1).colour, s.colour) << i;
      EXPECT_NE(lineStyle(i - 1).dash, s.dash) << i;
    }
  }
  // Each colour comes from the palette; the references' black is not one of them.
  for (size_t i = 0; i < 12; ++i)
    EXPECT_NE(std::find(kPalette.begin(), kPalette.end(), lineStyle(i).colour), kPalette.end());
  EXPECT_EQ(std::find(kPalette.begin(), kPalette.end(), kReferenceColour), kPalette.end());
}

TEST(PlotStyle, DashPatternsAreDistinctAndScaleWithTheWidth) {
  std::set<std::vector<double>> patterns;
  for (Dash d : kDashes) patterns.insert(dashPattern(d, 1.0));
  EXPECT_EQ(patterns.size(), kDashes.size());
  EXPECT_TRUE(dashPattern(Dash::Solid, 2.0).empty());
  const auto a = dashPattern(Dash::DashDot, 1.0), b = dashPattern(Dash::DashDot, 2.0);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_DOUBLE_EQ(b[i], 2.0 * a[i]);
  // Dots are (nearly) zero-length dashes, drawn by the round cap; never exactly 0 (see
  // dashPattern).
  EXPECT_GT(dashPattern(Dash::Dotted, 1.0)[0], 0.0);
  EXPECT_LT(dashPattern(Dash::Dotted, 1.0)[0], 0.01);
}

TEST(PlotStyle, ProfileLooksByModelByChannelAndForReferences) {
  // Twelve models in one channel: twelve distinct styles, in lineStyle order.
  const auto twelve = profileLooks(models(12));
  std::set<std::pair<std::string, Dash>> styles;
  for (size_t i = 0; i < twelve.size(); ++i) {
    EXPECT_EQ(twelve[i].line, lineStyle(i));
    EXPECT_FALSE(twelve[i].reference);
    styles.insert({hexName(twelve[i].line.colour), twelve[i].line.dash});
  }
  EXPECT_EQ(styles.size(), 12u);

  // Channels of two models: colour is the channel, the dash the model.
  std::vector<analysis::Curve> rgb;
  for (const char* m : {"dipole", "better-dipole"})
    for (const char* ch : {"r", "g", "b"}) rgb.push_back(synthetic(m, ch, 1.0, 10));
  auto ref = synthetic("reference", "g", 1.0, 10);
  ref.stderr_.assign(ref.value.size(), 0.01);
  rgb.push_back(ref);
  const auto looks = profileLooks(rgb);
  ASSERT_EQ(looks.size(), 7u);
  EXPECT_EQ(looks[0].name, "dipole (red)");
  EXPECT_EQ(looks[5].name, "better-dipole (blue)");
  EXPECT_EQ(looks[0].line.colour, channelColour("r"));
  EXPECT_EQ(looks[3].line.colour, channelColour("r"));
  EXPECT_EQ(looks[1].line.colour, channelColour("g"));
  EXPECT_EQ(looks[0].line.dash, looks[1].line.dash);
  EXPECT_NE(looks[0].line.dash, looks[3].line.dash);
  EXPECT_TRUE(looks[6].reference);
  EXPECT_EQ(looks[6].name, "reference (green) ±1 s.e.");
  EXPECT_EQ(looks[6].line.colour, channelColour("g"));
  // The channel colours are three different palette colours.
  EXPECT_NE(channelColour("r"), channelColour("g"));
  EXPECT_NE(channelColour("g"), channelColour("b"));

  // Seven models in three channels: more models than dashes, so every curve gets its own style.
  std::vector<analysis::Curve> many;
  for (int m = 0; m < 7; ++m)
    for (const char* ch : {"r", "g", "b"}) many.push_back(synthetic(std::to_string(m), ch, 1.0, 5));
  std::set<std::pair<std::string, Dash>> manyStyles;
  for (const auto& l : profileLooks(many)) manyStyles.insert({hexName(l.line.colour), l.line.dash});
  EXPECT_EQ(manyStyles.size(), 21u);
}

// ---- Axes.

TEST(PlotAxes, LogAxisLabelsDecadesAsPowersOfTenWithMinorTicks) {
  const Axis a = logAxis(3e-5, 0.4, true);
  EXPECT_EQ(a.kind, AxisKind::Log);
  EXPECT_DOUBLE_EQ(a.lo, 1e-5);
  EXPECT_DOUBLE_EQ(a.hi, 1.0);
  std::vector<TickLabel> labels;
  int minor = 0;
  for (const Tick& t : a.ticks) {
    if (t.major)
      labels.push_back(t.label);
    else
      ++minor;
  }
  const std::vector<TickLabel> expected = {{"10", "\u22125"}, {"10", "\u22124"}, {"10", "\u22123"},
                                           {"10", "\u22122"}, {"10", "\u22121"}, {"10", "0"}};
  EXPECT_EQ(labels, expected);
  EXPECT_EQ(minor, 5 * 8);  // 2..9 in each of the five decades
  for (const Tick& t : a.ticks) {
    EXPECT_GE(a.fraction(t.value), -1e-9);
    EXPECT_LE(a.fraction(t.value), 1.0 + 1e-9);
  }
  EXPECT_NEAR(a.fraction(1e-3), 0.4, 1e-12);
  EXPECT_TRUE(std::isnan(a.fraction(0.0)));

  // Twenty decades: every third labelled, still as 10^k.
  const Axis wide = logAxis(1e-18, 10.0, true);
  int labelled = 0;
  for (const Tick& t : wide.ticks)
    if (t.major) {
      ++labelled;
      EXPECT_EQ(t.label.text, "10");
    }
  EXPECT_GE(labelled, 5);
  EXPECT_LE(labelled, 8);
}

TEST(PlotAxes, NarrowLogAxisLabelsPlainNumbers) {
  const Axis a = logAxis(1.0, 8.0, false);
  std::vector<std::string> labels;
  for (const Tick& t : a.ticks)
    if (t.major) {
      EXPECT_TRUE(t.label.exponent.empty());
      labels.push_back(t.label.text);
    }
  EXPECT_EQ(labels, (std::vector<std::string>{"1", "2", "5"}));
  EXPECT_LT(a.lo, 1.0);
  EXPECT_GT(a.hi, 8.0);
}

TEST(PlotAxes, LinearAndSqrtAxes) {
  const Axis lin = linearAxis(-0.25, 3.7);
  EXPECT_LE(lin.lo, -0.25);
  EXPECT_GE(lin.hi, 3.7);
  std::vector<std::string> labels;
  for (const Tick& t : lin.ticks)
    if (t.major) labels.push_back(t.label.text);
  EXPECT_EQ(labels, (std::vector<std::string>{"\u22121", "0", "1", "2", "3", "4"}));

  const Axis sq = sqrtAxis(0.56);
  EXPECT_DOUBLE_EQ(sq.hi, 0.6);
  ASSERT_GE(sq.ticks.size(), 5u);
  EXPECT_EQ(sq.ticks.front().label.text, "0");
  EXPECT_EQ(sq.ticks.back().label.text, "0.6");
  EXPECT_NEAR(sq.fraction(0.15), std::sqrt(0.15 / 0.6), 1e-12);
  EXPECT_EQ(numberLabel(2e-5, 5), (TickLabel{"2\u00d710", "\u22125"}));
}

TEST(PlotAxes, TitlesCarryQuantityAndUnits) {
  PlotOptions o;
  const std::vector<analysis::Curve> lum = {synthetic("dipole", "luminance", 1.0, 3)};
  EXPECT_EQ(profileXTitle(o), "radial distance r [mm]");
  EXPECT_EQ(profileYTitle(o, lum), "diffuse reflectance R(r) [mm⁻²], luminance");
  o.times_r = true;
  o.length_unit = "2.5 mm";
  o.y_scale = YScale::Sqrt;
  EXPECT_EQ(profileYTitle(o, {synthetic("dipole", "r", 1.0, 3)}),
            "r·R(r) [(2.5 mm)⁻¹], red channel, square-root scale");
}

// ---- Files.

struct Stroke {
  Colour colour;
  std::string dash;  // "none" when solid
};

// The strokes of curve width in a cairo SVG: <path style="...stroke-width:W;...stroke:rgb(r%,g%,b%)
// ;...stroke-dasharray:a,b;...">. Cairo writes one path per stroke call: one per curve and one
// per legend sample.
std::vector<Stroke> curveStrokes(const std::string& svg) {
  std::vector<Stroke> out;
  const std::regex path(R"re(<path style="([^"]*)")re");
  const std::regex width(R"(stroke-width:([0-9.]+);)");
  const std::regex colour(R"(stroke:rgb\(([0-9.]+)%,([0-9.]+)%,([0-9.]+)%\))");
  const std::regex dash(R"(stroke-dasharray:([0-9.,]+);)");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path); it != std::sregex_iterator(); ++it) {
    const std::string style = (*it)[1];
    std::smatch w, c, d;
    if (!std::regex_search(style, w, width) || std::abs(std::stod(w[1]) - kCurveLineWidth) > 1e-6)
      continue;
    if (!std::regex_search(style, c, colour)) continue;
    auto channel = [&](int k) {
      return static_cast<std::uint8_t>(std::lround(std::stod(c[k]) * 2.55));
    };
    Stroke s{{channel(1), channel(2), channel(3)}, "none"};
    if (std::regex_search(style, d, dash)) s.dash = d[1];
    out.push_back(s);
  }
  return out;
}

std::string dashString(Dash dash) {
  std::string s;
  for (double v : dashPattern(dash, kCurveLineWidth)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    if (!s.empty()) s += ',';
    s += buf;
  }
  return s.empty() ? "none" : s;
}

// Every curve's (colour, dash) exactly twice (its curve and its legend sample), no two curves alike.
void expectDistinctCurveStrokes(const std::string& svg, size_t curves) {
  std::map<std::pair<std::string, std::string>, int> count;
  for (const Stroke& s : curveStrokes(svg)) ++count[{hexName(s.colour), s.dash}];
  EXPECT_EQ(count.size(), curves);
  for (const auto& [style, n] : count)
    EXPECT_EQ(n, 2) << style.first << " " << style.second;
  for (size_t i = 0; i < curves; ++i) {
    const LineStyle s = lineStyle(i);
    EXPECT_EQ(count.count({hexName(s.colour), dashString(s.dash)}), 1u)
        << "curve " << i << ": " << hexName(s.colour) << " " << dashString(s.dash);
  }
}

TEST(PlotFile, SvgOfTwelveCurvesHasTwelveDistinctStrokes) {
  PlotOptions o;
  o.title = "Twelve curves";
  o.width = 900;
  o.height = 600;
  const fs::path svg = tempFile("twelve.svg");
  fs::remove(svg);
  writeProfilePlot(svg.string(), models(12), o);
  const std::string text = readFile(svg);
  EXPECT_EQ(text.rfind("<?xml", 0), 0u);
  EXPECT_NE(text.find(R"(width="900px" height="600px" viewBox="0 0 900 600")"), std::string::npos);
  EXPECT_NE(text.find("</svg>"), std::string::npos);
  expectDistinctCurveStrokes(text, 12);
}

// Counts pixels within `tol` (per component) of `target`.
int countNear(cairo_surface_t* image, Colour target, int tol) {
  const int w = cairo_image_surface_get_width(image), h = cairo_image_surface_get_height(image);
  const int stride = cairo_image_surface_get_stride(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  int n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint32_t p;
      std::memcpy(&p, data + y * stride + 4 * x, 4);  // native-endian 0xAARRGGBB
      const int r = (p >> 16) & 0xff, g = (p >> 8) & 0xff, b = p & 0xff;
      if (std::abs(r - target.r) <= tol && std::abs(g - target.g) <= tol &&
          std::abs(b - target.b) <= tol)
        ++n;
    }
  return n;
}

struct PngImage {
  cairo_surface_t* surface;
  explicit PngImage(const fs::path& p) : surface(cairo_image_surface_create_from_png(p.c_str())) {}
  ~PngImage() { cairo_surface_destroy(surface); }
  PngImage(const PngImage&) = delete;
  PngImage& operator=(const PngImage&) = delete;
  bool ok() const { return cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS; }
};

TEST(PlotFile, PngHasTheRequestedSizeAndEveryChannelColour) {
  Medium marble;
  const auto curves = analysis::profileCurves(
      {"dipole"}, marble, {analysis::Channel::Red, analysis::Channel::Green, analysis::Channel::Blue},
      analysis::CurveOptions{});
  for (YScale scale : {YScale::Linear, YScale::Log, YScale::Sqrt}) {
    SCOPED_TRACE(yScaleName(scale));
    PlotOptions o;
    o.y_scale = scale;
    o.width = 640;
    o.height = 400;
    const fs::path png = tempFile(std::string("rgb_") + yScaleName(scale) + ".PNG");
    fs::remove(png);
    writeProfilePlot(png.string(), curves, o);
    EXPECT_EQ(readFile(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    const PngImage image(png);
    ASSERT_TRUE(image.ok());
    EXPECT_EQ(cairo_image_surface_get_width(image.surface), 640);
    EXPECT_EQ(cairo_image_surface_get_height(image.surface), 400);
    // Each channel's curve in its own colour: a line over a few hundred pixels, far more than 100
    // pixels of that colour. On the linear scale the three tails coincide and the last one drawn
    // (blue) covers the others beyond the peak: the red shows near the source and in the legend.
    const int least = scale == YScale::Linear ? 60 : 100;
    for (const char* ch : {"r", "g", "b"})
      EXPECT_GT(countNear(image.surface, channelColour(ch), 30), least) << ch;
  }
}

TEST(PlotFile, PdfAndSvgFromTheSameDrawing) {
  const auto curves = models(3);
  const fs::path pdf = tempFile("three.pdf"), svg = tempFile("three.svg");
  fs::remove(pdf);
  fs::remove(svg);
  writeProfilePlot(pdf.string(), curves, PlotOptions{});
  writeProfilePlot(svg.string(), curves, PlotOptions{});
  const std::string p = readFile(pdf);
  EXPECT_EQ(p.rfind("%PDF-", 0), 0u);
  EXPECT_NE(p.find("%%EOF"), std::string::npos);
  // 800 x 500 pt for the default 1600 x 1000 pixels.
  EXPECT_NE(p.find("/MediaBox [ 0 0 800 500 ]"), std::string::npos);
  expectDistinctCurveStrokes(readFile(svg), 3);
}

TEST(PlotFile, LogScaleWithNothingPositiveStillDraws) {
  auto c = synthetic("dipole", "luminance", 1.0, 10);
  for (auto& v : c.value) v = 0.0;
  PlotOptions o;
  o.width = 320;
  o.height = 200;
  const fs::path png = tempFile("all_zero.png");
  fs::remove(png);
  writeProfilePlot(png.string(), {c}, o);
  const PngImage image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(cairo_image_surface_get_width(image.surface), 320);
}

TEST(PlotFile, ReferenceMarkersAndErrorBarsAreDrawnAboveTheCurves) {
  // A reference that lies exactly on a model curve: where both are drawn, black must win.
  auto model = synthetic("dipole", "luminance", 1.0, 40);
  auto ref = model;
  ref.model = "reference";
  for (double v : ref.value) ref.stderr_.push_back(0.3 * v);
  PlotOptions o;
  o.width = 800;
  o.height = 500;
  const fs::path png = tempFile("reference.png");
  fs::remove(png);
  writeProfilePlot(png.string(), {model, ref}, o);
  const PngImage image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_GT(countNear(image.surface, kReferenceColour, 40), 40 * 6);
  // Cairo's SVG keeps the drawing order: the curve's stroke comes before the first error bar.
  const fs::path svg = tempFile("reference.svg");
  fs::remove(svg);
  writeProfilePlot(svg.string(), {model, ref}, o);
  const std::string text = readFile(svg);
  const size_t curve = text.find("stroke-width:1.6;");
  const size_t bar = text.find("stroke-width:0.9;");
  ASSERT_NE(curve, std::string::npos);
  ASSERT_NE(bar, std::string::npos);
  EXPECT_LT(curve, bar) << "error bars must be drawn after (above) the curves";
}

TEST(PlotFile, BadExtensionSizeOrPathFailsWithAClearError) {
  const auto c = synthetic("dipole", "luminance", 1.0, 10);
  const fs::path jpg = tempFile("bad.jpg");
  fs::remove(jpg);
  try {
    writeProfilePlot(jpg.string(), {c}, PlotOptions{});
    FAIL() << "expected ParameterError";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find(".png, .svg or .pdf"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(jpg));
  PlotOptions tiny;
  tiny.width = 10;
  EXPECT_THROW(writeProfilePlot(tempFile("tiny.png").string(), {c}, tiny), ParameterError);
  for (const char* name : {"no_such_dir/x.png", "no_such_dir/x.svg", "no_such_dir/x.pdf"}) {
    const std::string path = tempFile(name).string();
    try {
      writeProfilePlot(path, {c}, PlotOptions{});
      FAIL() << "expected std::runtime_error for " << path;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(XyPlot, LogAxesPngHasTheSizeAndEachSeriesColour) {
  const std::vector<XySeries> series = {{"a vs model", {1.0, 2.0, 4.0, 0.0}, {10.0, 5.0, 2.5, 1.0}},
                                        {"b vs physical", {3.0, 6.0}, {-1.0, 20.0}}};
  XyPlotOptions o;
  o.x_label = "GPU time per frame [ms]";
  o.y_label = "error [%]";
  o.log_x = o.log_y = true;
  o.width = 500;
  o.height = 300;
  const fs::path png = tempFile("xy.png");
  fs::remove(png);
  writeXyPlot(png.string(), series, o);
  const PngImage image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(cairo_image_surface_get_width(image.surface), 500);
  EXPECT_EQ(cairo_image_surface_get_height(image.surface), 300);
  EXPECT_GT(countNear(image.surface, lineStyle(0).colour, 30), 50);
  EXPECT_GT(countNear(image.surface, lineStyle(1).colour, 30), 10);
  EXPECT_THROW(writeXyPlot(tempFile("xy.jpg").string(), series, o), ParameterError);
}

// ---- The CLI's all-models plot: every model of the registry as a curve of its own style.

TEST(PlotAllModels, CliSvgGivesEveryModelItsOwnColourAndDash) {
  const size_t n = bssrdf::modelNames().size();
  ASSERT_GE(n, 9u);
  const fs::path svg = tempFile("all_models.svg");
  fs::remove(svg);
  const std::string command = std::string("'") + TRANSLUCENT_CLI + "' profile --preset Marble " +
                              "--model all --out '" + svg.string() + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  expectDistinctCurveStrokes(readFile(svg), n);
}

}  // namespace
}  // namespace translucent::plot
