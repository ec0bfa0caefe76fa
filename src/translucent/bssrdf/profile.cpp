// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/profile.h"
#include "translucent/optics/quadrature.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace translucent::bssrdf {
namespace {


// Table resolution: panels per decade of radius, and where the table stops (a fraction of the
// reflected energy left beyond r_max, or a hard cap in units of the inner scale).
constexpr int kPanelsPerDecade = 48;
constexpr double kTailFraction = 1e-11;
constexpr double kMaxRangeDecades = 9.0;

}  // namespace

double integratePanel(const RadialProfile& p, double a, double b) {
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double r = mid + half * kGauss8X[i];
    sum += kGauss8W[i] * r * p.R(r);
  }
  return 2.0 * std::numbers::pi * half * sum;
}

double RadialProfile::innerScale() const { return medium_.reducedMeanFreePath(); }

const RadialProfile::Cumulative& RadialProfile::cumulative() const {
  std::call_once(built_, [this] {
    // Build the table: a uniform first panel [0, r0], then log-spaced panels until the
    // contribution of the last decade is negligible relative to the total.
    const double r0 = 1e-4 * innerScale();
    const double step = std::pow(10.0, 1.0 / kPanelsPerDecade);
    Cumulative c;
    c.edges = {0.0};
    c.cdf = {0.0};
    // The first decades use uniform sub-panels so the near-source peak is resolved.
    for (int i = 1; i <= 16; ++i) {
      const double e = r0 * i / 16.0;
      c.cdf.push_back(c.cdf.back() + integratePanel(*this, c.edges.back(), e));
      c.edges.push_back(e);
    }
    const int maxPanels = static_cast<int>((4.0 + kMaxRangeDecades) * kPanelsPerDecade);
    double decadeStart = c.cdf.back();
    for (int i = 0; i < maxPanels; ++i) {
      const double a = c.edges.back(), b = a * step;
      c.cdf.push_back(c.cdf.back() + integratePanel(*this, a, b));
      c.edges.push_back(b);
      if ((i + 1) % kPanelsPerDecade == 0) {
        const double added = c.cdf.back() - decadeStart;
        decadeStart = c.cdf.back();
        // Past the inner scale, stop once a whole decade adds (almost) nothing.
        if (b > 10.0 * innerScale() && added <= kTailFraction * c.cdf.back()) break;
      }
    }
    cumulative_ = std::move(c);
  });
  return cumulative_;
}

double RadialProfile::Rd() const { return cumulative().total(); }

double RadialProfile::invertCumulative(double target) const {
  const auto& c = cumulative();
  if (target <= 0.0) return 0.0;
  if (target >= c.total()) return c.edges.back();
  // Panel holding the target, then Newton-bisection on F(r) = cdf[k] + ∫_{edge k}^r - target.
  const auto it = std::upper_bound(c.cdf.begin(), c.cdf.end(), target);
  const size_t k = static_cast<size_t>(it - c.cdf.begin()) - 1;
  double lo = c.edges[k], hi = c.edges[k + 1];
  const double base = c.cdf[k];
  // Start from linear interpolation of the cumulative inside the panel.
  double r = lo + (hi - lo) * (target - base) / (c.cdf[k + 1] - base);
  for (int iter = 0; iter < 60; ++iter) {
    const double f = base + integratePanel(*this, c.edges[k], r) - target;
    // Converged once the cumulative matches to ~1e-13 of the total: below the quadrature's own
    // error, so further steps only chase round-off.
    if (std::abs(f) <= 1e-13 * c.total()) return r;
    if (f > 0.0)
      hi = r;
    else
      lo = r;
    const double df = 2.0 * std::numbers::pi * r * R(r);
    double next = df > 0.0 ? r - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - r) <= 1e-13 * std::max(1.0, r) || hi - lo <= 1e-14 * hi) return next;
    r = next;
  }
  return r;
}

RadialSample RadialProfile::sample(double u) const {
  const double r = invertCumulative(u * cumulative().total());
  return {r, pdf(r)};
}

double RadialProfile::pdf(double r) const {
  const auto& c = cumulative();
  if (!(r >= 0.0) || r > c.edges.back()) return 0.0;
  // R first: far out it is 0 (or tiny) while 2π r can overflow (r = 1e308: inf · 0 = NaN).
  const double value = R(r);
  if (!(value > 0.0)) return 0.0;
  return r * (2.0 * std::numbers::pi * value / c.total());
}

double RadialProfile::radiusForFraction(double fraction) const {
  // Fraction of the total Rd (closed form where the model has one), not of the table.
  return invertCumulative(std::clamp(fraction, 0.0, 1.0) * Rd());
}

double Model::totalReflectance(double alpha_prime, double eta) const {
  ScalarMedium m{1.0 - alpha_prime, alpha_prime, 0.0, eta};
  return profile(m)->Rd();
}

std::unique_ptr<DirectionalProfile> Model::directional(const ScalarMedium&) const {
  return nullptr;
}

double azimuthalAverage(const DirectionalProfile& kernel, double r, double theta, int azimuths) {
  const glm::dvec3 n(0.0, 0.0, 1.0), x_i(0.0);
  const glm::dvec3 w(std::sin(theta), 0.0, std::cos(theta));
  double sum = 0.0;
  for (int k = 0; k < azimuths; ++k) {
    const double phi = 2.0 * std::numbers::pi * (k + 0.5) / azimuths;
    sum += kernel.R(x_i, n, w, glm::dvec3(r * std::cos(phi), r * std::sin(phi), 0.0), n);
  }
  return sum / azimuths;
}

}  // namespace translucent::bssrdf
