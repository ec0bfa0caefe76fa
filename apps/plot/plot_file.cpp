// SPDX-License-Identifier: GPL-3.0-or-later
// Pencil plots and x-y plots drawn with cairo into PNG, SVG and PDF files: the implementation of
// profile_plot.h.
// One drawing function serves the three formats: only the cairo surface differs.
#include "plot/profile_plot.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "plot/plot_axes.h"
#include "plot/plot_style.h"

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

// The layout's size (see writeProfilePlot); all lengths below are in its units.
constexpr double kLogicalWidth = 800.0, kLogicalHeight = 500.0;
constexpr int kMinPixels = 64, kMaxPixels = 16384;

// DejaVu Sans: on every Debian system (fonts-dejavu-core), and it has the glyphs the labels use
// (superscript minus and digits, ·, ±, µ, ×). fontconfig substitutes another sans font elsewhere.
constexpr const char* kFont = "DejaVu Sans";
constexpr double kTitleSize = 13.0, kAxisTitleSize = 11.0, kTickSize = 10.0, kLegendSize = 10.0;
constexpr double kSuperscriptScale = 0.72, kSuperscriptRise = 0.42;  // of the label's size
constexpr double kAscent = 0.76;  // DejaVu Sans digits and capitals, of the font size
constexpr double kPad = 12.0, kMajorTick = 5.0, kMinorTick = 3.0, kTickGap = 4.0;
constexpr double kFrameWidth = 0.8, kGridWidth = 0.6, kErrorBarWidth = 0.9;
constexpr double kMarkerRadius = 2.1;
constexpr size_t kMaxReferenceMarks = 80;  // a reference's markers along a profile plot
constexpr double kLegendRow = 1.6 * kLegendSize, kLegendSample = 32.0, kLegendGap = 6.0;

constexpr Colour kInk = {0x1a, 0x1a, 0x1a};
constexpr Colour kFrame = {0x33, 0x33, 0x33};
constexpr Colour kGrid = {0xdd, 0xdd, 0xdd};
constexpr Colour kMinorGrid = {0xf0, 0xf0, 0xf0};

void setColour(cairo_t* cr, Colour c) { cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

void setFont(cairo_t* cr, double size, bool bold = false) {
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

double advance(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

double textWidth(cairo_t* cr, const std::string& s, double size, bool bold = false) {
  setFont(cr, size, bold);
  return advance(cr, s);
}

void showText(cairo_t* cr, const std::string& s, double x, double baseline) {
  cairo_move_to(cr, x, baseline);
  cairo_show_text(cr, s.c_str());
}

double labelWidth(cairo_t* cr, const TickLabel& l, double size) {
  double w = textWidth(cr, l.text, size);
  if (!l.exponent.empty()) w += textWidth(cr, l.exponent, size * kSuperscriptScale);
  return w;
}

void showLabel(cairo_t* cr, const TickLabel& l, double size, double x, double baseline) {
  setFont(cr, size);
  showText(cr, l.text, x, baseline);
  if (l.exponent.empty()) return;
  const double w = advance(cr, l.text);
  setFont(cr, size * kSuperscriptScale);
  showText(cr, l.exponent, x + w, baseline - kSuperscriptRise * size);
}

// A marker centred at (x, y) as a path (the caller fills and strokes it).
void markerPath(cairo_t* cr, Marker m, double x, double y, double radius) {
  switch (m) {
    case Marker::Circle:
      cairo_new_sub_path(cr);
      cairo_arc(cr, x, y, radius, 0.0, 2.0 * std::numbers::pi);
      break;
    case Marker::Square: {
      const double a = 0.88 * radius;  // same area as the circle, about
      cairo_rectangle(cr, x - a, y - a, 2.0 * a, 2.0 * a);
      break;
    }
    case Marker::Triangle: {
      const double a = 1.3 * radius;
      cairo_move_to(cr, x, y - a);
      cairo_line_to(cr, x + 0.866 * a, y + 0.5 * a);
      cairo_line_to(cr, x - 0.866 * a, y + 0.5 * a);
      cairo_close_path(cr);
      break;
    }
    case Marker::Diamond: {
      const double a = 1.25 * radius;
      cairo_move_to(cr, x, y - a);
      cairo_line_to(cr, x + a, y);
      cairo_line_to(cr, x, y + a);
      cairo_line_to(cr, x - a, y);
      cairo_close_path(cr);
      break;
    }
  }
}

// Filled in its colour with a thin white edge, which keeps a marker readable over a curve; or
// open (an outline in its colour): a profile plot's references are drawn above the curves, and a
// filled marker hid the model curve that follows the reference closely (photon beam diffusion
// under the path-traced dots).
void drawMarker(cairo_t* cr, Marker m, Colour c, double x, double y, double radius,
                bool open = false) {
  markerPath(cr, m, x, y, radius);
  setColour(cr, c);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  if (open) {
    cairo_set_line_width(cr, 0.9);
    cairo_stroke(cr);
    return;
  }
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 0.5);
  cairo_stroke(cr);
}

void setLineStyle(cairo_t* cr, const LineStyle& s, double width) {
  setColour(cr, s.colour);
  cairo_set_line_width(cr, width);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);  // dots are zero-length dashes with round caps
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  const std::vector<double> d = dashPattern(s.dash, width);
  cairo_set_dash(cr, d.data(), static_cast<int>(d.size()), 0.0);
}

struct LegendEntry {
  std::string name;
  LineStyle line;
  bool has_line = true;
  bool has_marker = false;
  bool open_marker = false;  // drawn as an outline (a profile plot's reference)
  bool error_bar = false;
  Marker marker = Marker::Circle;
};

// Plot area in layout units and the mapping of values onto it.
struct Frame {
  double left = 0, top = 0, right = 1, bottom = 1;
  const Axis* x = nullptr;
  const Axis* y = nullptr;
  double px(double v) const { return left + x->fraction(v) * (right - left); }
  double py(double v) const { return bottom - y->fraction(v) * (bottom - top); }
};

struct Figure {
  std::string title, x_title, y_title;
  Axis x, y;
  std::vector<LegendEntry> legend;
  std::function<void(cairo_t*, const Frame&)> data;  // draws the curves, clipped to the frame
};

void drawLegendSample(cairo_t* cr, const LegendEntry& e, double x, double yc) {
  if (e.has_line) {
    setLineStyle(cr, e.line, kCurveLineWidth);
    cairo_move_to(cr, x + 1.0, yc);
    cairo_line_to(cr, x + kLegendSample - 1.0, yc);
    cairo_stroke(cr);
  }
  const double xc = x + 0.5 * kLegendSample;
  if (e.error_bar) {
    setColour(cr, e.line.colour);
    cairo_set_line_width(cr, kErrorBarWidth);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_set_dash(cr, nullptr, 0, 0.0);
    cairo_move_to(cr, xc, yc - 0.45 * kLegendSize);
    cairo_line_to(cr, xc, yc + 0.45 * kLegendSize);
    cairo_stroke(cr);
  }
  if (e.has_marker)
    drawMarker(cr, e.marker, e.line.colour, xc, yc, 1.25 * kMarkerRadius, e.open_marker);
}

// Lays out and draws the figure on a W x H canvas (layout units).
void drawFigure(cairo_t* cr, double W, double H, const Figure& fig) {
  // Hinting would snap glyph metrics to device pixels, so the layout would differ between the
  // PNG, the SVG and the PDF; without it one layout serves all three.
  cairo_font_options_t* fo = cairo_font_options_create();
  cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_antialias(fo, CAIRO_ANTIALIAS_GRAY);
  cairo_set_font_options(cr, fo);
  cairo_font_options_destroy(fo);

  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);

  // ---- Layout: title on top, y labels left, x labels below, legend right of the plot (or, when
  // that would leave the plot too narrow, below it in rows). The legend never covers data.
  double yTickWidth = 0.0;
  for (const Tick& t : fig.y.ticks)
    if (t.major) yTickWidth = std::max(yTickWidth, labelWidth(cr, t.label, kTickSize));
  bool xExponents = false;
  for (const Tick& t : fig.x.ticks) xExponents = xExponents || !t.label.exponent.empty();
  const double xTickAscent = (xExponents ? kSuperscriptRise + kSuperscriptScale * kAscent : kAscent) * kTickSize;

  Frame f;
  f.x = &fig.x;
  f.y = &fig.y;
  f.top = kPad + (fig.title.empty() ? 0.5 * kTickSize : 1.9 * kTitleSize);
  f.left = kPad + 1.3 * kAxisTitleSize + yTickWidth + kTickGap + kMajorTick;
  const double xLabelsHeight = kMajorTick + kTickGap + xTickAscent + 0.35 * kTickSize + 6.0 +
                               1.05 * kAxisTitleSize;
  f.bottom = H - kPad - xLabelsHeight;

  double legendTextWidth = 0.0;
  for (const auto& e : fig.legend)
    legendTextWidth = std::max(legendTextWidth, textWidth(cr, e.name, kLegendSize));
  const double columnWidth = kLegendSample + kLegendGap + legendTextWidth + 14.0;
  const auto n = static_cast<int>(fig.legend.size());
  int columns = 0, rows = 0;
  bool legendBelow = false;
  if (n > 0) {
    rows = std::max(1, static_cast<int>((f.bottom - f.top) / kLegendRow));
    columns = (n + rows - 1) / rows;
    rows = (n + columns - 1) / columns;  // balanced columns
    f.right = W - kPad - columns * columnWidth;
    if (f.right - f.left < 0.55 * (W - 2.0 * kPad)) {
      legendBelow = true;
      columns = std::max(1, static_cast<int>((W - 2.0 * kPad) / columnWidth));
      rows = (n + columns - 1) / columns;
      f.bottom -= rows * kLegendRow + 8.0;
      f.right = W - kPad - 0.5 * kTickSize * 2.5;
    }
  } else {
    f.right = W - kPad - 0.5 * kTickSize * 2.5;  // room for half of the last x label
  }
  // Degenerate sizes (a 64-pixel plot) still draw something rather than a negative rectangle.
  f.right = std::max(f.right, f.left + 1.0);
  f.bottom = std::max(f.bottom, f.top + 1.0);
  const double plotW = f.right - f.left, plotH = f.bottom - f.top;

  // ---- Grid (under everything).
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  const bool yMinorGrid = fig.y.kind == AxisKind::Log && std::log10(fig.y.hi / fig.y.lo) <= 6.5;
  const bool xMinorGrid = fig.x.kind == AxisKind::Log && std::log10(fig.x.hi / fig.x.lo) <= 6.5;
  auto grid = [&](bool major) {
    setColour(cr, major ? kGrid : kMinorGrid);
    cairo_set_line_width(cr, kGridWidth);
    for (const Tick& t : fig.y.ticks)
      if (t.major == major && (major || yMinorGrid)) {
        const double y = f.py(t.value);
        if (y > f.top + 0.5 && y < f.bottom - 0.5) {
          cairo_move_to(cr, f.left, y);
          cairo_line_to(cr, f.right, y);
        }
      }
    for (const Tick& t : fig.x.ticks)
      if (t.major == major && (major || xMinorGrid)) {
        const double x = f.px(t.value);
        if (x > f.left + 0.5 && x < f.right - 0.5) {
          cairo_move_to(cr, x, f.top);
          cairo_line_to(cr, x, f.bottom);
        }
      }
    cairo_stroke(cr);
  };
  grid(false);
  grid(true);

  // ---- Data, clipped to the frame.
  cairo_save(cr);
  cairo_rectangle(cr, f.left, f.top, plotW, plotH);
  cairo_clip(cr);
  if (fig.data) fig.data(cr, f);
  cairo_restore(cr);

  // ---- Frame and ticks (outward, so they never hide a curve).
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
  setColour(cr, kFrame);
  cairo_set_line_width(cr, kFrameWidth);
  cairo_rectangle(cr, f.left, f.top, plotW, plotH);
  cairo_stroke(cr);
  for (const Tick& t : fig.x.ticks) {
    const double x = f.px(t.value);
    if (!(x >= f.left - 0.01 && x <= f.right + 0.01)) continue;
    cairo_move_to(cr, x, f.bottom);
    cairo_line_to(cr, x, f.bottom + (t.major ? kMajorTick : kMinorTick));
  }
  for (const Tick& t : fig.y.ticks) {
    const double y = f.py(t.value);
    if (!(y >= f.top - 0.01 && y <= f.bottom + 0.01)) continue;
    cairo_move_to(cr, f.left, y);
    cairo_line_to(cr, f.left - (t.major ? kMajorTick : kMinorTick), y);
  }
  cairo_stroke(cr);

  // ---- Tick labels and axis titles.
  setColour(cr, kInk);
  const double xLabelBaseline = f.bottom + kMajorTick + kTickGap + xTickAscent;
  for (const Tick& t : fig.x.ticks) {
    const double x = f.px(t.value);
    if (!t.major || !(x >= f.left - 0.01 && x <= f.right + 0.01)) continue;
    showLabel(cr, t.label, kTickSize, x - 0.5 * labelWidth(cr, t.label, kTickSize), xLabelBaseline);
  }
  for (const Tick& t : fig.y.ticks) {
    const double y = f.py(t.value);
    if (!t.major || !(y >= f.top - 0.01 && y <= f.bottom + 0.01)) continue;
    const double w = labelWidth(cr, t.label, kTickSize);
    // Centred on the tick by the digits' height (a superscript sits above the centre line).
    showLabel(cr, t.label, kTickSize, f.left - kMajorTick - kTickGap - w, y + 0.5 * kAscent * kTickSize);
  }
  const double xTitleBaseline = xLabelBaseline + 0.35 * kTickSize + 6.0 + kAscent * kAxisTitleSize;
  const double xTitleWidth = textWidth(cr, fig.x_title, kAxisTitleSize);
  showText(cr, fig.x_title, 0.5 * (f.left + f.right - xTitleWidth), xTitleBaseline);
  {
    const double w = textWidth(cr, fig.y_title, kAxisTitleSize);
    cairo_save(cr);
    cairo_translate(cr, kPad + kAscent * kAxisTitleSize, 0.5 * (f.top + f.bottom));
    cairo_rotate(cr, -0.5 * std::numbers::pi);
    showText(cr, fig.y_title, -0.5 * w, 0.0);
    cairo_restore(cr);
  }
  if (!fig.title.empty()) {
    const double w = textWidth(cr, fig.title, kTitleSize, true);
    // Centred over the plot, or over the page when it is wider than the plot.
    double x = 0.5 * (f.left + f.right - w);
    if (x < kPad || x + w > W - kPad) x = 0.5 * (W - w);
    showText(cr, fig.title, x, kPad + kAscent * kTitleSize);
  }

  // ---- Legend: entries in column-major order (the order of the curves reads down).
  if (n > 0) {
    const double x0 = legendBelow ? f.left : f.right + 14.0;
    const double y0 = legendBelow ? xTitleBaseline + 0.3 * kAxisTitleSize + 8.0 : f.top + 2.0;
    for (int i = 0; i < n; ++i) {
      const int col = legendBelow ? i % columns : i / rows;
      const int row = legendBelow ? i / columns : i % rows;
      const double x = x0 + col * columnWidth;
      const double yc = y0 + (row + 0.5) * kLegendRow;
      const LegendEntry& e = fig.legend[static_cast<size_t>(i)];
      drawLegendSample(cr, e, x, yc);
      setColour(cr, kInk);
      setFont(cr, kLegendSize);
      showText(cr, e.name, x + kLegendSample + kLegendGap, yc + 0.5 * kAscent * kLegendSize);
    }
  }
}

// ---- Files.

enum class Format { Png, Svg, Pdf };

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

Format checkPlotFile(const std::string& path, int w, int h) {
  const std::string ext = lowerExtension(path);
  if (ext != ".png" && ext != ".svg" && ext != ".pdf")
    throw ParameterError(
        fmt::format("plot file '{}': expected a name ending in .png, .svg or .pdf", path));
  if (w < kMinPixels || w > kMaxPixels || h < kMinPixels || h > kMaxPixels)
    throw ParameterError(fmt::format("plot size {}x{}: expected width and height in [{}, {}] pixels",
                                     w, h, kMinPixels, kMaxPixels));
  return ext == ".png" ? Format::Png : ext == ".svg" ? Format::Svg : Format::Pdf;
}

// The file cairo's stream functions write to; the first failing write is remembered (cairo only
// says that a write failed, not why).
struct OutputFile {
  std::FILE* file = nullptr;
  int error = 0;
  static cairo_status_t write(void* closure, const unsigned char* data, unsigned int length) {
    auto* self = static_cast<OutputFile*>(closure);
    if (std::fwrite(data, 1, length, self->file) != length) {
      if (self->error == 0) self->error = errno != 0 ? errno : EIO;
      return CAIRO_STATUS_WRITE_ERROR;
    }
    return CAIRO_STATUS_SUCCESS;
  }
};

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};

void writeFigure(const std::string& path, int w, int h, const Figure& fig,
                 const std::string& documentTitle) {
  const Format format = checkPlotFile(path, w, h);
  const double s = std::max(1.0, std::min(w / kLogicalWidth, h / kLogicalHeight));
  const double W = w / s, H = h / s;

  OutputFile out;
  out.file = std::fopen(path.c_str(), "wb");
  if (!out.file)
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));

  std::unique_ptr<cairo_surface_t, SurfaceDeleter> surface;
  switch (format) {
    case Format::Png: surface.reset(cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h)); break;
    case Format::Svg:
      surface.reset(cairo_svg_surface_create_for_stream(&OutputFile::write, &out, w, h));
      cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);
      break;
    case Format::Pdf:
      surface.reset(cairo_pdf_surface_create_for_stream(&OutputFile::write, &out, W, H));
      cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_TITLE, documentTitle.c_str());
      cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATOR, "translucent");
      break;
  }
  {
    std::unique_ptr<cairo_t, ContextDeleter> cr(cairo_create(surface.get()));
    if (format != Format::Pdf) cairo_scale(cr.get(), s, s);
    drawFigure(cr.get(), W, H, fig);
    if (format == Format::Pdf) cairo_show_page(cr.get());
  }
  cairo_status_t status = CAIRO_STATUS_SUCCESS;
  if (format == Format::Png) {
    cairo_surface_flush(surface.get());
    status = cairo_surface_write_to_png_stream(surface.get(), &OutputFile::write, &out);
  }
  cairo_surface_finish(surface.get());  // SVG and PDF are written out here
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(surface.get());
  surface.reset();
  const bool closed = std::fclose(out.file) == 0;
  if (status != CAIRO_STATUS_SUCCESS || out.error != 0 || !closed) {
    const std::string why = out.error != 0 ? std::strerror(out.error)
                            : !closed       ? std::strerror(errno)
                                            : cairo_status_to_string(status);
    std::error_code ec;
    std::filesystem::remove(path, ec);  // no truncated file left behind
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path, why));
  }
}

}  // namespace

void writeProfilePlot(const std::string& path, const std::vector<analysis::Curve>& curves,
                      const PlotOptions& options) {
  checkPlotFile(path, options.width, options.height);
  const YScale scale = options.y_scale;
  const std::vector<CurveLook> looks = profileLooks(curves);
  const ProfileExtent extent = profileExtent(curves, scale);

  Figure fig;
  fig.title = options.title;
  fig.x_title = profileXTitle(options);
  fig.y_title = profileYTitle(options, curves);
  fig.x = linearAxis(0.0, extent.r_max > 0.0 ? extent.r_max : 1.0);
  fig.y = profileYAxis(scale, extent.values);
  for (const CurveLook& look : looks) {
    LegendEntry e;
    e.name = look.name;
    e.line = look.line;
    e.has_line = !look.reference;
    e.has_marker = e.error_bar = e.open_marker = look.reference;
    e.marker = look.marker;
    fig.legend.push_back(std::move(e));
  }
  fig.data = [&](cairo_t* cr, const Frame& f) {
    // Model curves first, in the order given, each one path (its runs as sub-paths).
    for (size_t k = 0; k < curves.size(); ++k) {
      if (looks[k].reference) continue;
      const analysis::Curve& c = curves[k];
      for (const auto& run : visibleRuns(c, scale)) {
        cairo_move_to(cr, f.px(c.r[run.front()]), f.py(c.value[run.front()]));
        for (size_t i : run) cairo_line_to(cr, f.px(c.r[i]), f.py(c.value[i]));
      }
      setLineStyle(cr, looks[k].line, kCurveLineWidth);
      cairo_stroke(cr);
    }
    // References above the curves: error bars, then markers on top of the bars. A bar's lower
    // end stops at the axis where the scale cannot show v - e (log: <= 0; sqrt: < 0).
    for (size_t k = 0; k < curves.size(); ++k) {
      if (!looks[k].reference) continue;
      const analysis::Curve& c = curves[k];
      setColour(cr, looks[k].line.colour);
      cairo_set_line_width(cr, kErrorBarWidth);
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
      cairo_set_dash(cr, nullptr, 0, 0.0);
      // At most kMaxReferenceMarks marks along the axis (every stride-th sample; the CSV keeps them
      // all): 200 touching circles would hide a model curve that follows the reference.
      const size_t stride = std::max<size_t>(1, (c.r.size() + kMaxReferenceMarks - 1) /
                                                     kMaxReferenceMarks);
      for (const auto& run : visibleRuns(c, scale))
        for (size_t i : run) {
          if (i % stride != 0) continue;
          const double e = stderrAt(c, i);
          if (e <= 0.0) continue;
          const double low = c.value[i] - e;
          const double yLow = scale == YScale::Linear || (scale == YScale::Sqrt && low >= 0.0) ||
                                      (scale == YScale::Log && low > 0.0)
                                  ? f.py(low)
                                  : f.bottom + 1.0;
          cairo_move_to(cr, f.px(c.r[i]), yLow);
          cairo_line_to(cr, f.px(c.r[i]), f.py(c.value[i] + e));
        }
      cairo_stroke(cr);
      for (const auto& run : visibleRuns(c, scale))
        for (size_t i : run)
          if (i % stride == 0)
            drawMarker(cr, looks[k].marker, looks[k].line.colour, f.px(c.r[i]), f.py(c.value[i]),
                       kMarkerRadius, /*open=*/true);
    }
  };
  writeFigure(path, options.width, options.height, fig,
              options.title.empty() ? "Radial reflectance profiles" : options.title);
}

void writeXyPlot(const std::string& path, const std::vector<XySeries>& series,
                 const XyPlotOptions& options) {
  checkPlotFile(path, options.width, options.height);
  auto usable = [](double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); };
  auto pointCount = [](const XySeries& s) { return std::min(s.x.size(), s.y.size()); };
  Range xr, yr;
  for (const XySeries& s : series)
    for (size_t i = 0; i < pointCount(s); ++i)
      if (usable(s.x[i], options.log_x) && usable(s.y[i], options.log_y)) {
        xr.add(s.x[i]);
        yr.add(s.y[i]);
      }
  // Linear axes get a margin of 4% before rounding to whole ticks, so that no marker sits on the
  // frame; log axes add theirs (logAxis).
  auto axis = [](bool log, const Range& r) {
    if (r.empty()) return log ? logAxis(0.1, 1.0, false) : linearAxis(0.0, 1.0);
    if (log) return logAxis(r.lo, r.hi, false);
    const double pad = 0.04 * (r.hi - r.lo);
    return linearAxis(r.lo - pad, r.hi + pad);
  };

  Figure fig;
  fig.title = options.title;
  fig.x_title = options.x_label;
  fig.y_title = options.y_label;
  fig.x = axis(options.log_x, xr);
  fig.y = axis(options.log_y, yr);
  constexpr std::array<Marker, 4> kMarkers = {Marker::Circle, Marker::Square, Marker::Triangle,
                                              Marker::Diamond};
  for (size_t k = 0; k < series.size(); ++k) {
    LegendEntry e;
    e.name = series[k].label;
    e.line = lineStyle(k);
    e.has_marker = true;
    e.marker = kMarkers[k % kMarkers.size()];
    fig.legend.push_back(std::move(e));
  }
  fig.data = [&](cairo_t* cr, const Frame& f) {
    for (size_t k = 0; k < series.size(); ++k) {
      const XySeries& s = series[k];
      bool first = true;
      for (size_t i = 0; i < pointCount(s); ++i)
        if (usable(s.x[i], options.log_x) && usable(s.y[i], options.log_y)) {
          (first ? cairo_move_to : cairo_line_to)(cr, f.px(s.x[i]), f.py(s.y[i]));
          first = false;
        }
      setLineStyle(cr, fig.legend[k].line, kCurveLineWidth);
      cairo_stroke(cr);
      for (size_t i = 0; i < pointCount(s); ++i)
        if (usable(s.x[i], options.log_x) && usable(s.y[i], options.log_y))
          drawMarker(cr, fig.legend[k].marker, fig.legend[k].line.colour, f.px(s.x[i]),
                     f.py(s.y[i]), 1.3 * kMarkerRadius);
    }
  };
  writeFigure(path, options.width, options.height, fig,
              options.title.empty() ? "x-y plot" : options.title);
}

void checkPlotOutput(const std::string& path, int width, int height) {
  (void)checkPlotFile(path, width, height);
}

}  // namespace translucent::plot
