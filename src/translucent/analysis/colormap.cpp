// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/colormap.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "translucent/analysis/color.h"
#include "translucent/io/oiio_plugin.h"  // the tick labels' text, through OpenImageIO's module
#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::analysis {
namespace {

#include "translucent/analysis/colormap_tables.inc"

constexpr std::array<uint8_t, 3> kGrey{128, 128, 128};

uint8_t to8(double v) {
  return static_cast<uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
}

std::array<uint8_t, 3> fromTable(const float (&table)[256][3], double t) {
  const int k = std::min(255, static_cast<int>(std::floor(256.0 * t)));
  return {to8(static_cast<double>(table[k][0])), to8(static_cast<double>(table[k][1])),
          to8(static_cast<double>(table[k][2]))};
}

color::Vec3 labFromLch(double L, double C, double hue_degrees) {
  const double h = hue_degrees * std::numbers::pi / 180.0;
  return {L, C * std::cos(h), C * std::sin(h)};
}

std::array<uint8_t, 3> diverging(double t) {
  static const color::Vec3 kRed = labFromLch(45.0, 70.0, 38.0);
  static const color::Vec3 kBlue = labFromLch(45.0, 60.0, -72.0);
  const double s = 2.0 * t - 1.0;
  const color::Vec3& end = s >= 0.0 ? kRed : kBlue;
  const double a = std::abs(s);
  const color::Vec3 lab{100.0 + a * (end[0] - 100.0), a * end[1], a * end[2]};
  const color::Vec3 srgb = color::labToSrgb(lab);
  return {to8(srgb[0]), to8(srgb[1]), to8(srgb[2])};
}

void checkRange(double lo, double hi, const char* what) {
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
    throw ParameterError(fmt::format("{}: range [{}, {}]: expected finite lo < hi", what, lo, hi));
}

}  // namespace

ColorMap parseColorMap(const std::string& name) {
  for (ColorMap m : {ColorMap::Viridis, ColorMap::Magma, ColorMap::Diverging})
    if (name == colorMapName(m)) return m;
  throw ParameterError(
      fmt::format("colour map '{}': expected one of viridis, magma, diverging", name));
}

const char* colorMapName(ColorMap map) {
  switch (map) {
    case ColorMap::Viridis:
      return "viridis";
    case ColorMap::Magma:
      return "magma";
    case ColorMap::Diverging:
      return "diverging";
  }
  return "?";
}

std::array<uint8_t, 3> mapColor(ColorMap map, double t) {
  if (std::isnan(t)) return kGrey;
  t = std::clamp(t, 0.0, 1.0);
  switch (map) {
    case ColorMap::Viridis:
      return fromTable(kViridis, t);
    case ColorMap::Magma:
      return fromTable(kMagma, t);
    case ColorMap::Diverging:
      return diverging(t);
  }
  return kGrey;
}

std::vector<uint8_t> falseColor(std::span<const float> values, int width, int height, ColorMap map,
                                double lo, double hi) {
  const size_t n =
      static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0));
  if (width < 1 || height < 1 || values.size() != n)
    throw ParameterError(
        fmt::format("false colour: {} values for a {}x{} map: expected {} (one a "
                    "pixel, at least 1x1)",
                    values.size(), width, height, n));
  checkRange(lo, hi, "false colour");
  std::vector<uint8_t> out(3 * n);
  for (size_t p = 0; p < n; ++p) {
    const auto c = mapColor(map, (static_cast<double>(values[p]) - lo) / (hi - lo));
    std::copy(c.begin(), c.end(), out.begin() + static_cast<std::ptrdiff_t>(3 * p));
  }
  return out;
}

ColorBarLayout colorBarLayout(int width, int height, double lo, double hi, int ticks) {
  checkRange(lo, hi, "colour bar");
  if (ticks < 2)
    throw ParameterError(fmt::format("colour bar: ticks is {}: expected at least 2", ticks));
  if (width < 2 * ticks)
    throw ParameterError(fmt::format(
        "colour bar: width {}: expected at least {} (2 pixels per tick)", width, 2 * ticks));
  if (height < 24)
    throw ParameterError(fmt::format(
        "colour bar: height {}: expected at least 24 (the bar, tick marks and labels)", height));
  ColorBarLayout l;
  // Labels take the lower ~45% of the image, at most 16 px high text.
  l.font_size = std::clamp(height * 2 / 5, 10, 16);
  l.bar_height = height - l.font_size - 6;
  for (int k = 0; k < ticks; ++k) {
    l.tick_value.push_back(lo + (hi - lo) * k / (ticks - 1));
    l.tick_x.push_back(
        static_cast<int>(std::lround(static_cast<double>(k) * (width - 1) / (ticks - 1))));
  }
  return l;
}

namespace {

// A value in [0, 1] as an 8-bit value, rounded as OpenImageIO converts float pixels to 8 bits
// (v * 255 + 0.5, clamped, truncated): the bar and the ticks are filled here, the labels are
// blended over them by the module.
uint8_t fill8(float v) {
  return static_cast<uint8_t>(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f));
}

// Fills columns [x0, x1) of rows [y0, y1) with colour v.
void fillRect(std::vector<uint8_t>& img, int width, int x0, int x1, int y0, int y1,
              const float (&v)[3]) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (size_t c = 0; c < 3; ++c)
        img[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3 +
            c] = fill8(v[c]);
}

}  // namespace

std::vector<uint8_t> colorBar(int width, int height, ColorMap map, double lo, double hi,
                              int ticks) {
  const ColorBarLayout l = colorBarLayout(width, height, lo, hi, ticks);
  std::vector<uint8_t> out(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
  const float white[3] = {1.0f, 1.0f, 1.0f}, ink[3] = {0.1f, 0.1f, 0.1f};
  fillRect(out, width, 0, width, 0, height, white);
  for (int x = 0; x < width; ++x) {
    const auto c = mapColor(map, (x + 0.5) / width);
    const float v[3] = {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
    fillRect(out, width, x, x + 1, 0, l.bar_height, v);
  }
  const io::OiioApi* api = nullptr;
  try {
    api = &io::plugin<io::OiioApi>("oiio");
  } catch (const io::PluginError& e) {
    throw ImageError(fmt::format("colour bar: cannot draw the tick labels: {}", e.what()));
  }
  const int textTop = l.bar_height + 4;
  for (int k = 0; k < ticks; ++k) {
    const int x = l.tick_x[static_cast<size_t>(k)];
    fillRect(out, width, x, x + 1, l.bar_height, std::min(l.bar_height + 3, height), ink);
    const int align = k == 0 ? -1 : k == ticks - 1 ? 1 : 0;
    const std::string text = fmt::format("{:.3g}", l.tick_value[static_cast<size_t>(k)]);
    if (std::string error; !api->render_text(out.data(), width, height, x, textTop, text.c_str(),
                                             l.font_size, "DejaVuSans", ink, align, &error))
      throw ImageError(
          fmt::format("colour bar: cannot draw the tick label '{}': {}", text, error));
  }
  return out;
}

}  // namespace translucent::analysis
