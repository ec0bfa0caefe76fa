// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/tsis/hybrid_split.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/vec3.hpp>

#include "translucent/techniques/technique.h"

namespace translucent::tsis {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kLocalFraction = 0.999;  // of the local term's mass inside the pattern
constexpr int kSub = 64;                  // integration steps per table interval or zone

// ∫_a^b 2πr R_c(r) W_l(r) dr by the midpoint rule over kSub steps (R interpolated as the GPU).
double ringMass(const bssrdf::ProfileTable& t, double rp, double k, double a, double b) {
  double sum = 0.0;
  const double h = (b - a) / kSub;
  for (int i = 0; i < kSub; ++i) {
    const double r = a + (i + 0.5) * h;
    sum += 2.0 * kPi * r * t.lookup(r) * localWeight(r, rp, k);
  }
  return sum * h;
}

}  // namespace

double localWeight(double r, double rp, double k) {
  // Symmetric about R_p (W_l(R_p − s) = 1 − W_l(R_p + s)); see the header for the seed's sign.
  const double e = 0.5 * std::exp(-std::abs(r - rp) * k);
  return r <= rp ? 1.0 - e : e;
}

double autoSplitRadius(const bssrdf::ProfileTable& t, double bound) {
  for (size_t i = t.R.size(); i-- > 1;)
    if (2.0 * kPi * t.radius(i) * double(t.R[i]) >= bound) return t.radius(i);
  return 0.0;
}

HybridSplit makeHybridSplit(const std::array<bssrdf::ProfileTable, 3>& tables, double kPerMm,
                            double boundPerMm, double mmPerUnit) {
  if (!(mmPerUnit > 0.0) || !std::isfinite(mmPerUnit))
    throw ParameterError("hybrid split: the medium's scale (mm per scene unit) must be positive");
  HybridSplit s;
  // r_mm = r · scale: K per scene unit = K_mm · scale, and the density 2πr R_d per scene unit is
  // the density per mm times scale.
  s.k = kPerMm * mmPerUnit;
  for (size_t c = 0; c < 3; ++c) s.rp[c] = autoSplitRadius(tables[c], boundPerMm * mmPerUnit);
  return s;
}

std::vector<glm::vec4> weightedProfile(const std::array<bssrdf::ProfileTable, 3>& tables,
                                       const HybridSplit& split, bool local) {
  const size_t n = tables[0].R.size();
  std::vector<glm::vec4> out(n, glm::vec4(0.0f));
  for (size_t c = 0; c < 3; ++c)
    for (size_t i = 0; i < n; ++i) {
      const double wl = localWeight(tables[c].radius(i), split.rp[c], split.k);
      out[i][int(c)] = static_cast<float>(double(tables[c].R[i]) * (local ? wl : 1.0 - wl));
    }
  return out;
}

std::vector<glm::vec4> localPattern(const std::array<bssrdf::ProfileTable, 3>& tables,
                                    const HybridSplit& split, int circles, int perCircle) {
  if (circles < 1 || perCircle < 1)
    throw ParameterError("local pattern: expected at least one circle of at least one sample");
  const double rMax = tables[0].r_max;
  const size_t n = tables[0].R.size();
  // The channels' normalised cumulative local densities, averaged, on the table grid.
  std::vector<double> cdf(n, 0.0);
  for (size_t c = 0; c < 3; ++c) {
    std::vector<double> f(n, 0.0);
    for (size_t i = 1; i < n; ++i)
      f[i] = f[i - 1] + ringMass(tables[c], split.rp[c], split.k, tables[c].radius(i - 1), tables[c].radius(i));
    if (f[n - 1] > 0.0)
      for (size_t i = 0; i < n; ++i) cdf[i] += f[i] / f[n - 1] / 3.0;
  }
  if (!(cdf[n - 1] > 0.0)) throw ParameterError("local pattern: the local profile is zero everywhere");
  auto inverse = [&](double u) {  // r with cdf(r) = u, linear between grid points
    const auto it = std::lower_bound(cdf.begin(), cdf.end(), u);
    if (it == cdf.begin()) return 0.0;
    if (it == cdf.end()) return rMax;
    const auto i = size_t(it - cdf.begin());
    const double t = (u - cdf[i - 1]) / std::max(cdf[i] - cdf[i - 1], 1e-300);
    return rMax * (double(i - 1) + t) / double(n - 1);
  };
  const double total = kLocalFraction * cdf[n - 1];
  const int zones = circles + 1;
  std::vector<double> bound(size_t(zones) + 1);
  for (int z = 0; z <= zones; ++z) bound[size_t(z)] = inverse(total * z / zones);

  std::vector<glm::vec4> out;
  auto push = [&](double x, double y, double rho, const glm::dvec3& w) {
    out.emplace_back(float(x), float(y), float(rho), 0.0f);
    out.emplace_back(float(w.x), float(w.y), float(w.z), 0.0f);
  };
  // Weight of one of `count` samples at radius rho standing for the zone [a, b].
  auto weights = [&](double a, double b, double rho, int count) {
    glm::dvec3 w(0.0);
    for (size_t c = 0; c < 3; ++c) {
      const double at = tables[c].lookup(rho) * localWeight(rho, split.rp[c], split.k);
      if (at > 0.0) w[int(c)] = ringMass(tables[c], split.rp[c], split.k, a, b) / (count * at);
    }
    return w;
  };
  push(0.0, 0.0, 0.0, weights(0.0, bound[1], 0.0, 1));
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int k = 1; k <= circles; ++k) {
    const double rho = inverse(total * (k + 0.5) / zones);
    const glm::dvec3 w = weights(bound[size_t(k)], bound[size_t(k) + 1], rho, perCircle);
    for (int m = 0; m < perCircle; ++m) {
      const double phi = 2.0 * kPi * m / perCircle + golden * k;
      push(rho * std::cos(phi), rho * std::sin(phi), rho, w);
    }
  }
  return out;
}

}  // namespace translucent::tsis
