// SPDX-License-Identifier: GPL-3.0-or-later
// The slab walker against published Monte Carlo benchmarks, analytic transport results, energy
// conservation, reciprocity, its own tallies, and the dipole's far field. Every tolerance is a
// number of standard errors (the walker's own, combined with the published one) unless stated.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "translucent/bssrdf/half_space.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/slab.h"
#include "published_setups.h"

namespace translucent::reference {
namespace {

using test_support::mcmlSlab;

constexpr double kPi = std::numbers::pi;

// |ours - published| < 4 sqrt(σ_ours² + σ_published²)
void expectAgrees(const Estimate& ours, double published, double publishedSigma,
                  const char* what) {
  const double tol = 4.0 * std::hypot(ours.std_error, publishedSigma);
  EXPECT_NEAR(ours.value, published, tol)
      << what << ": " << ours.value << " ± " << ours.std_error << " vs " << published << " ± "
      << publishedSigma;
  EXPECT_GT(ours.std_error, 0.0) << what;
}

TraceOptions opts(uint64_t photons, uint64_t seed = 1) {
  TraceOptions o;
  o.photons = photons;
  o.seed = seed;
  o.threads = 2;
  return o;
}

TEST(Slab, MatchesMcmlBenchmarkSlabWithEveryWalker) {
  // Published: Rd = 0.09734 ± 0.00035, Tt = 0.66096 ± 0.00020 (van de Hulst: 0.09739, 0.66096);
  // unscattered transmittance e^{-μt d} = e^{-2} exactly.
  struct Case {
    Kernel kernel;
    Absorption absorption;
    uint64_t photons;
  };
  for (const Case c : {Case{Kernel::Lanes, Absorption::Analog, 2'000'000},
                       Case{Kernel::Lanes, Absorption::Weighted, 1'000'000},
                       Case{Kernel::LanesPortable, Absorption::Analog, 1'000'000},
                       Case{Kernel::Scalar, Absorption::Analog, 500'000},
                       Case{Kernel::Scalar, Absorption::Weighted, 500'000}}) {
    SCOPED_TRACE(::testing::Message() << "kernel " << static_cast<int>(c.kernel) << " absorption "
                                      << static_cast<int>(c.absorption));
    TraceOptions o = opts(c.photons, 17);
    o.kernel = c.kernel;
    o.absorption = c.absorption;
    const SlabResult r = traceSlab(mcmlSlab(), o);
    EXPECT_EQ(r.photons, c.photons);
    EXPECT_FALSE(r.partial);
    EXPECT_EQ(r.specular_reflectance.value, 0.0);
    expectAgrees(r.diffuse_reflectance, 0.09734, 0.00035, "diffuse reflectance");
    expectAgrees(r.transmittance, 0.66096, 0.00020, "total transmittance");
    expectAgrees(r.unscattered_transmittance, std::exp(-2.0), 0.0, "unscattered transmittance");
    EXPECT_NEAR(r.diffuse_transmittance.value + r.unscattered_transmittance.value,
                r.transmittance.value, 1e-12);
  }
}

TEST(Slab, MatchesGiovanelliForSemiInfiniteMismatchedMedium) {
  // n = 1.5 inside, 1 outside, μa = 10, μs = 90, g = 0, semi-infinite: total reflectance
  // including the specular 0.04 is 0.2600 (Giovanelli 1955; MCML: 0.25907 ± 0.00170).
  SlabSetup s;
  s.sigma_a = 10.0;
  s.sigma_s = 90.0;
  s.n_inside = 1.5;
  const SlabResult r = traceSlab(s, opts(2'000'000, 3));
  EXPECT_NEAR(r.specular_reflectance.value, 0.04, 1e-15);  // ((1.5 - 1) / (1.5 + 1))²
  const Estimate total{r.specular_reflectance.value + r.diffuse_reflectance.value,
                       r.diffuse_reflectance.std_error};
  expectAgrees(total, 0.25907, 0.00170, "total reflectance vs MCML");
  // Giovanelli's value is given to 4 decimals: its rounding error is at most 5e-5.
  expectAgrees(total, 0.2600, 5e-5, "total reflectance vs Giovanelli");
  EXPECT_EQ(r.transmittance.value, 0.0);
}

// Chandrasekhar's H-function for isotropic scattering with albedo ω at μ = 1, from the
// fixed-point iteration 1/H(μ) = sqrt(1 - ω) + (ω/2) ∫0^1 μ' H(μ') / (μ + μ') dμ' on 64
// Gauss-Legendre nodes.
double chandrasekharH1(double omega) {
  const int n = 64;
  std::vector<double> mu(n), wt(n), h(n, 1.0);
  for (int i = 0; i < n; ++i) {  // Legendre nodes on [-1, 1] by Newton, mapped to [0, 1]
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    mu[static_cast<size_t>(i)] = 0.5 * (x + 1.0);
    wt[static_cast<size_t>(i)] = 1.0 / ((1.0 - x * x) * dp * dp);  // half of 2 / ((1-x²) P'²)
  }
  auto inverseH = [&](double m) {
    double s = 0.0;
    for (size_t j = 0; j < mu.size(); ++j) s += wt[j] * mu[j] * h[j] / (m + mu[j]);
    return std::sqrt(1.0 - omega) + 0.5 * omega * s;
  };
  for (int it = 0; it < 1000; ++it) {
    std::vector<double> next(n);
    double change = 0.0;
    for (size_t i = 0; i < mu.size(); ++i) {
      next[i] = 1.0 / inverseH(mu[i]);
      change = std::max(change, std::abs(next[i] - h[i]));
    }
    h = next;
    if (change < 1e-14) break;
  }
  return 1.0 / inverseH(1.0);
}

TEST(Slab, MatchesChandrasekharPlaneAlbedo) {
  // Semi-infinite, index matched, isotropic scattering, normal incidence: the exact reflectance
  // is the plane albedo A(1) = 1 - H(1) sqrt(1 - ω) (Chandrasekhar 1960, radiative transfer).
  EXPECT_NEAR(chandrasekharH1(0.9), 1.8501, 1e-4);  // tabulated H(1; ω = 0.9)
  for (double omega : {0.5, 0.9, 0.99}) {
    SlabSetup s;
    s.sigma_s = omega;
    s.sigma_a = 1.0 - omega;
    const SlabResult r = traceSlab(s, opts(omega > 0.95 ? 400'000 : 1'000'000, 5));
    const double exact = 1.0 - chandrasekharH1(omega) * std::sqrt(1.0 - omega);
    expectAgrees(r.diffuse_reflectance, exact, 0.0, "plane albedo");
  }
}

TEST(Slab, MatchesExactHalfSpaceAlbedoWithFresnelBoundary) {
  // Isotropic scattering under a Fresnel boundary: bssrdf::halfSpaceAlbedo solves the transport
  // exactly (Chandrasekhar's reflection function plus the interface by the adding method, a
  // deterministic quadrature). Per unit flux entering = diffuse reflectance / (1 - Rsp).
  struct Case {
    double omega, eta;
    uint64_t photons;
  };
  for (const Case c : {Case{0.5, 1.3, 1'000'000}, Case{0.9, 1.5, 1'000'000},
                       Case{0.99, 1.3, 300'000}, Case{0.95, 1.1, 300'000}}) {
    SlabSetup s;
    s.sigma_s = c.omega;
    s.sigma_a = 1.0 - c.omega;
    s.n_inside = c.eta;
    const SlabResult r = traceSlab(s, opts(c.photons, 11));
    const double entering = 1.0 - r.specular_reflectance.value;
    expectAgrees({r.diffuse_reflectance.value / entering, r.diffuse_reflectance.std_error / entering},
                 bssrdf::halfSpaceAlbedo(c.omega, c.eta), 0.0, "half-space albedo");
  }
}

TEST(Slab, UnscatteredTransmissionThroughInterreflectingSlab) {
  // test_support::interreflectingSlab: the unscattered part crosses at the refracted angle θt
  // and bounces between the faces without scattering (its closed form there). This checks entry
  // refraction, specular reflection and the internal-reflection roulette.
  const test_support::InterreflectingSlab c = test_support::interreflectingSlab();
  const SlabSetup& s = c.setup;
  const double rsp = c.rsp, tu = c.unscattered_transmittance;
  // Both absorption schemes, and the scalar walker (which calls optics/fresnel.h itself, where
  // the lane walker uses its float version).
  for (const auto& [kernel, absorption] : {std::pair{Kernel::Lanes, Absorption::Analog},
                                           std::pair{Kernel::Lanes, Absorption::Weighted},
                                           std::pair{Kernel::Scalar, Absorption::Analog}}) {
    TraceOptions o = opts(kernel == Kernel::Scalar ? 300'000 : 1'000'000, 9);
    o.kernel = kernel;
    o.absorption = absorption;
    const SlabResult r = traceSlab(s, o);
    EXPECT_NEAR(r.specular_reflectance.value, rsp, 1e-15);
    expectAgrees(r.unscattered_transmittance, tu, 0.0, "unscattered transmittance");
  }
}

TEST(Slab, ConservesEnergy) {
  // Without absorption every photon leaves: Rsp + R + T = 1 exactly per photon.
  SlabSetup s;
  s.sigma_a = 0.0;
  s.sigma_s = 20.0;
  s.g = 0.6;
  s.thickness = 0.3;
  s.n_inside = 1.4;
  s.n_below = 1.2;
  s.theta = 0.4;
  for (Kernel k : {Kernel::Lanes, Kernel::Scalar}) {
    for (Absorption a : {Absorption::Analog, Absorption::Weighted}) {
      TraceOptions o = opts(100'000);
      o.kernel = k;
      o.absorption = a;
      const SlabResult r = traceSlab(s, o);
      EXPECT_NEAR(r.specular_reflectance.value + r.diffuse_reflectance.value +
                      r.transmittance.value,
                  1.0, 1e-12);
      EXPECT_EQ(r.absorbed.value, 0.0);
    }
  }
  // With absorption: analog photons end in exactly one tally, so the sum is 1 to rounding; the
  // weighted mode is 1 in expectation (its roulette is unbiased), within the summed errors.
  s.sigma_a = 3.0;
  for (Absorption a : {Absorption::Analog, Absorption::Weighted}) {
    TraceOptions o = opts(200'000);
    o.absorption = a;
    const SlabResult r = traceSlab(s, o);
    const double sum = r.specular_reflectance.value + r.diffuse_reflectance.value +
                       r.transmittance.value + r.absorbed.value;
    const double tol = a == Absorption::Analog ? 1e-12
                                               : 4.0 * (r.diffuse_reflectance.std_error +
                                                        r.transmittance.std_error +
                                                        r.absorbed.std_error);
    EXPECT_NEAR(sum, 1.0, tol);
  }
}

TEST(Slab, AnalogAndWeightedAbsorptionAgree) {
  // Two unbiased estimators of the same quantities (seed Algorithm 1 vs MCML's implicit
  // capture) on a mismatched, anisotropic, finite slab under an oblique beam.
  SlabSetup s;
  s.sigma_a = 1.5;
  s.sigma_s = 30.0;
  s.g = -0.4;
  s.thickness = 0.25;
  s.n_inside = 1.33;
  s.n_below = 1.6;
  s.theta = 0.8;
  TraceOptions a = opts(400'000, 21), w = opts(400'000, 22);
  w.absorption = Absorption::Weighted;
  const SlabResult ra = traceSlab(s, a), rw = traceSlab(s, w);
  expectAgrees(ra.diffuse_reflectance, rw.diffuse_reflectance.value,
               rw.diffuse_reflectance.std_error, "R");
  expectAgrees(ra.transmittance, rw.transmittance.value, rw.transmittance.std_error, "T");
  expectAgrees(ra.absorbed, rw.absorbed.value, rw.absorbed.std_error, "A");
}

TEST(Slab, LongPathRouletteIsUnbiased) {
  // The seed's long-path roulette (section 3.2) keeps a path after N scatterings with chance 1/10
  // and weight x10. Each extra event multiplies the second moment by 10 x P(continue), so the
  // variance is finite only when a photon continues with probability < 1/10 per event: here a
  // thin, strongly absorbing slab (α = 0.1), with the roulette from the 2nd event on.
  SlabSetup s;
  s.sigma_a = 9.0;
  s.sigma_s = 1.0;
  s.thickness = 0.2;
  s.g = 0.3;
  TraceOptions plain = opts(1'000'000, 31), roulette = opts(1'000'000, 32);
  roulette.long_path_roulette = 1;
  const SlabResult a = traceSlab(s, plain), b = traceSlab(s, roulette);
  expectAgrees(b.diffuse_reflectance, a.diffuse_reflectance.value,
               a.diffuse_reflectance.std_error, "R");
  expectAgrees(b.diffuse_transmittance, a.diffuse_transmittance.value,
               a.diffuse_transmittance.std_error, "diffuse T");
  EXPECT_LT(b.scattering_events, a.scattering_events);
}

TEST(Slab, BitIdenticalOnOneOrManyThreads) {
  SlabSetup s = mcmlSlab();
  s.n_inside = 1.37;
  s.theta = 0.3;
  for (Kernel k : {Kernel::Lanes, Kernel::Scalar}) {
    TraceOptions o = opts(3 * kBlockPhotons * 7 + 123, 99);  // not a whole number of blocks
    o.kernel = k;
    o.radial_bins = 30;
    o.radial_max = 0.05;
    o.angle_bins = 6;
    o.threads = 1;
    const SlabResult a = traceSlab(s, o);
    o.threads = 4;
    const SlabResult b = traceSlab(s, o);
    EXPECT_EQ(a.photons, b.photons);
    EXPECT_EQ(a.scattering_events, b.scattering_events);
    EXPECT_EQ(a.diffuse_reflectance.value, b.diffuse_reflectance.value);
    EXPECT_EQ(a.diffuse_reflectance.std_error, b.diffuse_reflectance.std_error);
    EXPECT_EQ(a.transmittance.value, b.transmittance.value);
    EXPECT_EQ(a.absorbed.std_error, b.absorbed.std_error);
    EXPECT_EQ(a.radial.rd, b.radial.rd);
    EXPECT_EQ(a.radial.rd_stderr, b.radial.rd_stderr);
    EXPECT_EQ(a.angular.rd_r_theta, b.angular.rd_r_theta);
    // A different seed is a different run.
    o.seed = 100;
    EXPECT_NE(traceSlab(s, o).diffuse_reflectance.value, a.diffuse_reflectance.value);
  }
}

TEST(Slab, AngularReflectanceIsReciprocal) {
  // Helmholtz reciprocity of the azimuth-averaged BRDF f(θi, θo) = f(θo, θi), with
  // f ≈ Rd(θo) / <cos θ>_bin for the per-steradian tally in 5° bins. Light from θi = 27.5° seen
  // at 62.5° must match light from 62.5° seen at 27.5°. This involves the entry refraction and
  // specular loss, the exit Fresnel transmission and refraction, and the angular bookkeeping.
  // (Averaging over the bins is symmetric only to second order in their width: ~0.1% here, far
  // below the 4σ ≈ 3% tolerance.)
  SlabSetup s;
  s.sigma_a = 1.0;
  s.sigma_s = 10.0;
  s.g = 0.5;
  s.n_inside = 1.33;
  TraceOptions o = opts(1'000'000, 41);
  o.angle_bins = 18;
  const int low = 5, high = 12;  // [25°, 30°] and [60°, 65°]
  auto brdf = [&](double thetaIn, int bin) {
    s.theta = thetaIn;
    const SlabResult r = traceSlab(s, o);
    const double a = bin * 5.0 * kPi / 180.0, b = (bin + 1) * 5.0 * kPi / 180.0;
    const double meanCos = 0.5 * (std::cos(a) + std::cos(b));
    return Estimate{r.angular.rd[static_cast<size_t>(bin)] / meanCos,
                    r.angular.rd_stderr[static_cast<size_t>(bin)] / meanCos};
  };
  const Estimate f1 = brdf(27.5 * kPi / 180.0, high);
  const Estimate f2 = brdf(62.5 * kPi / 180.0, low);
  expectAgrees(f1, f2.value, f2.std_error, "f(27.5°, 62.5°) vs f(62.5°, 27.5°)");
}

TEST(Slab, RadialAndAngularTalliesAddUpToTheDiffuseReflectance) {
  SlabSetup s;
  s.sigma_a = 0.5;
  s.sigma_s = 10.0;
  s.g = 0.8;
  s.n_inside = 1.4;
  TraceOptions o = opts(200'000, 51);
  o.radial_bins = 50;
  o.radial_max = 1.0;
  o.angle_bins = 9;
  const SlabResult r = traceSlab(s, o);
  // 2π Σ Rd(r_i) r_i Δr + (beyond r_max) = Rd: the same photons, so up to rounding.
  double radial = r.radial.beyond.value, angular = 0.0, joint = r.radial.beyond.value;
  for (size_t i = 0; i < r.radial.r.size(); ++i)
    radial += 2.0 * kPi * r.radial.rd[i] * r.radial.r[i] * r.radial.dr;
  for (size_t j = 0; j < r.angular.theta.size(); ++j) {
    const double solid = 2.0 * kPi * (std::cos(j * r.angular.dtheta) - std::cos((j + 1) * r.angular.dtheta));
    angular += r.angular.rd[j] * solid;
    for (size_t i = 0; i < r.radial.r.size(); ++i)
      joint += r.angular.rd_r_theta[i * r.angular.theta.size() + j] * solid * 2.0 * kPi *
               r.radial.r[i] * r.radial.dr;
  }
  EXPECT_NEAR(radial, r.diffuse_reflectance.value, 1e-12);
  EXPECT_NEAR(angular, r.diffuse_reflectance.value, 1e-12);
  EXPECT_NEAR(joint, r.diffuse_reflectance.value, 1e-12);
  EXPECT_GT(r.radial.beyond.value, 0.0);
  // Annulus centres and errors.
  EXPECT_NEAR(r.radial.r.front(), 0.01, 1e-15);
  EXPECT_NEAR(r.radial.dr, 0.02, 1e-15);
  for (size_t i = 0; i < r.radial.r.size(); ++i) EXPECT_GT(r.radial.rd_stderr[i], 0.0);
}

TEST(Slab, FarFieldApproachesTheClassicDipole) {
  // Highly scattering semi-infinite medium, η = 1, isotropic, α = 1/1.01. Diffusion is exact
  // only asymptotically: near the source (r of a few mean free paths ℓ) the dipole's point
  // source at depth ℓ' and its extrapolated boundary misplace light (the Monte Carlo profile is
  // 20-25% below it at r ≈ 2ℓ here). Far away these errors fade and what remains is
  //  - the decay rate: diffusion's σtr = 0.1741/ℓ vs the exact transport root ν = 0.1734/ℓ of
  //    (ω/2ν) ln((1+ν)/(1-ν)) = 1, a drift of e^{0.0007 r}: < 1.5% over r <= 20ℓ;
  //  - the far-field amplitude of P1 diffusion against transport, a few percent at 1 - ω = 1%.
  // So on r in [10ℓ, 20ℓ] the ratio Monte Carlo / dipole must lie within 8% (+ 4σ) of 1, and be
  // much closer to 1 than at 1.5-3ℓ.
  ScalarMedium m{0.01, 1.0, 0.0, 1.0};
  const SlabSetup s = SlabSetup::semiInfinite(m);
  TraceOptions o = opts(2'000'000, 61);
  o.radial_bins = 40;
  o.radial_max = 20.0;
  const SlabResult r = traceSlab(s, o);
  const auto dipole = bssrdf::model("dipole").profile(m);
  // Sums over a range of annuli of Monte Carlo and dipole reflected power (dipole averaged over
  // each annulus by the midpoint rule on 64 sub-rings); per-annulus errors are independent
  // enough to add in quadrature (a photon lands in one annulus only; the small negative
  // covariance of a multinomial makes this conservative).
  auto ratio = [&](double r0, double r1) {
    double mc = 0.0, var = 0.0, dip = 0.0;
    for (size_t i = 0; i < r.radial.r.size(); ++i) {
      if (r.radial.r[i] < r0 || r.radial.r[i] > r1) continue;
      const double area = 2.0 * kPi * r.radial.r[i] * r.radial.dr;
      mc += r.radial.rd[i] * area;
      var += std::pow(r.radial.rd_stderr[i] * area, 2);
      const double a = r.radial.r[i] - 0.5 * r.radial.dr;
      for (int k = 0; k < 64; ++k) {
        const double rr = a + (k + 0.5) * r.radial.dr / 64.0;
        dip += 2.0 * kPi * rr * dipole->R(rr) * r.radial.dr / 64.0;
      }
    }
    return Estimate{mc / dip, std::sqrt(var) / dip};
  };
  const Estimate far = ratio(10.0, 20.0), near = ratio(1.5, 3.0);
  EXPECT_NEAR(far.value, 1.0, 0.08 + 4.0 * far.std_error) << "far-field ratio";
  EXPECT_LT(std::abs(far.value - 1.0) + 4.0 * far.std_error, std::abs(near.value - 1.0))
      << "near " << near.value << " far " << far.value;
}

TEST(Slab, StopsWhenTheProgressCallbackSaysSo) {
  SlabSetup s = mcmlSlab();
  TraceOptions o = opts(4'000'000'000ull);
  int calls = 0;
  uint64_t last = 0;
  const SlabResult r = traceSlab(s, o, [&](const TraceProgress& p) {
    EXPECT_GE(p.photons_done, last);
    EXPECT_EQ(p.photons_total, o.photons);
    last = p.photons_done;
    return ++calls < 2;
  });
  EXPECT_TRUE(r.partial);
  EXPECT_LT(r.photons, o.photons);
  EXPECT_EQ(r.photons % kBlockPhotons, 0u);
  EXPECT_GE(calls, 3);  // two during the run, one at the end
  if (r.photons > 0) {
    EXPECT_TRUE(std::isfinite(r.diffuse_reflectance.value));
    EXPECT_NEAR(r.diffuse_reflectance.value + r.transmittance.value + r.absorbed.value, 1.0, 1e-12);
  }
  // A complete run reports all photons done at the end.
  TraceOptions small = opts(5000);
  uint64_t final = 0;
  const SlabResult full = traceSlab(s, small, [&](const TraceProgress& p) {
    final = p.photons_done;
    return true;
  });
  EXPECT_FALSE(full.partial);
  EXPECT_EQ(final, 5000u);
  EXPECT_GT(full.seconds, 0.0);
  EXPECT_GT(full.photonsPerSecond(), 0.0);
  EXPECT_EQ(full.threads, 2);
}

TEST(Slab, RejectsBadParameters) {
  auto throwsNaming = [](SlabSetup s, TraceOptions o, const std::string& name) {
    try {
      (void)traceSlab(s, o);
      ADD_FAILURE() << "no error for " << name;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  const TraceOptions o = opts(1000);
  SlabSetup s = mcmlSlab();
  s.g = 1.0;
  throwsNaming(s, o, "g");
  s = mcmlSlab();
  s.sigma_s = -1.0;
  throwsNaming(s, o, "sigma_s");
  s = mcmlSlab();
  s.theta = kPi / 2;
  throwsNaming(s, o, "theta");
  s = mcmlSlab();
  s.thickness = 0.0;
  throwsNaming(s, o, "thickness");
  s = mcmlSlab();
  s.n_below = 0.0;
  throwsNaming(s, o, "n_below");
  s = mcmlSlab();
  s.thickness = std::numeric_limits<double>::infinity();
  s.sigma_a = 0.0;
  throwsNaming(s, o, "sigma_a");  // semi-infinite without absorption never ends
  TraceOptions bad = o;
  bad.radial_bins = 10;
  throwsNaming(mcmlSlab(), bad, "radial_max");
  bad = o;
  bad.photons = 0;
  throwsNaming(mcmlSlab(), bad, "photons");
}

}  // namespace
}  // namespace translucent::reference
