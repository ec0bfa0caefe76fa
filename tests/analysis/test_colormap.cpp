// SPDX-License-Identifier: GPL-3.0-or-later
// False colour and colour bars (src/analysis/colormap.h): the published end points of viridis and
// magma, their lightness increasing along the map, the diverging map's white centre and
// symmetric lightness, NaN grey, the mapping of a range, and the colour bar's bar and labels.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "translucent/analysis/color.h"
#include "translucent/analysis/colormap.h"
#include "translucent/io/image_io.h"
#include "translucent/optics/medium.h"

namespace translucent::analysis {
namespace {

using Rgb8 = std::array<uint8_t, 3>;

double lightness(const Rgb8& c) {
  return color::srgbToLab({c[0] / 255.0, c[1] / 255.0, c[2] / 255.0})[0];
}

TEST(ColorMaps, EndPointsAreMatplotlibs) {
  // matplotlib's _viridis_data[0] = (0.267004, 0.004874, 0.329415) -> (68, 1, 84),
  // [255] = (0.993248, 0.906157, 0.143936) -> (253, 231, 37); _magma_data[0] = (0.001462,
  // 0.000466, 0.013866) -> (0, 0, 4), [255] = (0.987053, 0.991438, 0.749504) -> (252, 253, 191).
  EXPECT_EQ(mapColor(ColorMap::Viridis, 0.0), (Rgb8{68, 1, 84}));
  EXPECT_EQ(mapColor(ColorMap::Viridis, 1.0), (Rgb8{253, 231, 37}));
  EXPECT_EQ(mapColor(ColorMap::Magma, 0.0), (Rgb8{0, 0, 4}));
  EXPECT_EQ(mapColor(ColorMap::Magma, 1.0), (Rgb8{252, 253, 191}));
  // Viridis' middle entry, _viridis_data[128] = (0.127568, 0.566949, 0.550556) -> (33, 145, 140).
  EXPECT_EQ(mapColor(ColorMap::Viridis, 128.0 / 256.0), (Rgb8{33, 145, 140}));
  // Out of range clamps; NaN is mid grey.
  EXPECT_EQ(mapColor(ColorMap::Viridis, -3.0), mapColor(ColorMap::Viridis, 0.0));
  EXPECT_EQ(mapColor(ColorMap::Magma, 7.0), mapColor(ColorMap::Magma, 1.0));
  EXPECT_EQ(mapColor(ColorMap::Diverging, std::nan("")), (Rgb8{128, 128, 128}));
}

TEST(ColorMaps, SequentialLightnessIncreases) {
  // Both are designed with monotone lightness (in CAM02-UCS); CIE L* of the 8-bit colours of the
  // 256 entries must not decrease by more than the rounding of 8 bits (0.25 L*), and rise overall
  // by far (viridis 16 -> 92, magma 0 -> 98).
  for (ColorMap m : {ColorMap::Viridis, ColorMap::Magma}) {
    double previous = -1.0;
    for (int k = 0; k < 256; ++k) {
      const double L = lightness(mapColor(m, (k + 0.5) / 256.0));
      EXPECT_GT(L, previous - 0.25) << colorMapName(m) << " " << k;
      previous = std::max(previous, L);
    }
    EXPECT_GT(lightness(mapColor(m, 1.0)) - lightness(mapColor(m, 0.0)), 70.0) << colorMapName(m);
  }
}

TEST(ColorMaps, DivergingIsWhiteInTheMiddleAndSymmetricInLightness) {
  EXPECT_EQ(mapColor(ColorMap::Diverging, 0.5), (Rgb8{255, 255, 255}));
  const Rgb8 red = mapColor(ColorMap::Diverging, 1.0), blue = mapColor(ColorMap::Diverging, 0.0);
  EXPECT_GT(red[0], red[1] + 100);
  EXPECT_GT(blue[2], blue[0] + 100);
  // L* falls linearly from 100 to 45 on both sides (8-bit rounding: ±0.5 L*).
  for (int k = 0; k <= 20; ++k) {
    const double s = k / 20.0;
    const double expected = 100.0 - 55.0 * s;
    EXPECT_NEAR(lightness(mapColor(ColorMap::Diverging, 0.5 + 0.5 * s)), expected, 0.5) << s;
    EXPECT_NEAR(lightness(mapColor(ColorMap::Diverging, 0.5 - 0.5 * s)), expected, 0.5) << s;
  }
}

TEST(FalseColor, MapsTheRangeAndNaN) {
  const std::vector<float> v{-1.0f, 0.0f, 1.0f, std::nanf(""), 5.0f, -5.0f};
  const auto rgb = falseColor(v, 3, 2, ColorMap::Diverging, -1.0, 1.0);
  ASSERT_EQ(rgb.size(), 18u);
  const auto at = [&](int p) { return Rgb8{rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]}; };
  EXPECT_EQ(at(0), mapColor(ColorMap::Diverging, 0.0));
  EXPECT_EQ(at(1), (Rgb8{255, 255, 255}));
  EXPECT_EQ(at(2), mapColor(ColorMap::Diverging, 1.0));
  EXPECT_EQ(at(3), (Rgb8{128, 128, 128}));
  EXPECT_EQ(at(4), at(2));  // saturates
  EXPECT_EQ(at(5), at(0));
  EXPECT_THROW(falseColor(v, 2, 2, ColorMap::Viridis, 0.0, 1.0), ParameterError);
  EXPECT_THROW(falseColor(v, 3, 2, ColorMap::Viridis, 1.0, 1.0), ParameterError);
  EXPECT_EQ(parseColorMap("magma"), ColorMap::Magma);
  EXPECT_THROW(parseColorMap("jet"), ParameterError);
}

TEST(ColorBar, ShowsTheMapAboveAndLabelsBelow) {
  const int w = 300, h = 40;
  const auto bar = colorBar(w, h, ColorMap::Viridis, 0.0, 0.5, 6);
  ASSERT_EQ(bar.size(), static_cast<size_t>(w * h * 3));
  const ColorBarLayout l = colorBarLayout(w, h, 0.0, 0.5, 6);
  ASSERT_GT(l.bar_height, 10);
  EXPECT_EQ(l.tick_x.front(), 0);
  EXPECT_EQ(l.tick_x.back(), w - 1);
  EXPECT_NEAR(l.tick_value[1], 0.1, 1e-12);
  const auto px = [&](int x, int y) {
    const size_t i = 3 * (static_cast<size_t>(y) * w + static_cast<size_t>(x));
    return Rgb8{bar[i], bar[i + 1], bar[i + 2]};
  };
  // The bar: column x is the colour of lo + (hi - lo)(x + ½)/w.
  for (int x : {0, 1, 77, 150, 299})
    for (int y : {0, l.bar_height - 1})
      EXPECT_EQ(px(x, y), mapColor(ColorMap::Viridis, (x + 0.5) / w)) << x;
  // Labels: dark text pixels below the bar near every tick, and none far from the ticks' labels
  // (the white gap between "0.1" at x = 60 and "0.2" at x = 120).
  const auto darkIn = [&](int x0, int x1) {
    int n = 0;
    for (int y = l.bar_height + 3; y < h; ++y)
      for (int x = std::max(0, x0); x < std::min(w, x1); ++x) n += px(x, y)[0] < 100 ? 1 : 0;
    return n;
  };
  for (int x : l.tick_x) EXPECT_GT(darkIn(x - 15, x + 15), 5) << x;
  EXPECT_EQ(darkIn(82, 98), 0);
}

TEST(ColorBar, WritesAPngThatReadsBack) {
  const int w = 120, h = 30;
  const auto bar = colorBar(w, h, ColorMap::Magma, -2.0, 2.0);
  const std::string path =
      (std::filesystem::temp_directory_path() / "translucent_test_colorbar.png").string();
  writePng8(path, w, h, bar);
  const RgbImage back = readRgb(path);
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  for (size_t i = 0; i < bar.size(); ++i) ASSERT_NEAR(back.rgb[i], bar[i] / 255.0f, 1e-6f) << i;
  std::filesystem::remove(path);
  EXPECT_THROW(colorBar(w, 10, ColorMap::Magma, -2.0, 2.0), ParameterError);
  EXPECT_THROW(colorBar(w, h, ColorMap::Magma, 2.0, -2.0), ParameterError);
}

}  // namespace
}  // namespace translucent::analysis
