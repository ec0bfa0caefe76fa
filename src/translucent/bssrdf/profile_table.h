// SPDX-License-Identifier: GPL-3.0-or-later
// 1D tables of a radial profile, sized from its effective range, ready to become GPU textures:
// R(r), r·R(r) and the normalised cumulative 2π∫0^r R r' dr' / Rd on a uniform radius grid.
#pragma once

#include <vector>

#include "translucent/bssrdf/profile.h"

namespace translucent::bssrdf {

struct ProfileTable {
  double r_max = 0.0;  // radius of the last entry [length]
  double rd = 0.0;     // total diffuse reflectance of the profile
  std::vector<float> R;         // R(r_i), r_i = r_max · i / (n - 1) (R[0]: see tabulate)
  std::vector<float> r_times_R; // r_i R(r_i)
  std::vector<float> cdf;       // fraction of Rd within r_i (cdf[0] = 0)

  size_t size() const { return R.size(); }
  double radius(size_t i) const { return r_max * static_cast<double>(i) / double(R.size() - 1); }
  // Linear interpolation of R at r (0 beyond r_max).
  double lookup(double r) const;
};

// Tabulates `profile` on n >= 2 entries up to the radius holding `fraction` of Rd
// (default 0.999: the 95% effective range is well inside). Every entry is finite: where R
// diverges at r = 0, R[0] holds R(Δr/4) and r_times_R[0] the finite limit of r·R.
// A profile clamped at the source (1/max(r, 1e-6)) is treated as the singular one it stands for:
// R(0) more than kClampedRatio times R a quarter step out.
ProfileTable tabulate(const RadialProfile& profile, size_t n = 1024, double fraction = 0.999);

// Whether a finite R(0) is the clamped value of a singularity: far above R(Δr/4), which a
// profile that is smooth at the source (the dipoles) stays close to.
inline constexpr double kClampedRatio = 4.0;
inline bool isClampedSingularity(double r0_value, double quarter_step_value) {
  return quarter_step_value > 0.0 && r0_value > kClampedRatio * quarter_step_value;
}

}  // namespace translucent::bssrdf
