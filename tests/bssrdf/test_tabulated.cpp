// SPDX-License-Identifier: GPL-3.0-or-later
// Tabulated profiles (bssrdf/tabulated.h): a dense table of an analytic model is that model
// (R between samples, Rd, the 95% radius and the sampler, at two scales), both file formats load,
// and bad files are refused naming file and line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <fmt/format.h>

#include "translucent/bssrdf/profile_curves.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/bssrdf/tabulated.h"
#include "translucent/optics/presets.h"

namespace translucent::bssrdf {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("translucent_tab_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The analytic model's R(r) of each channel of `medium` (scale 1: mm) on a log grid of radii.
ProfileSamples tableOf(const Model& m, const Medium& medium, int n) {
  ProfileSamples t;
  const auto ps = profiles(m, medium);
  const double rMax = ps[0]->radiusForFraction(0.99999);
  for (int i = 0; i < n; ++i) {
    const double r = 1e-4 * std::pow(rMax / 1e-4, double(i) / (n - 1));
    t.r_mm.push_back(r);
    for (int c = 0; c < 3; ++c) t.R_mm[size_t(c)].push_back(ps[size_t(c)]->R(r));
  }
  t.eta = medium.eta;
  return t;
}

std::string messageOf(const std::string& path) {
  try {
    (void)readProfileSamples(path);
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Tabulated, DenseTableOfTheDipoleIsTheDipole) {
  Medium medium = preset("Skin1").medium();
  const Model& dipole = model("dipole");
  const std::string path = tempPath("dipole.csv");
  writeProfileSamples(path, tableOf(dipole, medium, 2000), {"dense table of the dipole, Skin1"});
  const Model& tab = model(path);
  EXPECT_TRUE(tab.tabulated());
  EXPECT_FALSE(dipole.tabulated());
  EXPECT_EQ(&tab, &model(path)) << "loaded once per path";
  for (double scale : {1.0, 10.0}) {  // 10: one scene unit is a centimetre
    medium.scale = scale;
    const auto a = profiles(dipole, medium), b = profiles(tab, medium);
    for (size_t c = 0; c < 3; ++c) {
      SCOPED_TRACE(::testing::Message() << "scale " << scale << " channel " << c);
      // 2000 log-spaced samples: the log-log interpolant is within ~1e-4 of the dipole.
      for (double r : {0.003, 0.0171, 0.1, 0.377, 1.0, 2.9}) {
        const double rs = r / scale;
        EXPECT_NEAR(b[c]->R(rs) / a[c]->R(rs), 1.0, 1e-3) << "r " << r << " mm";
      }
      EXPECT_NEAR(b[c]->Rd() / a[c]->Rd(), 1.0, 1e-3);
      EXPECT_NEAR(b[c]->radiusForFraction(0.95) / a[c]->radiusForFraction(0.95), 1.0, 1e-3);
      // The sampler inverts its own cumulative: the median sample holds half of Rd.
      const double median = b[c]->sample(0.5).r;
      EXPECT_NEAR(median / b[c]->radiusForFraction(0.5), 1.0, 1e-6);
      EXPECT_NEAR(b[c]->pdf(median), 2.0 * std::numbers::pi * median * b[c]->R(median) / b[c]->Rd(), 1e-9 * b[c]->pdf(median));
    }
  }
  std::filesystem::remove(path);
}

TEST(Tabulated, ReadsTheCurvesCsvOfProfileAndConvertsUnits) {
  const Medium medium = preset("Marble").medium();
  const Model& dipole = model("better-dipole");
  const ProfileSamples t = tableOf(dipole, medium, 400);
  // The CSV of `translucent profile --channel all --reference`: r in cm here (# units: cm), so
  // R is per cm² (100 × per mm²).
  std::string text = "# units: cm\nmodel,channel,r,value,stderr\n";
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < t.r_mm.size(); ++i)
      text += fmt::format("reference,{},{:.17g},{:.17g},0.1\n", "rgb"[c], t.r_mm[i] / 10.0,
                          t.R_mm[size_t(c)][i] * 100.0);
  text += "better-dipole,r,0.1,5,\n";  // another model's rows are ignored
  const std::string path = tempPath("curves.csv");
  writeText(path, text);
  const ProfileSamples back = readProfileSamples(path);
  ASSERT_EQ(back.r_mm.size(), t.r_mm.size());
  for (size_t i = 0; i < t.r_mm.size(); i += 37) {
    EXPECT_NEAR(back.r_mm[i] / t.r_mm[i], 1.0, 1e-12);
    for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(back.R_mm[c][i] / t.R_mm[c][i], 1.0, 1e-12);
  }
  const auto a = profiles(dipole, medium), b = profiles(model(path), medium);
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(b[c]->Rd() / a[c]->Rd(), 1.0, 3e-3);
  std::filesystem::remove(path);
}

TEST(Tabulated, NeedsAChannelAndHasNoRdOfAlbedo) {
  const std::string path = tempPath("small.csv");
  writeText(path, "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n1,0.1,0.2,0.3\n2,0.01,0.02,0.03\n");
  const Model& tab = model(path);
  EXPECT_THROW((void)tab.profile(ScalarMedium{0.1, 1.0, 0.0, 1.3}), ParameterError);
  EXPECT_THROW((void)tab.totalReflectance(0.9, 1.3), ParameterError);
  // Below the first sample R is held; beyond the last it decays with the fitted slope.
  const auto& t = dynamic_cast<const TabulatedModel&>(tab);
  EXPECT_DOUBLE_EQ(t.Rmm(1, 0.0), 2.0);
  EXPECT_NEAR(t.Rmm(0, 3.0), 0.01 * std::exp(std::log(0.1) * 1.0), 1e-12);
  EXPECT_NEAR(t.Rmm(2, std::sqrt(0.1 * 1.0)), std::sqrt(3.0 * 0.3), 1e-12) << "log-log midpoint";
  std::filesystem::remove(path);
}

TEST(Tabulated, BadFilesNameFileAndLine) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"r,R_r,R_g,R_b\n0.1,1,2,3\n1,1,1,1\n", "no '# units: mm' line"},
      {"# units: furlong\nr,R_r,R_g,R_b\n", ":1: units 'furlong'"},
      {"# units: mm\nradius,a,b,c\n", ":2: header 'radius,a,b,c'"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.05,1,2,3\n", ":4: r 0.05 after 0.1"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.2,1,x,3\n", ":4: R 'x'"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.2,1,-2,3\n", ":4: R (green channel) -2"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,2\n", ":3: 3 values: expected 4"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n", "1 samples: expected at least 2"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,0,2,3\n0.2,0,2,3\n", "red channel is 0 everywhere"},
      {"model,channel,r,value\na,r,0.1,1\nb,r,0.1,1\n", "none named 'reference'"},
      {"model,channel,r,value\nreference,r,0.1,1\nreference,r,0.2,1\n", "no 'g' channel rows"},
      {"", "no header"},
  };
  const std::string path = tempPath("bad.csv");
  for (const auto& c : cases) {
    writeText(path, c.text);
    const std::string msg = messageOf(path);
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << msg;
  }
  std::filesystem::remove(path);
  EXPECT_NE(messageOf(path).find("cannot read"), std::string::npos);
  try {
    (void)model("no-such-model");
    ADD_FAILURE();
  } catch (const UnknownModelError& e) {
    EXPECT_NE(std::string(e.what()).find(".csv"), std::string::npos) << e.what();
  }
}

// Values no renderer can use (R = 1e300 gave non-finite pixels; R = 1e-320 or radii up to 5e300
// an all-zero image) are refused with the file and line; a NUL byte in a cell is shown, not the
// end of the message.
TEST(Tabulated, RefusesValuesOutOfRangeAndShowsControlBytes) {
  struct Case {
    std::string text;
    const char* expected;
  };
  const Case cases[] = {
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.2,1e300,1,1\n",
       ":4: R (red channel) 1e+300 (1e+300 per mm²): expected at most 1e+30 per mm²"},
      // A channel whose peak is subnormal: "the green channel's largest R is 1e-320", or
      // ":3: R '1e-320'" where from_chars reports the underflow.
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,1e-320,1\n0.2,1,1e-321,1\n", "1e-320"},
      {"# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n5e300,1,1,1\n",
       ":4: r 5e+300 (5e+300 mm): expected at most 1000000 mm"},
      {"# units: m\nr,R_r,R_g,R_b\n0.1,1,1,1\n2000,1,1,1\n", ":4: r 2000 (2000000 mm)"},
      {std::string("# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.2,1,x\0y,1\n", 48),
       ":4: R 'x\\x00y': expected a finite number"},
  };
  const std::string path = tempPath("range.csv");
  for (const auto& c : cases) {
    writeText(path, c.text);
    const std::string msg = messageOf(path);
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << msg;
    EXPECT_NE(msg, "(no error)");
  }
  // A tail far below the peak range is an ordinary exponential decay, not an error.
  writeText(path, "# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n10,1e-35,1e-40,1e-300\n");
  EXPECT_EQ(messageOf(path), "(no error)");
  std::filesystem::remove(path);
}

// Between a subnormal sample and an ordinary one the ratio of the values overflows: R(r) was
// v0 · (v1 / v0)^t = inf there, and Rd inf (fuzz_tabulated; tests/fuzz/corpus/tabulated/
// crash_subnormal_next_to_normal.csv). Interpolated in logarithms it stays between the two.
TEST(Tabulated, InterpolationBetweenSubnormalAndOrdinaryValuesIsFinite) {
  const std::string path = tempPath("subnormal.csv");
  writeText(path, "# units: mm\nr,R_r,R_g,R_b\n0.1,1,1e-320,1\n0.2,1,13e-2,11\n");
  const TabulatedModel model(readProfileSamples(path));
  std::filesystem::remove(path);
  for (double r : {0.1, 0.10001, 0.15, 0.19999, 0.2}) {
    const double R = model.Rmm(1, r);
    EXPECT_TRUE(std::isfinite(R)) << r;
    EXPECT_GE(R, 0.0) << r;
    EXPECT_LE(R, 0.13 * (1 + 1e-12)) << r;
  }
  EXPECT_NEAR(model.Rmm(1, 0.2 - 1e-12), 0.13, 1e-9);
  ScalarMedium m;
  m.channel = 1;
  const auto p = model.profile(m);
  EXPECT_TRUE(std::isfinite(p->Rd()) && p->Rd() > 0.0) << p->Rd();
}

// A channel that is 0 but for a sliver far out integrated to Rd = 0, which sampling divides by
// (fuzz_tabulated; corpus/tabulated/crash_zero_but_a_far_sliver.csv): refused with the radii.
TEST(Tabulated, ChannelTheQuadratureSeesAsZeroIsRefused) {
  const std::string path = tempPath("sliver.csv");
  writeText(path, "# Units: M\nR,r_r,r_g,r_b\n1.0012,0,6,7\n1.002,4,6,2\n");
  const std::string msg = messageOf(path);
  std::filesystem::remove(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("red channel integrates to Rd = 0"), std::string::npos) << msg;
  EXPECT_NE(msg.find("between r = 1001.2 and 1002 mm"), std::string::npos) << msg;
}

}  // namespace
}  // namespace translucent::bssrdf
