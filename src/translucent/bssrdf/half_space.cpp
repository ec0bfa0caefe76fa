// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/half_space.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "translucent/bssrdf/improved_diffusion.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"

namespace translucent::bssrdf {
namespace {

constexpr int kPoints = 16;  // Gauss-Legendre points per panel

// Nodes and weights of Gauss-Legendre panels between consecutive edges. The panel that starts at
// `sqrt_onset` (if any) is mapped by x = a + (b - a) s², which makes a √(x - a) onset smooth in s
// (the Fresnel transmittance out of the medium rises like that above the critical cosine).
void panels(const std::vector<double>& edges, std::vector<double>& x, std::vector<double>& w,
            double sqrt_onset = -1.0) {
  const auto& g = improved::gaussLegendre(kPoints);
  for (size_t k = 0; k + 1 < edges.size(); ++k) {
    const double a = edges[k], len = edges[k + 1] - a;
    const bool squared = a == sqrt_onset;
    for (size_t i = 0; i < g.x.size(); ++i) {
      const double s = g.x[i];
      x.push_back(squared ? a + len * s * s : a + len * s);
      w.push_back(squared ? 2.0 * len * s * g.w[i] : len * g.w[i]);
    }
  }
}

// ln(1 - ω θ cot θ) at the nodes of the θ quadrature of H, and the node data the denominator
// cos²θ + μ² sin²θ needs. Panels graded by decades towards θ = 0 (for ω = 1 the argument vanishes
// like θ²/3: a logarithmic singularity) and towards θ = π/2 (for small μ the integrand peaks at
// π/2 - θ ~ μ); nodes near π/2 are kept as x = π/2 - θ so that cot θ = tan x keeps its precision.
class HQuadrature {
 public:
  explicit HQuadrature(double omega) {
    std::vector<double> edges{0.0};
    for (double e = 1e-10; e < 0.05; e *= 10.0) edges.push_back(e);
    edges.push_back(0.3);
    edges.push_back(0.25 * std::numbers::pi);
    std::vector<double> t, tw;  // near 0, in θ
    std::vector<double> x, xw;  // near π/2, in x = π/2 - θ
    panels(edges, t, tw);
    panels(edges, x, xw);
    for (size_t i = 0; i < t.size(); ++i) add(omega, t[i], 0.5 * std::numbers::pi - t[i], tw[i]);
    for (size_t i = 0; i < x.size(); ++i) add(omega, 0.5 * std::numbers::pi - x[i], x[i], xw[i]);
  }

  double H(double mu) const {
    double sum = 0.0;
    for (size_t i = 0; i < logArg_.size(); ++i)
      sum += w_[i] * logArg_[i] / (cos2_[i] + mu * mu * sin2_[i]);
    return std::exp(-mu * std::numbers::inv_pi * sum);
  }

 private:
  // θ and its complement c = π/2 - θ, both given so that neither loses precision.
  void add(double omega, double theta, double c, double w) {
    double oneMinus;  // 1 - ω θ cot θ
    if (theta < 1e-2) {
      // θ cot θ = 1 - θ²/3 - θ⁴/45 - 2θ⁶/945 - θ⁸/4725 - ...: no cancellation as ω -> 1.
      const double t2 = theta * theta;
      oneMinus = (1.0 - omega) +
                 omega * t2 * (1.0 / 3.0 + t2 * (1.0 / 45.0 + t2 * (2.0 / 945.0 + t2 / 4725.0)));
    } else {
      oneMinus = 1.0 - omega * theta * std::tan(c);  // cot θ = tan(π/2 - θ)
    }
    logArg_.push_back(std::log(oneMinus));
    w_.push_back(w);
    const double s = std::sin(c), co = std::cos(c);  // cos θ = sin c, sin θ = cos c
    cos2_.push_back(s * s);
    sin2_.push_back(co * co);
  }

  std::vector<double> logArg_, w_, cos2_, sin2_;
};

void checkOmega(double omega) {
  if (!(omega >= 0.0 && omega <= 1.0))
    throw ParameterError(
        fmt::format("half-space albedo: single-scattering albedo omega must be in [0, 1], got {}",
                    omega));
}

// Solves A x = b in place (dense, partial pivoting); A is n x n row-major.
std::vector<double> solve(std::vector<double> A, std::vector<double> b) {
  const size_t n = b.size();
  for (size_t k = 0; k < n; ++k) {
    size_t piv = k;
    for (size_t i = k + 1; i < n; ++i)
      if (std::abs(A[i * n + k]) > std::abs(A[piv * n + k])) piv = i;
    if (piv != k) {
      for (size_t j = 0; j < n; ++j) std::swap(A[k * n + j], A[piv * n + j]);
      std::swap(b[k], b[piv]);
    }
    for (size_t i = k + 1; i < n; ++i) {
      const double f = A[i * n + k] / A[k * n + k];
      if (f == 0.0) continue;
      for (size_t j = k; j < n; ++j) A[i * n + j] -= f * A[k * n + j];
      b[i] -= f * b[k];
    }
  }
  for (size_t k = n; k-- > 0;) {
    double s = b[k];
    for (size_t j = k + 1; j < n; ++j) s -= A[k * n + j] * b[j];
    b[k] = s / A[k * n + k];
  }
  return b;
}

}  // namespace

double chandrasekharH(double mu, double omega) {
  checkOmega(omega);
  if (!(mu >= 0.0 && mu <= 1.0))
    throw ParameterError(fmt::format("chandrasekharH: mu must be in [0, 1], got {}", mu));
  return HQuadrature(omega).H(mu);
}

double halfSpaceAlbedo(double omega, double eta) {
  checkOmega(omega);
  if (!(eta > 0.0) || !std::isfinite(eta))
    throw ParameterError(fmt::format("half-space albedo: eta must be finite and > 0, got {}", eta));
  if (omega == 0.0) return 0.0;
  if (omega == 1.0) return 1.0;  // nothing is absorbed and the half-space has no other exit
  const HQuadrature hq(omega);
  const double h1 = hq.H(1.0);
  if (eta == 1.0) return 1.0 - h1 * std::sqrt(1.0 - omega);
  // Nyström nodes in μ: panels graded towards 0, with a break at the critical cosine where Fr
  // has a kink (total internal reflection below it).
  std::vector<double> edges{0.0, 1e-4, 1e-3, 1e-2, 0.05, 0.15, 0.35, 0.6, 1.0};
  double muC = -1.0;
  if (eta > 1.0) {
    muC = std::sqrt(1.0 - 1.0 / (eta * eta));
    // Drop the fixed edges too close to μc (panels there would be needlessly thin).
    std::erase_if(edges, [&](double e) { return e > 0.0 && e < 1.0 && std::abs(e - muC) < 0.02; });
    edges.push_back(muC);
    std::sort(edges.begin(), edges.end());
  }
  std::vector<double> mu, w;
  panels(edges, mu, w, muC);
  const size_t n = mu.size();
  std::vector<double> h(n), fr(n);
  for (size_t i = 0; i < n; ++i) {
    h[i] = hq.H(mu[i]);
    fr[i] = fresnelReflectance(-mu[i], eta);  // seen from inside the medium
  }
  const double q = 0.25 * omega;  // ρ = q H(μ) H(μ') / (μ + μ')
  std::vector<double> A(n * n), b(n);
  for (size_t i = 0; i < n; ++i) {
    b[i] = q * h[i] * h1 / (mu[i] + 1.0) * std::numbers::inv_pi;
    for (size_t j = 0; j < n; ++j)
      A[i * n + j] = (i == j ? 1.0 : 0.0) -
                     2.0 * w[j] * q * h[i] * h[j] / (mu[i] + mu[j]) * fr[j] * mu[j];
  }
  const std::vector<double> U = solve(std::move(A), std::move(b));
  double rd = 0.0;
  for (size_t i = 0; i < n; ++i) rd += w[i] * (1.0 - fr[i]) * U[i] * mu[i];
  return std::clamp(2.0 * std::numbers::pi * rd, 0.0, 1.0);
}

}  // namespace translucent::bssrdf
