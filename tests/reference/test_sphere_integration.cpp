// SPDX-License-Identifier: GPL-3.0-or-later
// BSSRDF integration on the lit sphere (src/reference/sphere_integration.h): both surface
// samplers against deterministic quadrature of the same integral, against each other on whole
// images (per-pixel z-test at a corrected significance level, as in Mitsuba's render tests), and
// the path tracer against the dipole, whose known bias is measured and bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"
#include "sphere_test_helpers.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;

using test_support::gauss;
using test_support::withSampling;

// B(x_o) for x_o at polar angle beta from the light (light along +z): the integral over the
// sphere in polar coordinates (θ', φ') about x_o, where |x_o - x_i| = 2R sin(θ'/2) and
// dA = R² sin θ' dθ' dφ'. The integrand is smooth except for a kink at the terminator, where
// E -> 0 continuously; dense panels resolve it.
double quadratureExitance(const bssrdf::RadialProfile& p, double R, double eta, double beta) {
  const glm::dvec3 n_o(std::sin(beta), 0.0, std::cos(beta));
  glm::dvec3 t1 = glm::normalize(glm::cross(n_o, glm::dvec3(0.0, 1.0, 0.0)));
  const glm::dvec3 t2 = glm::cross(n_o, t1);
  auto ring = [&](double th) {
    const double d = 2.0 * R * std::sin(0.5 * th);
    const double rd = p.R(d);
    auto azimuth = [&](double ph) {
      const glm::dvec3 n = std::cos(th) * n_o + std::sin(th) * (std::cos(ph) * t1 + std::sin(ph) * t2);
      const double cosI = n.z;
      return cosI > 0.0 ? fresnelTransmittance(cosI, eta) * cosI : 0.0;
    };
    return rd * R * R * std::sin(th) * gauss(azimuth, 0.0, 2.0 * kPi, beta == 0.0 ? 1 : 64);
  };
  return test_support::gradedPolar(ring);
}

SphereScene sceneWithLightOnZ(double radius, int size) {
  SphereScene s;
  s.radius = radius;
  s.light_direction = {0.0, 0.0, 1.0};
  s.view_direction = {0.0, 0.0, 1.0};
  s.width = s.height = size;
  return s;
}


TEST(SphereIntegration, BothSamplersMatchQuadratureAtAPoint) {
  // One point facing the light and one 70° away (its neighbourhood reaches past the
  // terminator), dipole profile, η = 1.3: the Monte Carlo mean of each sampler within 4 standard
  // errors of the quadrature.
  const double R = 2.0;
  const ScalarMedium m{0.05, 1.0, 0.0, 1.3};
  const SphereScene scene = sceneWithLightOnZ(R, 4);
  const auto profile = bssrdf::model("dipole").profile(m);
  for (const double beta : {0.0, 70.0 * kPi / 180.0}) {
    const double exact = quadratureExitance(*profile, R, m.eta, beta);
    const glm::dvec3 x_o = R * glm::dvec3(std::sin(beta), 0.0, std::cos(beta));
    for (const auto& [sampling, n] : {std::pair{SurfaceSampling::Uniform, 400'000},
                                     std::pair{SurfaceSampling::Importance, 60'000}}) {
      SCOPED_TRACE(::testing::Message() << "beta " << beta << " sampling "
                                        << (sampling == SurfaceSampling::Uniform ? "uniform" : "importance"));
      const SphereIntegrator integ(bssrdf::model("dipole"), scene, m, withSampling(sampling));
      Rng rng(3, 0);
      double s = 0.0, s2 = 0.0;
      for (int i = 0; i < n; ++i) {
        const double v = integ.sampleExitance(x_o, 0, rng);
        s += v;
        s2 += v * v;
      }
      const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1));
      EXPECT_NEAR(mean, exact, 4.0 * se) << "quadrature " << exact;
      EXPECT_LT(se, 0.01 * exact);  // the test has power
    }
  }
}

TEST(SphereIntegration, UniformAndImportanceImagesAgreePixelByPixel) {
  // Two unbiased estimators of the same pixel averages: per pixel z = Δ / sqrt(σ1² + σ2²) must
  // stay below the two-sided threshold for a 1% family-wise level over all covered pixels
  // (Šidák correction), and the pooled z² must be consistent with a χ² of that many degrees of
  // freedom (its mean 1 within 5 standard deviations of the χ² mean, sqrt(2/n)).
  SphereScene scene = sceneWithLightOnZ(2.0, 20);
  scene.light_direction = {0.6, 0.3, 1.0};  // a terminator inside the image
  const ScalarMedium m{0.05, 0.95, 0.0, 1.3};
  SphereIntegrator uniform(bssrdf::model("dipole"), scene, m, withSampling(SurfaceSampling::Uniform, 4));
  SphereIntegrator importance(bssrdf::model("dipole"), scene, m, withSampling(SurfaceSampling::Importance, 5));
  // Both estimators are heavy-tailed in places (uniform: rare samples near x_o where the profile
  // peaks; importance: the dark side, reached only by its uniform fraction), which makes their
  // sample standard errors unreliable with few samples (at 256 and 96 samples per pixel the mean
  // z² is 1.18 and single pixels reach |z| = 5.4); these counts give mean z² = 1.02.
  uniform.addPass(2048);
  importance.addPass(1024);
  std::vector<double> z;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) {
      const Estimate a = uniform.images().exitance.pixel(x, y, 0);
      const Estimate b = importance.images().exitance.pixel(x, y, 0);
      if (a.value == 0.0 && b.value == 0.0) continue;  // off the sphere (or unlit and unreached)
      z.push_back((a.value - b.value) / std::hypot(a.std_error, b.std_error));
    }
  ASSERT_GT(z.size(), 250u);
  const double n = static_cast<double>(z.size());
  const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / n);  // Šidák, per pixel
  // Two-sided normal quantile by bisection on erfc.
  double lo = 0.0, hi = 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
  }
  double z2 = 0.0;
  for (double v : z) {
    EXPECT_LT(std::abs(v), lo);
    z2 += v * v;
  }
  EXPECT_NEAR(z2 / n, 1.0, 5.0 * std::sqrt(2.0 / n)) << "mean z² over " << n << " pixels";
}

// Ring averages of an image about its centre (light and view on the same axis): rings of equal
// width in ρ/R, ring k holding the pixels whose centres lie in [k, k+1) R/rings.
std::vector<std::vector<uint32_t>> rings(int size, double margin, int count) {
  std::vector<std::vector<uint32_t>> out(static_cast<size_t>(count));
  const double half = 0.5 * size, discRadius = half / margin;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double rho = std::hypot(x + 0.5 - half, y + 0.5 - half) / discRadius;
      if (rho < 1.0)
        out[static_cast<size_t>(rho * count)].push_back(static_cast<uint32_t>(y * size + x));
    }
  return out;
}

TEST(SphereIntegration, PathTracerAgreesWithTheDipoleWithinItsKnownBias) {
  // A large sphere (R = 50 reduced mean free paths) of a highly scattering medium (α' = 0.99,
  // η = 1.3, g = 0), lit and seen head-on. The path tracer is exact; the dipole integrated over
  // the sphere is not: it is a diffusion approximation for a flat half space. For this medium
  // the dipole's total reflectance is 1.9% below Monte Carlo on the flat half space (0.6445 vs
  // 0.6570 per unit transmitted flux, traced with traceSlab; checked below), and on the sphere
  // it falls further behind towards the rim, where light arrives at grazing angles (the dipole
  // ignores the incident direction) and the surface curves away within a diffusion length
  // (1/σtr = 5.8 ℓ'). Measured relative differences (dipole - path tracer) / path tracer on 8
  // rings of equal width in ρ/R, centre to rim, 400k photons vs 64 samples per pixel:
  //   -3.9%, -4.0%, -4.2%, -4.3%, -4.9%, -6.8%, -9.1%, -12.1%   (±1.5 to 3.6%, 1σ, per ring)
  // Asserted: within 8% on the inner half of the disc and 16% on the outer half, and below the
  // path tracer on average over the inner half (the sign of the half-space bias).
  const double R = 50.0;
  const ScalarMedium m{0.01, 0.99, 0.0, 1.3};
  const SphereScene scene = sceneWithLightOnZ(R, 32);
  TracerOptions to;
  to.seed = 7;
  to.threads = 2;
  SpherePathTracer tracer(scene, m, to);
  tracer.addPass(400'000);
  SphereIntegrator dipole(bssrdf::model("dipole"), scene, m, withSampling(SurfaceSampling::Importance, 3));
  dipole.addPass(64);

  const auto ringPixels = rings(32, scene.margin, 8);
  std::vector<uint32_t> inner;
  for (int k = 0; k < 8; ++k) {
    const auto& px = ringPixels[static_cast<size_t>(k)];
    const Estimate pt = tracer.images().exitance.average(px, 0);
    const Estimate dp = dipole.images().exitance.average(px, 0);
    const double rel = (dp.value - pt.value) / pt.value;
    const double tol = k < 4 ? 0.08 : 0.16;
    EXPECT_LT(std::abs(rel), tol) << "ring " << k << ": path tracer " << pt.value << " ± "
                                  << pt.std_error << ", dipole " << dp.value << " ± "
                                  << dp.std_error;
    if (k < 4) inner.insert(inner.end(), px.begin(), px.end());
  }
  const Estimate pt = tracer.images().exitance.average(inner, 0);
  const Estimate dp = dipole.images().exitance.average(inner, 0);
  EXPECT_LT(dp.value, pt.value) << "inner half: dipole " << dp.value << " ± " << dp.std_error
                                << ", path tracer " << pt.value << " ± " << pt.std_error;

  // The half-space bias quoted above.
  SlabSetup slab = SlabSetup::semiInfinite(m);
  TraceOptions so;
  so.photons = 300'000;
  so.threads = 2;
  const SlabResult r = traceSlab(slab, so);
  const double mc = r.diffuse_reflectance.value / (1.0 - r.specular_reflectance.value);
  const double dipoleRd = bssrdf::model("dipole").profile(m)->Rd();
  EXPECT_NEAR(dipoleRd / mc, 0.981, 0.006) << "dipole " << dipoleRd << ", Monte Carlo " << mc;
}

TEST(SphereIntegration, RejectsBadOptions) {
  const ScalarMedium m{0.05, 1.0, 0.0, 1.3};
  IntegrationOptions o;
  o.defensive = 0.0;
  EXPECT_THROW(SphereIntegrator(bssrdf::model("dipole"), sceneWithLightOnZ(1.0, 4), m, o),
               ParameterError);
  SphereIntegrator ok(bssrdf::model("dipole"), sceneWithLightOnZ(1.0, 4), m, IntegrationOptions{});
  EXPECT_THROW(ok.addPass(0), ParameterError);
  ScalarMedium bad = m;
  bad.sigma_a = std::nan("");
  EXPECT_THROW(SphereIntegrator(bssrdf::model("dipole"), sceneWithLightOnZ(1.0, 4), bad,
                                IntegrationOptions{}),
               ParameterError);
}

}  // namespace
}  // namespace translucent::reference
