// SPDX-License-Identifier: GPL-3.0-or-later
// .bssrdf models on the GPU against the C++ models they mirror: curves, energy radius, profile
// tables and the (Rd, ld) inversion of data/bssrdf/dipole.bssrdf vs bssrdf::model("dipole").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "gpu_test.h"
#include "translucent/optics/inversion.h"
#include "translucent/optics/presets.h"

namespace translucent::gpu {
namespace {

using testing::GpuTest;

class BssrdfProfiles : public GpuTest {};

// profile's code path: GPU curves of dipole.bssrdf beside profileCurves() of the C++ dipole.
// dipole.bssrdf is written for single precision (~1e-6 relative of the double model where exp()
// does not underflow); 1e-5 leaves room for float radii and luminance sums.
TEST_F(BssrdfProfiles, CurvesMatchCppDipole) {
  auto e = BssrdfEvaluator::builtin("dipole");
  const Medium medium = preset("Skin1").medium();
  const std::vector<analysis::Channel> channels{analysis::Channel::Red,
                                                analysis::Channel::Luminance};
  analysis::CurveOptions opts;
  opts.r_max = 5.0;
  opts.points = 100;
  const auto grid = analysis::radiusGrid(*opts.r_max, opts.points);
  const auto gpu = bssrdfCurves(e, "dipole-file", medium, channels, grid, false);
  const auto cpp = analysis::profileCurves({"dipole"}, medium, channels, opts);
  ASSERT_EQ(gpu.size(), cpp.size());
  for (size_t k = 0; k < gpu.size(); ++k) {
    EXPECT_EQ(gpu[k].model, "dipole-file");
    EXPECT_EQ(gpu[k].channel, cpp[k].channel);
    for (size_t i = 0; i < grid.size(); ++i)
      EXPECT_NEAR(gpu[k].value[i], cpp[k].value[i], 1e-5 * cpp[k].value[i]) << "r=" << grid[i];
  }
}

// The sphere integration's path for plug-ins (`integrate sphere --model F.bssrdf`): the file's
// GPU values tabulated as a model for one medium (at scale 10, so the mm conversion is exercised)
// have the C++ dipole's R(r) between the table's radii, Rd and 95% radius, to the table's
// interpolation (4000 log-spaced radii) and float precision.
TEST_F(BssrdfProfiles, TabulatedModelOfAFileIsItsProfile) {
  auto e = BssrdfEvaluator::builtin("dipole");
  Medium medium = preset("Skin1").medium();
  medium.scale = 10.0;
  const auto table = bssrdfTabulatedModel(e, medium, "dipole.bssrdf");
  EXPECT_TRUE(table->tabulated());
  const auto a = bssrdf::profiles(bssrdf::model("dipole"), medium);
  const auto b = bssrdf::profiles(*table, medium);
  for (size_t c = 0; c < 3; ++c) {
    SCOPED_TRACE(c);
    for (double r : {0.0013, 0.01, 0.0537, 0.2, 0.61})
      EXPECT_NEAR(b[c]->R(r) / a[c]->R(r), 1.0, 2e-5) << "r " << r;
    EXPECT_NEAR(b[c]->Rd() / a[c]->Rd(), 1.0, 1e-5);
    EXPECT_NEAR(b[c]->radiusForFraction(0.95) / a[c]->radiusForFraction(0.95), 1.0, 1e-5);
  }
}

// Tables from GPU values against the C++ dipole: r_max (the 99.9% radius, found from GPU values)
// and Rd within 1e-4 / 1e-5 relative (float values integrated in double); each entry above 1e-6
// of the peak within 1e-4 of the C++ R at the table's own radius (tabulate() at a radius 1e-5
// away would differ by up to σtr r · 1e-5 ≈ 1e-4 at the far end, so entries are compared at the
// same radii); cdf within 1e-5 of the C++ cumulative.
TEST_F(BssrdfProfiles, TableMatchesCppTabulate) {
  auto e = BssrdfEvaluator::builtin("dipole");
  const auto& dipole = bssrdf::model("dipole");
  for (const char* name : {"Marble", "Skin1", "Ketchup"}) {
    const Medium medium = preset(name).medium();
    for (int c = 0; c < 3; ++c) {
      SCOPED_TRACE(std::string(name) + " channel " + std::to_string(c));
      const auto cppProfile = dipole.profile(medium.channel(c));
      const auto ref = bssrdf::tabulate(*cppProfile, 256);
      const auto t = tabulateBssrdf(e, medium, c, 256);
      ASSERT_EQ(t.size(), 256u);
      EXPECT_NEAR(t.r_max, ref.r_max, 1e-4 * ref.r_max);
      EXPECT_NEAR(t.rd, ref.rd, 1e-5 * ref.rd);
      const double peak = *std::max_element(ref.R.begin(), ref.R.end());
      double cumulative = 0.0;
      for (size_t i = 0; i < t.size(); ++i) {
        const double r = t.radius(i), want = cppProfile->R(r);
        if (want > 1e-6 * peak) {
          EXPECT_NEAR(t.R[i], want, 1e-4 * want) << "i=" << i;
          EXPECT_NEAR(t.r_times_R[i], r * want, 1e-4 * r * want + 1e-30) << "i=" << i;
        }
        if (i > 0) cumulative += bssrdf::integratePanel(*cppProfile, t.radius(i - 1), r);
        const double cdf = std::min(1.0, cumulative / cppProfile->Rd());
        EXPECT_NEAR(t.cdf[i], cdf, 1e-5) << "i=" << i;
      }
    }
  }
}

// Inversion through the file's DiffuseReflectance kernel vs the C++ bisection on the dipole's
// closed-form Rd(α'). Tolerance 1e-6 on α': the kernel works in float, so Rd carries a relative
// error ε of a few 1e-7; α' then moves by ε Rd / (dRd/dα') <= ε α' because d ln Rd / d ln α' >= 1
// for the dipole (Rd is α' times a factor increasing in α').
TEST_F(BssrdfProfiles, InversionMatchesCppDipole) {
  auto e = BssrdfEvaluator::builtin("dipole");
  const auto& dipole = bssrdf::model("dipole");
  for (double eta : {1.0, 1.3, 1.5}) {
    for (double rd : {0.01, 0.1, 0.3, 0.6, 0.8}) {
      const Rgb rdv{rd, rd * 0.5, rd * 0.9}, ld{1.0, 2.0, 0.5};
      const Medium gpu = invertBssrdfMedium(e, rdv, ld, eta);
      const Medium cpp =
          invertMedium([&](double a) { return dipole.totalReflectance(a, eta); }, rdv, ld, eta);
      for (int c = 0; c < 3; ++c) {
        const double ag = gpu.channel(c).reducedAlbedo(), ac = cpp.channel(c).reducedAlbedo();
        EXPECT_NEAR(ag, ac, 1e-6) << "eta=" << eta << " rd=" << rdv[size_t(c)];
      }
      EXPECT_EQ(gpu.eta, eta);
    }
  }
}

TEST_F(BssrdfProfiles, UnreachableRdNamesTheRange) {
  auto e = BssrdfEvaluator::builtin("dipole");
  try {
    invertBssrdfMedium(e, {0.5, 1.5, 0.5}, {1.0, 1.0, 1.0}, 1.3);
    FAIL() << "expected ParameterError";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("Rd (green channel) is 1.5: not reachable"),
              std::string::npos)
        << err.what();
  }
  EXPECT_THROW(invertBssrdfMedium(e, {0.5, 0.5, 0.5}, {1.0, 0.0, 1.0}, 1.3), ParameterError);
}

TEST_F(BssrdfProfiles, NoDiffuseReflectanceSectionIsAClearError) {
  testing::TempDir dir;
  const auto path = dir.write("plain.bssrdf",
                              "analytic radial no_wi no_wo\n"
                              "::begin shader\n"
                              "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                              "  return vec3(exp(-length(Xo - Xi)));\n"
                              "}\n"
                              "::end shader\n");
  BssrdfEvaluator e(path);
  try {
    invertBssrdfMedium(e, {0.5, 0.5, 0.5}, {1.0, 1.0, 1.0}, 1.3);
    FAIL() << "expected ParameterError";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("plain.bssrdf: no diffuseReflectance section"),
              std::string::npos)
        << err.what();
  }
  // R(r) = e^-r: Rd = 2π ∫ r e^-r dr = 2π, whatever the medium.
  const auto energy = bssrdfRadiusForFraction(e, preset("Marble").medium(), 0.5);
  EXPECT_NEAR(energy.rd[0], 2.0 * M_PI, 1e-5 * 2.0 * M_PI);
  // Half of Γ(2): (1 + r) e^-r = 1/2 at r = 1.678346990...
  EXPECT_NEAR(energy.radius[1], 1.6783469900166608, 1e-5);
}

// A radial plug-in `file` whose Bssrdf() returns `value` (GLSL, with r = |Xo - Xi|) is refused
// by bssrdfRadiusForFraction with a message naming the file and holding `says`.
void expectRefused(const std::string& file, const std::string& value, const std::string& says) {
  testing::TempDir dir;
  const auto path = dir.write(file, "analytic radial no_wi no_wo\n"
                                    "::begin shader\n"
                                    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                                    "  float r = length(Xo - Xi);\n"
                                    "  return " + value + ";\n"
                                    "}\n"
                                    "::end shader\n");
  BssrdfEvaluator e(path);
  try {
    bssrdfRadiusForFraction(e, preset("Marble").medium(), 0.5);
    FAIL() << "expected ParameterError";
  } catch (const ParameterError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find(file + ": Bssrdf() returned "), std::string::npos) << what;
    EXPECT_NE(what.find(says), std::string::npos) << what;
  }
}

// A shader that returns NaN only away from the origin: the error names the file and says NaN,
// instead of "not integrable ... needs absorption".
TEST_F(BssrdfProfiles, NanProfileIsNamed) {
  expectRefused("nan.bssrdf", "r > 1.0 ? vec3(uintBitsToFloat(0x7fc00000u)) : vec3(exp(-r))",
                "NaN or infinite values in the red channel");
}

// A shader that is finite on the x axis, where the profile is sampled, and NaN elsewhere (an
// atan2 of the azimuth gone wrong): it used to render without a word; now named as on the axis.
TEST_F(BssrdfProfiles, NanOffTheAxisIsNamed) {
  expectRefused("offaxis.bssrdf",
                "abs(Xo.y - Xi.y) > 1e-6 * r ? vec3(uintBitsToFloat(0xff800000u)) : vec3(exp(-r))",
                "samples off the x axis");
}

// A valid profile that decays more slowly than the diffusion models (e^(-r/100) in a medium
// whose 40/σtr is ~340): its integral used to stop at 40/σtr with a tail above the bound and
// the profile was refused as "not integrable ... needs absorption"; the range now grows.
TEST_F(BssrdfProfiles, SlowlyDecayingProfileIsIntegrated) {
  testing::TempDir dir;
  const auto path = dir.write("slow.bssrdf",
                              "analytic radial no_wi no_wo\n"
                              "::begin shader\n"
                              "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                              "  return vec3(exp(-length(Xo - Xi) / 100.0));\n"
                              "}\n"
                              "::end shader\n");
  BssrdfEvaluator e(path);
  const auto energy = bssrdfRadiusForFraction(e, preset("Marble").medium(), 0.5);
  // 2π ∫ r e^(-r/100) dr = 2π 10^4; half of it within 100 · 1.678346990...
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(energy.rd[c], 2.0 * M_PI * 1e4, 1e-4 * 2.0 * M_PI * 1e4) << c;
    EXPECT_NEAR(energy.radius[c], 167.83469900166608, 1e-3) << c;
  }
}

// A shader that clamps r at the source (1/max(r, 1e-6)) has a finite but huge R(0): the table
// holds R a quarter step out there, as for an infinite R(0), not 1e6 (a speckled render).
TEST_F(BssrdfProfiles, ClampedSingularityIsTabulatedAsOne) {
  testing::TempDir dir;
  const auto path = dir.write("clamped.bssrdf",
                              "analytic radial no_wi no_wo\n"
                              "::begin shader\n"
                              "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                              "  float r = length(Xo - Xi);\n"
                              "  return vec3(exp(-r) / max(r, 1e-6));\n"
                              "}\n"
                              "::end shader\n");
  BssrdfEvaluator e(path);
  const auto t = tabulateBssrdf(e, preset("Marble").medium(), 0, 256);
  ASSERT_GE(t.size(), 2u);
  // 1/r: R(Δr/4) = 4 R(Δr); r·R ~ e^-r, about 1 near the source.
  EXPECT_LT(t.R[0], 5.0f * t.R[1]);
  EXPECT_GT(t.R[0], 3.0f * t.R[1]);
  EXPECT_NEAR(t.r_times_R[0], t.r_times_R[1], 0.1f * t.r_times_R[1]);
}

}  // namespace
}  // namespace translucent::gpu
