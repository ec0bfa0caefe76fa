// SPDX-License-Identifier: GPL-3.0-or-later
// The exact half-space albedo (bssrdf/half_space.h) against independent computations and published
// values: the H-function from the classical fixed-point iteration, its zeroth-moment identity,
// Chandrasekhar's table, and Giovanelli's reflectance of a Fresnel-bounded half-space.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "translucent/bssrdf/half_space.h"
#include "translucent/optics/medium.h"

namespace translucent::bssrdf {
namespace {

// Composite midpoint-free rule for these checks: Gauss-Legendre 8 points on panels graded by
// decades towards 0 (written out here rather than borrowed from the library).
struct Rule {
  std::vector<double> x, w;
};
Rule gradedRule() {
  static const double gx[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                               -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                               0.7966664774136267,  0.9602898564975363};
  static const double gw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                               0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                               0.2223810344533745, 0.1012285362903763};
  const double edges[] = {0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.03, 0.1, 0.2, 0.35, 0.5, 0.7, 1.0};
  Rule r;
  for (size_t k = 0; k + 1 < std::size(edges); ++k) {
    const double a = edges[k], b = edges[k + 1];
    for (int i = 0; i < 8; ++i) {
      r.x.push_back(0.5 * (a + b) + 0.5 * (b - a) * gx[i]);
      r.w.push_back(0.5 * (b - a) * gw[i]);
    }
  }
  return r;
}

// H by the fixed-point iteration 1/H(μ) = sqrt(1 - ω) + (ω/2) ∫0^1 μ' H(μ') / (μ + μ') dμ'
// (Chandrasekhar ch. V; the form that converges also for ω = 1), on the graded rule.
double iteratedH(double mu, double omega) {
  const Rule r = gradedRule();
  std::vector<double> h(r.x.size(), 1.0);
  auto inverseH = [&](double m) {
    double s = 0.0;
    for (size_t j = 0; j < r.x.size(); ++j) s += r.w[j] * r.x[j] * h[j] / (m + r.x[j]);
    return std::sqrt(1.0 - omega) + 0.5 * omega * s;
  };
  for (int it = 0; it < 5000; ++it) {
    double change = 0.0;
    std::vector<double> next(h.size());
    for (size_t i = 0; i < h.size(); ++i) {
      next[i] = 1.0 / inverseH(r.x[i]);
      change = std::max(change, std::abs(next[i] - h[i]));
    }
    h = next;
    if (change < 1e-13) break;
  }
  return 1.0 / inverseH(mu);
}

TEST(HalfSpace, HFunctionMatchesTheFixedPointIteration) {
  // Two independent computations: Chandrasekhar's explicit integral (library) and the iteration
  // of the nonlinear integral equation (here). The iteration slows down as ω -> 1 (its
  // contraction factor tends to 1; at ω = 1 it does not settle in any practical number of
  // steps), so it is compared up to ω = 0.9999, with a bound that follows its residual.
  for (double omega : {0.2, 0.5, 0.9, 0.99, 0.9999})
    for (double mu : {0.0, 1e-4, 0.05, 0.3, 0.7, 1.0}) {
      const double tol = omega > 0.999 ? 1e-7 : 1e-8;
      EXPECT_NEAR(chandrasekharH(mu, omega), iteratedH(mu, omega), tol)
          << "omega " << omega << " mu " << mu;
    }
  EXPECT_EQ(chandrasekharH(0.0, 0.7), 1.0);  // H(0) = 1 for every ω
}

TEST(HalfSpace, HFunctionPublishedValues) {
  // Chandrasekhar 1960, Table of H(μ) for isotropic scattering (4-5 decimals, so the bound is
  // the table's rounding): ω = 1: H(1) = 2.90781 (the conservative case, which the iteration of
  // the test above cannot reach); ω = 0.9: H(1) = 1.8501.
  EXPECT_NEAR(chandrasekharH(1.0, 1.0), 2.90781, 5e-6);
  EXPECT_NEAR(chandrasekharH(1.0, 0.9), 1.8501, 5e-5);
}

TEST(HalfSpace, HFunctionZerothMomentIdentity) {
  // (ω/2) ∫0^1 H(μ) dμ = 1 - sqrt(1 - ω) (Chandrasekhar ch. V), by an independent quadrature.
  const Rule r = gradedRule();
  for (double omega : {0.3, 0.8, 0.95, 0.9999, 1.0}) {
    double s = 0.0;
    for (size_t i = 0; i < r.x.size(); ++i) s += r.w[i] * chandrasekharH(r.x[i], omega);
    // 2e-8 is reached at ω = 1, where both H and the identity's right side have their
    // strongest endpoint behaviour; below that the agreement is ~1e-10.
    EXPECT_NEAR(0.5 * omega * s, 1.0 - std::sqrt(1.0 - omega), omega == 1.0 ? 5e-8 : 1e-9)
        << omega;
  }
}

TEST(HalfSpace, IndexMatchedAlbedoIsTheClosedForm) {
  for (double omega : {0.1, 0.5, 0.9, 0.99})
    EXPECT_NEAR(halfSpaceAlbedo(omega, 1.0),
                1.0 - iteratedH(1.0, omega) * std::sqrt(1.0 - omega), 1e-8);
  // A published value of the closed form: ω = 0.5 gives 0.1152 (H(1) = 1.2512).
  EXPECT_NEAR(halfSpaceAlbedo(0.5, 1.0), 1.0 - 1.2512 * std::sqrt(0.5), 1e-4);
}

TEST(HalfSpace, MatchesGiovanelliForAFresnelBoundary) {
  // n = 1.5 inside, air outside, ω = 0.9 (μa = 10, μs = 90), g = 0, normal incidence: total
  // reflectance including the specular 0.04 is 0.2600 (Giovanelli 1955, as quoted by MCML, Wang,
  // Jacques & Zheng 1995). Giovanelli's value is itself a 1955 numerical solution, and it is 8e-5
  // above ours (0.25992): the project's slab tracer with 2.4e8 photons gives 0.229083 ± 0.000027
  // per unit flux entering (`translucent pathtrace slab --sigma-a 10 --sigma-s 90 --eta 1.5
  // --photons 2.4e8 --seed 7`), ours is 0.229082. So the bound here is 1e-4 on the total, the
  // published value's rounding (5e-5) plus its observed deviation from the Monte Carlo.
  EXPECT_NEAR(0.04 + 0.96 * halfSpaceAlbedo(0.9, 1.5), 0.2600, 1e-4);
  // And the 2.4e8-photon Monte Carlo value itself, within 4 of its standard errors.
  EXPECT_NEAR(halfSpaceAlbedo(0.9, 1.5), 0.229083, 4.0 * 0.000027);
}

TEST(HalfSpace, ConservesEnergyAndIncreasesWithAlbedo) {
  for (double eta : {0.8, 1.0, 1.1, 1.3, 1.44, 1.6, 2.0}) {
    double prev = 0.0;
    for (double omega : {1e-6, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999, 0.99999, 1.0 - 1e-9}) {
      const double rd = halfSpaceAlbedo(omega, eta);
      EXPECT_GT(rd, prev) << "omega " << omega << " eta " << eta;
      EXPECT_LT(rd, 1.0) << "omega " << omega << " eta " << eta;
      prev = rd;
    }
    // Without absorption all light leaves: the quadrature approaches 1 like 1 - c sqrt(1 - ω).
    EXPECT_NEAR(halfSpaceAlbedo(1.0 - 1e-12, eta), 1.0, 1e-4) << eta;
    EXPECT_EQ(halfSpaceAlbedo(0.0, eta), 0.0);
    EXPECT_EQ(halfSpaceAlbedo(1.0, eta), 1.0);
  }
}

TEST(HalfSpace, RejectsBadInput) {
  EXPECT_THROW((void)halfSpaceAlbedo(-0.1, 1.3), ParameterError);
  EXPECT_THROW((void)halfSpaceAlbedo(1.1, 1.3), ParameterError);
  EXPECT_THROW((void)halfSpaceAlbedo(0.5, 0.0), ParameterError);
  EXPECT_THROW((void)chandrasekharH(1.5, 0.5), ParameterError);
}

}  // namespace
}  // namespace translucent::bssrdf
