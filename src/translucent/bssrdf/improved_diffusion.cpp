// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/improved_diffusion.h"

#include <algorithm>
#include <array>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include "translucent/optics/fresnel.h"

namespace translucent::bssrdf::improved {

double fresnelMoment(int n, double eta) {
  // Below the critical cosine μc (η > 1) the reflectance is 1 and the moment is μc^{n+1}/(n+1).
  // Above it Fr - 1 behaves like sqrt(μ - μc), so substitute μ = μc + (1 - μc) s², which makes the
  // integrand smooth, and use 4 Gauss-Legendre panels of 16 points.
  const double muC = eta > 1.0 ? std::sqrt(1.0 - 1.0 / (eta * eta)) : 0.0;
  double sum = std::pow(muC, n + 1) / (n + 1);
  const auto& g = gaussLegendre(16);
  const int panels = 4;
  for (int p = 0; p < panels; ++p) {
    for (size_t i = 0; i < g.x.size(); ++i) {
      const double s = (p + g.x[i]) / panels;
      const double mu = muC + (1.0 - muC) * s * s;
      const double jac = 2.0 * (1.0 - muC) * s / panels;
      sum += g.w[i] * jac * fresnelReflectance(-mu, eta) * std::pow(mu, n);
    }
  }
  return sum;
}

ImprovedDiffusion::ImprovedDiffusion(const ScalarMedium& m) {
  sigma_a = m.sigma_a;
  sigma_tp = m.sigmaTPrime();
  alpha_p = m.reducedAlbedo();
  D = (2.0 * m.sigma_a + m.sigmaSPrime()) / (3.0 * sigma_tp * sigma_tp);
  sigma_tr = std::sqrt(m.sigma_a / D);
  const double c1 = fresnelMoment(1, m.eta), c2 = fresnelMoment(2, m.eta);
  zb = 2.0 * D * (1.0 + 3.0 * c2) / (1.0 - 2.0 * c1);
  c_phi = 0.25 * (1.0 - 2.0 * c1);
  c_e = 0.5 * (1.0 - 3.0 * c2);
}

namespace {

// Asymptotic series erfcx(x) √π x = Σ_n (-1)^n (2n-1)!! / (2x²)^n; with x >= 25 the eighth term
// is below 1e-20, so the truncation error is far below double precision.
constexpr double kAsymptotic = 25.0;

double asymptoticSum(double x, bool skipFirst) {
  const double q = 1.0 / (2.0 * x * x);
  double term = 1.0, sum = skipFirst ? 0.0 : 1.0;
  for (int n = 1; n <= 8; ++n) {
    term *= -(2.0 * n - 1.0) * q;
    sum += term;
  }
  return sum;
}

}  // namespace

double erfcx(double x) {
  if (x < kAsymptotic) return std::exp(x * x) * std::erfc(x);
  return asymptoticSum(x, false) / (std::sqrt(std::numbers::pi) * x);
}

double erfcxDeficit(double x) {
  // Direct difference loses ~log10(2x²) digits: at most 13 digits are left below x = 25.
  if (x < kAsymptotic) return 1.0 / (std::sqrt(std::numbers::pi) * x) - erfcx(x);
  return -asymptoticSum(x, true) / (std::sqrt(std::numbers::pi) * x);
}

const GaussRule& gaussLegendre(int n) {
  if (n < 1 || n > 64) throw std::invalid_argument("gaussLegendre: n must be in [1, 64]");
  static std::array<GaussRule, 65> rules;
  static std::array<std::once_flag, 65> flags;
  const auto k = static_cast<size_t>(n);
  std::call_once(flags[k], [n, k] {
    // Newton iteration on P_n from the Chebyshev-like initial guesses (Numerical Recipes gauleg).
    GaussRule g;
    g.x.resize(k);
    g.w.resize(k);
    for (int i = 0; i < (n + 1) / 2; ++i) {
      double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), pp = 1.0;
      for (int iter = 0; iter < 100; ++iter) {
        double p1 = 1.0, p2 = 0.0;
        for (int j = 1; j <= n; ++j) {
          const double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
        }
        pp = n * (z * p1 - p2) / (z * z - 1.0);
        const double dz = p1 / pp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      const double w = 2.0 / ((1.0 - z * z) * pp * pp);
      // Map [-1, 1] to [0, 1]: node (1 ∓ z)/2, weight w/2.
      g.x[static_cast<size_t>(i)] = 0.5 * (1.0 - z);
      g.x[k - 1 - static_cast<size_t>(i)] = 0.5 * (1.0 + z);
      g.w[static_cast<size_t>(i)] = g.w[k - 1 - static_cast<size_t>(i)] = 0.5 * w;
    }
    rules[k] = std::move(g);
  });
  return rules[k];
}

double LogRadialTable::operator()(double r) const {
  // 4-point Lagrange interpolation of y in x = ln r on the uniform grid, window shifted inside the
  // table at its ends.
  const double t = (std::log(r) - x0_) / h_;
  const int n = static_cast<int>(y_.size());
  int i = std::clamp(static_cast<int>(std::floor(t)) - 1, 0, n - 4);
  const double u = t - i;  // position relative to node i, in [0, 3] inside the table
  const double* y = y_.data() + i;
  const double l0 = -(u - 1.0) * (u - 2.0) * (u - 3.0) / 6.0;
  const double l1 = u * (u - 2.0) * (u - 3.0) / 2.0;
  const double l2 = -u * (u - 1.0) * (u - 3.0) / 2.0;
  const double l3 = u * (u - 1.0) * (u - 2.0) / 6.0;
  const double yi = l0 * y[0] + l1 * y[1] + l2 * y[2] + l3 * y[3];
  return std::exp(yi - k_ * r) / r;
}

}  // namespace translucent::bssrdf::improved
