// SPDX-License-Identifier: GPL-3.0-or-later
// Sphere integration of a directional model (the directional dipole's kernel with the light's true
// direction, reference/sphere_integration.h): both surface samplers against deterministic
// quadrature of the same integral, and the model against the path tracer at oblique light, next to
// the classic dipole (issue 14 §1).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"
#include "sphere_test_helpers.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;

using test_support::gauss;
using test_support::withSampling;

// B(x_o) = ∫ R(x_i, n_i, l; x_o, n_o) E0 Ft(n_i·l) (n_i·l) dA by quadrature in polar coordinates
// (θ', φ') about x_o (dA = R² sin θ' dθ' dφ'), panels graded towards θ' = 0 where the kernel
// peaks; E0 = 1.
double quadratureExitance(const bssrdf::DirectionalProfile& k, double R, double eta,
                          const glm::dvec3& n_o, const glm::dvec3& light) {
  glm::dvec3 t1 = glm::normalize(glm::cross(n_o, std::abs(n_o.y) < 0.9 ? glm::dvec3(0, 1, 0)
                                                                       : glm::dvec3(1, 0, 0)));
  const glm::dvec3 t2 = glm::cross(n_o, t1);
  const glm::dvec3 x_o = R * n_o;
  auto ring = [&](double th) {
    auto azimuth = [&](double ph) {
      const glm::dvec3 n =
          std::cos(th) * n_o + std::sin(th) * (std::cos(ph) * t1 + std::sin(ph) * t2);
      const double cosI = glm::dot(n, light);
      if (!(cosI > 0.0)) return 0.0;
      return k.R(R * n, n, light, x_o, n_o) * fresnelTransmittance(cosI, eta) * cosI;
    };
    return R * R * std::sin(th) * gauss(azimuth, 0.0, 2.0 * kPi, 64);
  };
  return test_support::gradedPolar(ring);
}


TEST(SphereIntegrationDirectional, BothSamplersMatchQuadratureAtObliqueLight) {
  // Light 60° from x_o's normal, and a point near the terminator: the directional kernel is far
  // from the radial restriction the importance sampler draws from, so this checks that the
  // mixture stays unbiased for it.
  const double R = 2.0;
  const ScalarMedium m{0.05, 1.0, 0.0, 1.3};
  SphereScene scene;
  scene.radius = R;
  scene.light_direction = {std::sin(kPi / 3.0), 0.0, std::cos(kPi / 3.0)};
  scene.width = scene.height = 4;
  const glm::dvec3 light = glm::normalize(scene.light_direction);
  const auto kernel = bssrdf::model("directional-dipole").directional(m);
  for (const double beta : {0.0, 100.0 * kPi / 180.0}) {
    const glm::dvec3 n_o(-std::sin(beta), 0.0, std::cos(beta));  // beta from +z, away from the light
    const double exact = quadratureExitance(*kernel, R, m.eta, n_o, light);
    ASSERT_GT(exact, 0.0);
    for (const auto& [sampling, n] : {std::pair{SurfaceSampling::Uniform, 400'000},
                                     std::pair{SurfaceSampling::Importance, 100'000}}) {
      SCOPED_TRACE(::testing::Message() << "beta " << beta << " sampling "
                                        << (sampling == SurfaceSampling::Uniform ? "uniform" : "importance"));
      const SphereIntegrator integ(bssrdf::model("directional-dipole"), scene, m, withSampling(sampling));
      Rng rng(5, 0);
      double s = 0.0, s2 = 0.0;
      for (int i = 0; i < n; ++i) {
        const double v = integ.sampleExitance(R * n_o, 0, rng);
        s += v;
        s2 += v * v;
      }
      const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1));
      EXPECT_NEAR(mean, exact, 4.0 * se) << "quadrature " << exact;
      EXPECT_LT(se, 0.02 * exact);  // the test has power
    }
  }
}

// Pixels of the lit sphere's image grouped by the angle between their normal and the light.
struct Band {
  double lo, hi;  // cosine of the angle to the light
  std::vector<uint32_t> pixels;
};

std::vector<Band> lightBands(const SphereScene& scene) {
  std::vector<Band> bands{{0.8, 1.0, {}}, {0.5, 0.8, {}}, {0.2, 0.5, {}}};
  const CameraModel camera(scene.camera());
  const SphereBody body(scene.radius);
  const glm::dvec3 light = glm::normalize(scene.light_direction);
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x) {
      glm::dvec3 o, d;
      camera.ray(x + 0.5, y + 0.5, o, d);
      SurfaceHit hit;
      if (!body.intersect(o, d, 0.0, 1e30, hit)) continue;
      const glm::dvec3 n = glm::normalize(o + hit.t * d);
      // Keep pixels well inside the disc (the pixel average at the rim mixes misses).
      if (glm::dot(n, glm::normalize(scene.view_direction)) < 0.3) continue;
      const double c = glm::dot(n, light);
      for (Band& b : bands)
        if (c >= b.lo && c < b.hi) b.pixels.push_back(static_cast<uint32_t>(y * scene.width + x));
    }
  return bands;
}

TEST(SphereIntegrationDirectional, PathTracerAtObliqueLightNextToTheClassicDipole) {
  // The measurement the issue asks for: a sphere of R = 20 reduced mean free paths of a highly
  // scattering medium (α' = 0.99, η = 1.3, g = 0), seen along +z and lit from 60° off the view
  // axis. Exitance averaged over bands of the cosine between the normal and the light, relative
  // to the path tracer (400k photons, ±0.4% per band; 64 samples per pixel for the models).
  // Measured (seeds as below):
  //   cos to light   [0.8, 1.0)   [0.5, 0.8)   [0.2, 0.5)
  //   dipole           -6.1%       -11.9%       -20.6%
  //   directional      +28.3%      +23.5%       +19.7%
  // The directional dipole is too bright throughout, by about its excess at normal incidence on
  // the flat half space (Rd 0.86 against the path tracer's 0.657; directional_dipole.cpp), but
  // its error changes half as much from the lit centre to grazing light as the dipole's (8.6
  // against 14.5 points): it follows the dependence on the light's direction that the classic
  // dipole misses. Asserted: those signs, the directional model within [+10%, +40%] in every
  // band, and the smaller change of its error across the bands (by at least 3 points, against
  // noise of under 1 point).
  const double R = 20.0;
  const ScalarMedium m{0.01, 0.99, 0.0, 1.3};
  SphereScene scene;
  scene.radius = R;
  scene.light_direction = {std::sin(kPi / 3.0), 0.0, std::cos(kPi / 3.0)};
  scene.view_direction = {0.0, 0.0, 1.0};
  scene.width = scene.height = 32;
  TracerOptions to;
  to.seed = 9;
  to.threads = 2;
  SpherePathTracer tracer(scene, m, to);
  tracer.addPass(400'000);
  SphereIntegrator dipole(bssrdf::model("dipole"), scene, m, withSampling(SurfaceSampling::Importance, 3));
  dipole.addPass(64);
  SphereIntegrator directional(bssrdf::model("directional-dipole"), scene, m,
                               withSampling(SurfaceSampling::Importance, 4));
  directional.addPass(64);
  const auto bands = lightBands(scene);
  std::vector<double> relDipole, relDirectional;
  for (const Band& b : bands) {
    ASSERT_GT(b.pixels.size(), 20u);
    const Estimate pt = tracer.images().exitance.average(b.pixels, 0);
    const Estimate dp = dipole.images().exitance.average(b.pixels, 0);
    const Estimate dd = directional.images().exitance.average(b.pixels, 0);
    relDipole.push_back((dp.value - pt.value) / pt.value);
    relDirectional.push_back((dd.value - pt.value) / pt.value);
    std::printf("cos to light [%.1f, %.1f), %zu pixels: path tracer %.5g ± %.2g, dipole %+.1f%%, "
                "directional dipole %+.1f%%\n",
                b.lo, b.hi, b.pixels.size(), pt.value, pt.std_error, 100.0 * relDipole.back(),
                100.0 * relDirectional.back());
    EXPECT_LT(relDipole.back(), 0.0);
    EXPECT_GT(relDirectional.back(), 0.10);
    EXPECT_LT(relDirectional.back(), 0.40);
  }
  ASSERT_EQ(relDipole.size(), 3u);
  ASSERT_EQ(relDirectional.size(), 3u);
  const double changeDipole = std::abs(relDipole[2] - relDipole[0]);
  const double changeDirectional = std::abs(relDirectional[2] - relDirectional[0]);
  EXPECT_LT(changeDirectional + 0.03, changeDipole)
      << "change of the relative error from the lit centre to grazing light";
}

}  // namespace
}  // namespace translucent::reference
