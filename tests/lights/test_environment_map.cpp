// SPDX-License-Identifier: GPL-3.0-or-later
// Environment maps (lights/environment_map.h): the transmitted-irradiance kernel's λ_l, the SH
// irradiance, and the importance sampler that the point-cloud technique, the path tracer and the
// model reference share.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/io/image_io.h"
#include "translucent/lights/environment_map.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"

namespace translucent::lights {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Environment, LambdasReduceToRamamoorthiHanrahanWithoutFresnel) {
  // λ_l = 2π ∫0^1 Ft(η, t) t P_l(t) dt against an independent fine midpoint rule; Ft <= 1 bounds
  // λ_0 and λ_1 by the values without an interface (π, 2π/3).
  for (double eta : {1.0, 1.3, 1.5}) {
    const auto lambda = transmittedIrradianceLambdas(eta);
    std::array<double, 3> check{};
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) / n, w = 2.0 * kPi * fresnelTransmittance(t, eta) * t / n;
      check[0] += w;
      check[1] += w * t;
      check[2] += w * 0.5 * (3.0 * t * t - 1.0);
    }
    for (int l = 0; l < 3; ++l) EXPECT_NEAR(lambda[size_t(l)], check[size_t(l)], 1e-6) << "eta " << eta;
    EXPECT_LE(lambda[0], kPi + 1e-9);
    EXPECT_LE(lambda[1], 2.0 * kPi / 3.0 + 1e-9);
  }
  const auto one = transmittedIrradianceLambdas(1.0);
  EXPECT_NEAR(one[0], kPi, 1e-6);  // η = 1: Ft = 1 at every angle (no interface)
  EXPECT_NEAR(one[1], 2.0 * kPi / 3.0, 1e-6);
  EXPECT_NEAR(one[2], kPi / 4.0, 1e-6);
}

TEST(Environment, ShIrradianceOfALinearSkyIsExact) {
  // L(ω) = 1 + ω_y has only l = 0, 1 terms: E(n) = λ0 + λ1 n_y exactly (up to the midpoint
  // quadrature over the map), for any rotation about +y.
  EnvironmentMap map = EnvironmentMap::constant(glm::vec3(1.0f), 256, 128);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const double v = (y + 0.5) / map.height;
      const float value = float(1.0 + std::cos(kPi * v));
      for (int c = 0; c < 3; ++c) map.rgb[(size_t(y) * size_t(map.width) + size_t(x)) * 3 + size_t(c)] = value;
    }
  const auto lambda = transmittedIrradianceLambdas(1.3);
  const auto sh = irradianceSh9(map, 40.0, 1.3, glm::dvec3(1.0, 2.0, 3.0));
  for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(1, 0, 0),
                             glm::normalize(glm::dvec3(1, 2, -3))}) {
    const double want = lambda[0] + lambda[1] * n.y;
    const glm::dvec3 e = evalSh9(sh, n);
    EXPECT_NEAR(e.x, want, 2e-4 * lambda[0]) << n.x << " " << n.y << " " << n.z;
    EXPECT_NEAR(e.z, 3.0 * want, 6e-4 * lambda[0]);
  }
}

// A grey map with a bright patch.
EnvironmentMap patchMap() {
  EnvironmentMap map = EnvironmentMap::constant(glm::vec3(0.2f, 0.1f, 0.4f), 128, 64);
  for (int y = 10; y < 20; ++y)
    for (int x = 30; x < 50; ++x) {
      float* p = &map.rgb[(size_t(y) * 128 + size_t(x)) * 3];
      p[0] = 50.0f;
      p[1] = 20.0f;
      p[2] = 5.0f;
    }
  return map;
}

// ∫ over the texel rows [y0, y1) and columns [x0, x1) of channel c of the map, by a fine midpoint
// rule in θ (independent of the samplers' closed-form solid angles).
double regionIntegral(const EnvironmentMap& m, int c, int x0, int x1, int y0, int y1) {
  double sum = 0.0;
  const int sub = 64;
  for (int y = y0; y < y1; ++y) {
    double band = 0.0;  // ∫ sin θ dθ over the row
    for (int k = 0; k < sub; ++k) band += std::sin(kPi * (y + (k + 0.5) / sub) / m.height) * kPi / (m.height * sub);
    for (int x = x0; x < x1; ++x) sum += double(m.texel(x, y)[c]) * band * 2.0 * kPi / m.width;
  }
  return sum;
}

TEST(Environment, ImportanceSamplesHaveExactlyTheirDensity) {
  // Sampling ∝ w(L) ΔΩ per texel, uniform in solid angle inside it: L_w / pdf is the constant
  // ∫ w(L) dω for every sample (what lets every photon of the path tracer carry the same flux),
  // and pdf(direction) agrees with the sample's pdf.
  const EnvironmentMap map = patchMap();
  for (int c = 0; c < 3; ++c) {
    const EnvironmentSampler sampler(map, 25.0, SampleWeight(c + 1));
    const double integral = regionIntegral(map, c, 0, 128, 0, 64);
    EXPECT_NEAR(sampler.integral(), integral, 1e-6 * integral) << "channel " << c;
    for (int k = 0; k < 4096; ++k) {
      const auto s = sampler.sequence(uint64_t(k), 7);
      ASSERT_NEAR(glm::length(s.direction), 1.0, 1e-12);
      ASSERT_GT(s.pdf, 0.0);
      ASSERT_NEAR(s.radiance[c] / s.pdf, sampler.integral(), 1e-9 * sampler.integral()) << k;
      ASSERT_NEAR(sampler.pdf(s.direction), s.pdf, 1e-9 * s.pdf) << k;
      ASSERT_EQ(glm::dvec3(map.lookup(s.direction, 25.0)), s.radiance) << k;
    }
  }
  EnvironmentMap black = EnvironmentMap::constant(glm::vec3(0.0f), 8, 4);
  EXPECT_THROW(EnvironmentSampler(black, 0.0), ParameterError);
  // A map with no blue: the blue sampler has nothing to sample, the luminance one does.
  EnvironmentMap red = EnvironmentMap::constant(glm::vec3(1.0f, 0.0f, 0.0f), 8, 4);
  EXPECT_THROW(EnvironmentSampler(red, 0.0, SampleWeight::Blue), ParameterError);
  EXPECT_NO_THROW(EnvironmentSampler(red, 0.0));
}

TEST(Environment, SamplesFollowTheMapChiSquare) {
  // Pearson χ² of 200000 pseudo-random samples over 8 x 8 direction regions (4 rows of θ bands x
  // 8 φ sectors of the unrotated map, plus the patch split finely) against the probabilities of
  // the fine midpoint rule. 63 degrees of freedom: the 0.999 quantile is 103.4.
  const EnvironmentMap map = patchMap();
  const EnvironmentSampler sampler(map, 0.0, SampleWeight::Green);
  const int bx = 8, by = 8, n = 200000;
  std::vector<double> expected(size_t(bx * by));
  const double total = regionIntegral(map, 1, 0, 128, 0, 64);
  for (int j = 0; j < by; ++j)
    for (int i = 0; i < bx; ++i)
      expected[size_t(j * bx + i)] =
          n * regionIntegral(map, 1, i * 16, (i + 1) * 16, j * 8, (j + 1) * 8) / total;
  std::vector<double> count(expected.size(), 0.0);
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&] {  // splitmix64
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  for (int k = 0; k < n; ++k) {
    const double u = next(), v = next();
    const auto s = sampler.sample({u, v});
    const glm::ivec2 t = map.texelOf(s.direction, 0.0);
    count[size_t((t.y / 8) * bx + t.x / 16)] += 1.0;
  }
  double chi2 = 0.0;
  for (size_t b = 0; b < count.size(); ++b) {
    ASSERT_GT(expected[b], 5.0);
    chi2 += (count[b] - expected[b]) * (count[b] - expected[b]) / expected[b];
  }
  EXPECT_LT(chi2, 103.4);
}

// A map that is black everywhere (0, or negative values clamped to 0) lights nothing: every
// renderer drew black with exit 0 (the tracer refused some of these, the renderers not). Refused
// at load, for all of them, naming the file.
TEST(Environment, RefusesABlackMap) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("translucent-env-black-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string black = (dir / "black.exr").string();
  const std::string negative = (dir / "negative.exr").string();
  analysis::writeExr(black, 4, 2, std::vector<float>(4 * 2 * 3, 0.0f));
  analysis::writeExr(negative, 4, 2, std::vector<float>(4 * 2 * 3, -1e-5f));
  for (const std::string& file : {black, negative}) {
    try {
      (void)EnvironmentMap::load(file);
      ADD_FAILURE() << file << " accepted";
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("environment map '" + file + "': every pixel is 0"),
                std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("it emits no light"), std::string::npos) << e.what();
    }
  }
  std::vector<float> one(4 * 2 * 3, 0.0f);
  one[7] = 0.5f;
  analysis::writeExr(black, 4, 2, one);
  EXPECT_NO_THROW((void)EnvironmentMap::load(black));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace translucent::lights
