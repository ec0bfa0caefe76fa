// SPDX-License-Identifier: GPL-3.0-or-later
// GPU evaluation of .bssrdf models against the C++ models, and GLSL errors mapped back to the
// .bssrdf file.
#include <gtest/gtest.h>

#include <gmock/gmock.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <glm/geometric.hpp>

#include <fmt/format.h>

#include "translucent/bssrdf/registry.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "gpu_test.h"
#include "translucent/optics/presets.h"
#include "seed_listing.h"

namespace translucent::gpu {
namespace {

using ::testing::HasSubstr;
using testing::GpuTest;
using testing::TempDir;

struct Agreement {
  double worst = 0.0;  // largest |gpu - cpu| / cpu
  std::string where;   // where it occurred
  size_t compared = 0, skipped = 0;
};

// Relative difference |gpu - cpu| / cpu of a .bssrdf model against a C++ model on
// r in [r0 * 10 ld, 10 ld] (ld = 1/sigma_tr of each channel), for every preset and channel.
// Channels without absorption (Spectralon) have ld = inf and are compared on [.., 10 * 1000 l'].
// Values below `floor` are skipped: single precision cannot represent them (a normal float is at
// least 1.2e-38, and GPUs flush smaller results to zero).
Agreement compareProfiles(BssrdfEvaluator& gpu, const bssrdf::Model& cpu, double r0,
                          double floor = 0.0) {
  constexpr int kRadii = 97;
  Agreement a;
  for (const Preset& preset : presets()) {
    const Medium medium = preset.medium();
    gpu.setMedium(medium);
    for (int c = 0; c < 3; ++c) {
      const ScalarMedium ch = medium.channel(c);
      const auto profile = cpu.profile(ch);
      const double ld =
          ch.sigma_a > 0.0 ? ch.diffuseMeanFreePath() : 1000.0 * ch.reducedMeanFreePath();
      std::vector<float> radii(kRadii);
      for (int k = 0; k < kRadii; ++k)
        radii[static_cast<size_t>(k)] =
            static_cast<float>(10.0 * ld * (r0 + (1.0 - r0) * k / (kRadii - 1.0)));
      const auto values = gpu.profile(radii);
      for (int k = 0; k < kRadii; ++k) {
        // Compare at the radius the GPU saw (the float-rounded one).
        const double r = radii[static_cast<size_t>(k)];
        const double expected = profile->R(r);
        const double got = values[static_cast<size_t>(k)][static_cast<size_t>(c)];
        if (expected < floor) {
          ++a.skipped;
          continue;
        }
        ++a.compared;
        const double rel = std::abs(got - expected) / expected;
        if (!(rel <= a.worst)) {
          a.worst = std::isnan(rel) ? std::numeric_limits<double>::infinity() : rel;
          a.where = fmt::format("{} {} r = {} ({} ld): gpu {} cpu {}", preset.name,
                                kChannelNames[c], r, r / ld, got, expected);
        }
      }
    }
  }
  return a;
}

TEST_F(GpuTest, DipoleBssrdfMatchesTheCppDipoleForEveryPreset) {
  auto gpu = BssrdfEvaluator::builtin("dipole");
  EXPECT_TRUE(gpu.file().attributes.radial);
  const Agreement a = compareProfiles(gpu, bssrdf::model("dipole"), 0.0);
  EXPECT_LE(a.worst, 1e-4) << "worst at " << a.where;
  EXPECT_EQ(a.skipped, 0u);
  std::printf("dipole.bssrdf vs C++: worst relative difference %.3g at %s\n", a.worst,
              a.where.c_str());
}

TEST_F(GpuTest, NormalizedDiffusionFitBssrdfMatchesTheCppModelForEveryPreset) {
  // R(0) is infinite (1/r singularity): start at 0.01 ld. Far out, e^(-s r/3ld) with s up to 24
  // leaves the float range; those points are skipped (the test checks that most are compared).
  auto gpu = BssrdfEvaluator::builtin("normalized-diffusion-fit");
  const Agreement a = compareProfiles(gpu, bssrdf::model("normalized-diffusion-fit"), 1e-3, 1e-30);
  EXPECT_LE(a.worst, 1e-4) << "worst at " << a.where;
  EXPECT_GT(a.compared, 3 * a.skipped);
  std::printf(
      "normalized-diffusion-fit.bssrdf vs C++: worst relative difference %.3g at %s "
      "(%zu compared, %zu below 1e-30 skipped)\n",
      a.worst, a.where.c_str(), a.compared, a.skipped);
}

TEST_F(GpuTest, BetterDipoleBssrdfMatchesTheCppModelForEveryPreset) {
  auto gpu = BssrdfEvaluator::builtin("better-dipole");
  const Agreement a = compareProfiles(gpu, bssrdf::model("better-dipole"), 0.0);
  EXPECT_LE(a.worst, 1e-4) << "worst at " << a.where;
  EXPECT_EQ(a.skipped, 0u);
  std::printf("better-dipole.bssrdf vs C++: worst relative difference %.3g at %s\n", a.worst,
              a.where.c_str());
}

// The directional file's profile kernel (normal incidence on a plane) is the C++ model's radial
// restriction, on [0, r_99.9] (the radius holding 99.9% of Rd) of every preset and channel. Not
// beyond: far out the real and image sources cancel to a few parts in 10^4 and single precision
// keeps no digit of the difference (the radial files avoid that with a cancellation-free form,
// which the directional kernel, with its direction-dependent distances, does not have).
TEST_F(GpuTest, DirectionalDipoleBssrdfProfileMatchesTheCppModelForEveryPreset) {
  auto gpu = BssrdfEvaluator::builtin("directional-dipole");
  EXPECT_FALSE(gpu.file().attributes.radial);
  EXPECT_TRUE(gpu.file().attributes.no_wo);
  double worst = 0.0;
  std::string where;
  for (const Preset& preset : presets()) {
    const Medium medium = preset.medium();
    gpu.setMedium(medium);
    for (int c = 0; c < 3; ++c) {
      const auto profile = bssrdf::model("directional-dipole").profile(medium.channel(c));
      const double rMax = profile->radiusForFraction(0.999);
      std::vector<float> radii(97);
      for (size_t k = 0; k < radii.size(); ++k) radii[k] = static_cast<float>(rMax * k / 96.0);
      const auto values = gpu.profile(radii);
      for (size_t k = 0; k < radii.size(); ++k) {
        const double r = radii[k];
        const double expected = profile->R(r);
        const double got = values[k][static_cast<size_t>(c)];
        const double rel = std::abs(got - expected) / expected;
        if (!(rel <= worst)) {
          worst = std::isnan(rel) ? std::numeric_limits<double>::infinity() : rel;
          where = fmt::format("{} {} r = {} ({} r_99.9)", preset.name, kChannelNames[c], r,
                              r / rMax);
        }
      }
    }
  }
  EXPECT_LE(worst, 1e-4) << "worst at " << where;
  std::printf("directional-dipole.bssrdf profile vs C++: worst relative difference %.3g at %s\n",
              worst, where.c_str());
}

// The directional file at arbitrary geometry (points on spheres of a few mean free paths, light
// from every direction above x_i, both sides of the sphere) against the C++ kernel, every preset
// and channel: relative difference at most 1e-4 wherever the kernel is above 1e-6 of its largest
// value in the set (below that single precision loses the real-minus-image difference).
TEST_F(GpuTest, DirectionalDipoleBssrdfMatchesTheCppKernelAtObliqueIncidence) {
  auto gpu = BssrdfEvaluator::builtin("directional-dipole");
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto unit = [&] {
    return glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
  };
  double worst = 0.0;
  std::string where;
  size_t compared = 0, zero = 0;
  for (const Preset& preset : presets()) {
    const Medium medium = preset.medium();
    gpu.setMedium(medium);
    // Geometry in units of the green channel's l'; the same queries for the three channels.
    const double l = medium.channel(1).reducedMeanFreePath();
    std::vector<BssrdfQuery> queries;
    std::vector<std::array<glm::dvec3, 5>> exact;  // x_i, n_i, w_i, x_o, n_o in double
    for (int k = 0; k < 400; ++k) {
      const double R = l * (2.0 + 18.0 * uniform(rng));
      const glm::dvec3 n_i = unit();
      // x_o within a few l' of x_i (also far sometimes), on the same sphere.
      const glm::dvec3 n_o = glm::normalize(n_i + (k % 4 == 0 ? 2.0 : 0.3) * unit());
      glm::dvec3 w = unit();
      if (glm::dot(w, n_i) < 0.0) w = -w;
      // Round the inputs to float first, so that both sides see the same geometry.
      const glm::vec3 xi(R * n_i), ni(n_i), wi(w), xo(R * n_o), no(n_o);
      queries.push_back({xi, ni, wi, xo, no, no});
      exact.push_back({glm::dvec3(xi), glm::dvec3(ni), glm::dvec3(wi), glm::dvec3(xo), glm::dvec3(no)});
    }
    const auto values = gpu.evaluate(queries);
    for (int c = 0; c < 3; ++c) {
      const auto kernel = bssrdf::model("directional-dipole").directional(medium.channel(c));
      std::vector<double> cpu(queries.size());
      double peak = 0.0;
      for (size_t q = 0; q < queries.size(); ++q) {
        const auto& e = exact[q];
        cpu[q] = kernel->R(e[0], e[1], e[2], e[3], e[4]);
        peak = std::max(peak, cpu[q]);
      }
      for (size_t q = 0; q < queries.size(); ++q) {
        const double got = values[q][static_cast<size_t>(c)];
        if (cpu[q] < 1e-6 * peak) {
          EXPECT_LE(std::abs(got), 1e-6 * peak) << preset.name << " " << q;
          ++zero;
          continue;
        }
        ++compared;
        const double rel = std::abs(got - cpu[q]) / cpu[q];
        if (!(rel <= worst)) {
          worst = std::isnan(rel) ? std::numeric_limits<double>::infinity() : rel;
          where = fmt::format("{} {} query {}: gpu {} cpu {}", preset.name, kChannelNames[c], q,
                              got, cpu[q]);
        }
      }
    }
  }
  EXPECT_LE(worst, 1e-4) << "worst at " << where;
  EXPECT_GT(compared, 10u * zero);
  std::printf("directional-dipole.bssrdf vs C++ kernel: %zu values, worst relative difference %.3g "
              "at %s (%zu below 1e-6 of the peak)\n",
              compared, worst, where.c_str(), zero);
}

TEST_F(GpuTest, DiffuseReflectanceOfEveryBuiltinMatchesTheCppModel) {
  const std::vector<float> albedos{0.01f, 0.05f, 0.25f, 0.5f, 0.75f, 0.9f,
                                   0.99f, 0.999f, 0.99999f, 1.0f};
  for (const char* name : {"dipole", "normalized-diffusion-fit", "better-dipole"}) {
    auto gpu = BssrdfEvaluator::builtin(name);
    ASSERT_TRUE(gpu.hasDiffuseReflectance()) << name;
    for (double eta : {1.0, 1.25, 1.5}) {  // exactly representable in float
      Medium m;
      m.eta = eta;
      gpu.setMedium(m);
      const auto rd = gpu.diffuseReflectance(albedos);
      for (size_t i = 0; i < albedos.size(); ++i) {
        const double expected = bssrdf::model(name).totalReflectance(albedos[i], eta);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(rd[i][static_cast<size_t>(c)], expected, 1e-5 * expected)
              << name << " alpha' " << albedos[i] << " eta " << eta;
      }
    }
  }
}

TEST_F(GpuTest, SeedListingA2MatchesTheCppDipole) {
  // The seed's own listing (with the transcription's LaTeX artifacts undone) computes the same
  // profile as the C++ dipole: Bssrdf() returns Rd(r) of Eq. 2.37 in Jensen's form.
  TempDir dir;
  auto gpu = BssrdfEvaluator(dir.write("listing_a2.bssrdf", translucent::testing::kSeedListingA2Glsl));
  const Agreement a = compareProfiles(gpu, bssrdf::model("dipole"), 0.0);
  EXPECT_LE(a.worst, 1e-4) << a.where;
  // Its DiffuseReflectance is Eq. 3.2.
  gpu.setMedium(Medium{});
  const std::vector<float> albedos{0.3f, 0.9f, 0.999f};
  const auto rd = gpu.diffuseReflectance(albedos);
  for (size_t i = 0; i < albedos.size(); ++i)
    EXPECT_NEAR(rd[i][0], bssrdf::model("dipole").totalReflectance(albedos[i], Medium{}.eta),
                1e-5 * double(rd[i][0]));
}

TEST_F(GpuTest, ParametersBecomeUniforms) {
  auto gpu = BssrdfEvaluator::builtin("dipole");
  gpu.setMedium(presets().front().medium());
  const std::vector<float> radii{0.0f, 0.5f, 2.0f};
  const auto base = gpu.profile(radii);
  EXPECT_EQ(std::get<double>(gpu.parameter("Multiplier")), 1.0);
  gpu.setParameter("Multiplier", 2.5);
  const auto scaled = gpu.profile(radii);
  for (size_t i = 0; i < radii.size(); ++i)
    for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(scaled[i][c], 2.5f * base[i][c], 1e-6f * scaled[i][c]);

  EXPECT_THROW(gpu.setParameter("Multiplier", 11.0), ParameterError);  // outside [0, 10]
  EXPECT_THROW(gpu.setParameter("Multiplier", true), ParameterError);  // wrong type
  try {
    gpu.setParameter("Gain", 1.0);
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("no parameter 'Gain' (declared: Multiplier)"));
  }
  Medium bad;
  bad.sigma_a[1] = -1.0;
  EXPECT_THROW(gpu.setMedium(bad), ParameterError);
}

// A small model whose shader section has an error on a known line.
constexpr const char* kBroken = R"(analytic radial
::begin parameters
float Gain 0 2 1
::end parameters
::begin initializer
void init() {}
::end initializer
::begin shader
vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {
  float r = distance(Xi, Xo);
  return vec3(Gain * exp(-r)) * undefinedFactor;
}
::end shader
)";

std::string evaluatorError(const std::filesystem::path& file) {
  try {
    BssrdfEvaluator e(file);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_F(GpuTest, GlslErrorInABssrdfSectionIsReportedAtTheBssrdfLine) {
  TempDir dir;
  const auto file = dir.write("broken.bssrdf", kBroken);
  const std::string e = evaluatorError(file);
  EXPECT_THAT(e, HasSubstr(file.string() + ":11: error")) << e;
  EXPECT_THAT(e, HasSubstr("undefinedFactor")) << e;

  // A syntax error in the initializer (statement level) and a parameter whose name is a GLSL
  // keyword (reported on its declaration line).
  std::string text = kBroken;
  text.replace(text.find("void init() {}"), 14, "void init() { float x = 1.0 }");
  text.replace(text.find("undefinedFactor"), 15, "1.0");
  const auto second = dir.write("init.bssrdf", text);
  EXPECT_THAT(evaluatorError(second), HasSubstr(second.string() + ":6: error"));
  text.replace(text.find("void init() { float x = 1.0 }"), 29, "void init() {}");
  text.replace(text.find("float Gain 0 2 1"), 16, "float int 0 2 1");
  const auto third = dir.write("keyword.bssrdf", text);
  EXPECT_THAT(evaluatorError(third), HasSubstr(third.string() + ":3: error"));
}

TEST_F(GpuTest, BssrdfModelWithoutOptionalSectionsEvaluates) {
  TempDir dir;
  std::string text = kBroken;
  text.replace(text.find(" * undefinedFactor"), 18, "");
  text.erase(text.find("::begin initializer"), text.find("::begin shader") - text.find("::begin initializer"));
  auto gpu = BssrdfEvaluator(dir.write("plain.bssrdf", text));
  EXPECT_FALSE(gpu.hasDiffuseReflectance());
  EXPECT_THROW(gpu.diffuseReflectance(std::vector<float>{0.5f}), GlError);
  gpu.setParameter("Gain", 0.5);
  const auto v = gpu.profile(std::vector<float>{0.0f, 1.0f, -2.0f});
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(v[0][c], 0.5f);
    EXPECT_NEAR(v[1][c], 0.5 * std::exp(-1.0), 1e-6);
    EXPECT_NEAR(v[2][c], 0.5 * std::exp(-2.0), 1e-6);  // negative radius: Xo on the -x axis
  }
  EXPECT_TRUE(gpu.profile(std::vector<float>{}).empty());
}

TEST_F(GpuTest, BssrdfReloadKeepsTheOldKernelsOnFailure) {
  TempDir dir;
  std::string good = kBroken;
  good.replace(good.find(" * undefinedFactor"), 18, "");
  const auto file = dir.write("model.bssrdf", good);
  BssrdfEvaluator gpu(file);
  gpu.setParameter("Gain", 2.0);
  const std::vector<float> radii{0.0f, 1.0f};
  EXPECT_FLOAT_EQ(gpu.profile(radii)[0][0], 2.0f);

  dir.write("model.bssrdf", kBroken);  // GLSL error on line 11
  EXPECT_FALSE(gpu.reload());
  EXPECT_THAT(gpu.lastError(), HasSubstr(file.string() + ":11: error")) << gpu.lastError();
  EXPECT_FLOAT_EQ(gpu.profile(radii)[0][0], 2.0f);

  dir.write("model.bssrdf", "analytic\n::begin shader\n");  // unterminated section
  EXPECT_FALSE(gpu.reload());
  EXPECT_THAT(gpu.lastError(), HasSubstr(file.string() + ":2: error: unterminated section"));
  EXPECT_FLOAT_EQ(gpu.profile(radii)[0][0], 2.0f);

  // A working edit: the value set for Gain survives, the new code runs.
  std::string edited = good;
  edited.replace(edited.find("exp(-r)"), 7, "exp(-2.0 * r)");
  dir.write("model.bssrdf", edited);
  EXPECT_TRUE(gpu.reload()) << gpu.lastError();
  EXPECT_EQ(std::get<double>(gpu.parameter("Gain")), 2.0);
  EXPECT_NEAR(gpu.profile(radii)[1][0], 2.0 * std::exp(-2.0), 1e-6);
}

}  // namespace
}  // namespace translucent::gpu
