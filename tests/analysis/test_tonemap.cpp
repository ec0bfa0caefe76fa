// SPDX-License-Identifier: GPL-3.0-or-later
// Display tone maps (io/image_io.h): the clamp operator and Reinhard's global operator
// s / (1 + s) (Reinhard, Stark, Shirley & Ferwerda 2002, Eq. 3) scaled by the rendered pixels'
// average as Chang 2007 applies it, against their closed forms; the PNG writer's use of them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "translucent/io/image_io.h"

namespace translucent::analysis {
namespace {

TEST(ToneMap, ClampScalesClampsAndAppliesTheGamma) {
  const ToneMap tm{1.0, 2.0};
  EXPECT_DOUBLE_EQ(toneMapValue(0.125, tm), std::sqrt(0.25));
  EXPECT_DOUBLE_EQ(toneMapValue(3.0, tm), 1.0);
  EXPECT_EQ(toneMapValue(-1.0, tm), 0.0);
  EXPECT_EQ(toneMapValue(std::numeric_limits<double>::quiet_NaN(), tm), 0.0);
}

TEST(ToneMap, ReinhardMapsTheAverageToKeyOverOnePlusKey) {
  ToneMap tm{0.0, 1.0, ToneOperator::Reinhard, 1.0, 0.04};
  EXPECT_DOUBLE_EQ(toneMapValue(0.04, tm), 0.5);  // s = 1
  tm.key = 0.18;
  EXPECT_NEAR(toneMapValue(0.04, tm), 0.18 / 1.18, 1e-15);
  // s = key v 2^exposure / average, then s / (1 + s), then the gamma.
  tm = {2.0, 2.2, ToneOperator::Reinhard, 0.5, 0.1};
  const double s = 0.5 * 0.3 * 4.0 / 0.1;
  EXPECT_NEAR(toneMapValue(0.3, tm), std::pow(s / (1.0 + s), 1.0 / 2.2), 1e-15);
  // Monotonic, below white however bright; black and NaN stay black.
  double last = 0.0;
  for (double v = 1e-6; v < 1e9; v *= 3.0) {
    const double d = toneMapValue(v, tm);
    EXPECT_GT(d, last);
    EXPECT_LT(d, 1.0);
    last = d;
  }
  EXPECT_EQ(toneMapValue(0.0, tm), 0.0);
  EXPECT_EQ(toneMapValue(std::numeric_limits<double>::quiet_NaN(), tm), 0.0);
}

TEST(ToneMap, TheAverageIsOverTheRenderedPixelsOnly) {
  // Two rendered pixels, two empty ones (the background) and one NaN pixel.
  const std::vector<float> rgb{0.1f, 0.2f, 0.3f, 0.0f, 0.0f, 0.0f, 0.5f, 0.0f, 0.1f,
                               0.0f, 0.0f, 0.0f, std::nanf(""), 0.0f, 0.0f};
  const ToneMap tm = withImageAverage({}, rgb);
  EXPECT_NEAR(tm.average, (0.1 + 0.2 + 0.3 + 0.5 + 0.0 + 0.1) / 6.0, 1e-7);
  EXPECT_EQ(withImageAverage({}, std::vector<float>(12, 0.0f)).average, 0.0);
}

TEST(ToneMap, ParsesTheOperatorsAndNamesThemInErrors) {
  EXPECT_EQ(parseToneOperator("clamp", "x"), ToneOperator::Clamp);
  EXPECT_EQ(parseToneOperator("reinhard", "x"), ToneOperator::Reinhard);
  try {
    parseToneOperator("aces", "--tonemap");
    FAIL();
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("--tonemap 'aces'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("reinhard"), std::string::npos) << e.what();
  }
}

TEST(ToneMap, PngWriterTakesTheImagesAverageForReinhard) {
  // The writer sets the average from the image: a pixel at the average of the rendered pixels
  // is written as round(255 · 0.5) at gamma 1 and key 1.
  const auto path = std::filesystem::temp_directory_path() /
                    ("translucent-tonemap-" + std::to_string(::getpid()) + ".png");
  const std::vector<float> rgb{0.2f, 0.2f, 0.2f, 0.6f, 0.6f, 0.6f, 0.0f, 0.0f, 0.0f, 1.2f, 1.2f, 1.2f};
  writePng(path.string(), 4, 1, rgb, ToneMap{0.0, 1.0, ToneOperator::Reinhard, 1.0, 0.0});
  const RgbImage img = readRgb(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(img.width, 4);
  // average 2/3: 0.2 -> 0.3/1.3, 0.6 -> 0.9/1.9, 1.2 -> 1.8/2.8; 8-bit values read back as v/255.
  const double expected[4] = {0.3 / 1.3, 0.9 / 1.9, 0.0, 1.8 / 2.8};
  for (int p = 0; p < 4; ++p)
    EXPECT_NEAR(double(img.rgb[size_t(3 * p)]), std::round(255.0 * expected[p]) / 255.0, 1e-6) << p;
  EXPECT_THROW(writePng(path.string(), 4, 1, rgb, ToneMap{0.0, 1.0, ToneOperator::Reinhard, 0.0, 0.0}),
               ImageError);
}

}  // namespace
}  // namespace translucent::analysis
