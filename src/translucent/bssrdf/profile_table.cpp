// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/profile_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace translucent::bssrdf {

double ProfileTable::lookup(double r) const {
  if (r < 0.0 || r > r_max || R.size() < 2) return 0.0;
  const double x = r / r_max * double(R.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), R.size() - 2);
  const double t = x - double(i);
  return (1.0 - t) * double(R[i]) + t * double(R[i + 1]);
}

ProfileTable tabulate(const RadialProfile& profile, size_t n, double fraction) {
  if (n < 2) throw std::invalid_argument("tabulate: a profile table needs at least 2 entries");
  ProfileTable t;
  t.rd = profile.Rd();
  t.r_max = profile.radiusForFraction(fraction);
  t.R.resize(n);
  t.r_times_R.resize(n);
  t.cdf.resize(n);
  double cumulative = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double r = t.radius(i);
    double value = profile.R(r), rValue = r * value;
    if (i == 0 && !std::isfinite(value)) {
      // Profiles with a 1/r singularity at the source (normalized diffusion, beam integrals):
      // r·R has a finite limit there; R[0] holds R a quarter step out so a texture stays finite.
      const double eps = 1e-7 * t.radius(1);
      rValue = eps * profile.R(eps);
      value = profile.R(0.25 * t.radius(1));
    } else if (i == 0 && isClampedSingularity(value, profile.R(0.25 * t.radius(1)))) {
      // The same singularity with r clamped (1/max(r, 1e-6)): R(0) is finite but huge, and the
      // first texel would spread it over the whole first step (a speckled render).
      const double quarter = 0.25 * t.radius(1);
      value = profile.R(quarter);
      rValue = quarter * value;  // r·R is ~constant near a 1/r singularity
    }
    t.R[i] = static_cast<float>(value);
    t.r_times_R[i] = static_cast<float>(rValue);
    if (i > 0) cumulative += integratePanel(profile, t.radius(i - 1), r);
    t.cdf[i] = static_cast<float>(std::min(1.0, cumulative / t.rd));
  }
  return t;
}

}  // namespace translucent::bssrdf
