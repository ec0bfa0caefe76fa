// SPDX-License-Identifier: GPL-3.0-or-later
// Independent long-double references for the extended-source models (quantized diffusion, photon
// beam diffusion): brute-force composite Gauss-Legendre quadrature of the defining integrals, with
// the improved-diffusion constants recomputed here from the Fresnel formula. Shares nothing with
// src/bssrdf but translucent::fresnelReflectance.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"

namespace translucent::test {

using LD = long double;
inline constexpr LD kPiL = 3.141592653589793238462643383279502884L;

// 20-point Gauss-Legendre on [-1, 1] in long double (Newton on P_20).
struct Gauss20 {
  std::array<LD, 20> x{}, w{};
  Gauss20() {
    const int n = 20;
    for (int i = 0; i < n; ++i) {
      LD z = std::cos(kPiL * (i + 0.75L) / (n + 0.5L)), pp = 1.0L;
      for (int iter = 0; iter < 100; ++iter) {
        LD p1 = 1.0L, p2 = 0.0L;
        for (int j = 1; j <= n; ++j) {
          const LD p3 = p2;
          p2 = p1;
          p1 = ((2.0L * j - 1.0L) * z * p2 - (j - 1.0L) * p3) / j;
        }
        pp = n * (z * p1 - p2) / (z * z - 1.0L);
        const LD dz = p1 / pp;
        z -= dz;
        if (std::fabs(dz) < 1e-19L) break;
      }
      x[static_cast<size_t>(i)] = z;
      w[static_cast<size_t>(i)] = 2.0L / ((1.0L - z * z) * pp * pp);
    }
  }
  LD panel(const std::function<LD(LD)>& f, LD a, LD b) const {
    const LD h = 0.5L * (b - a), m = 0.5L * (a + b);
    LD s = 0.0L;
    for (size_t i = 0; i < x.size(); ++i) s += w[i] * f(m + h * x[i]);
    return s * h;
  }
  // ∫_0^end f with a first panel [0, start] and then panels growing by `ratio`.
  LD graded(const std::function<LD(LD)>& f, LD start, LD end, LD ratio = 1.25L) const {
    LD sum = panel(f, 0.0L, std::min(start, end)), a = start;
    while (a < end) {
      const LD b = std::min(a * ratio, end);
      sum += panel(f, a, b);
      a = b;
    }
    return sum;
  }
};

inline const Gauss20& gauss20() {
  static const Gauss20 g;
  return g;
}

// Improved-diffusion constants (Grosjean D, zb = 2AD, C_φ, C_E) from moments of the exact
// internal Fresnel reflectance, integrated with the substitution μ = μc + (1-μc) s² above the
// critical cosine.
struct ImprovedConstants {
  LD st, alpha, sa, D, str, zb, cphi, ce;
  explicit ImprovedConstants(const ScalarMedium& m) {
    const LD ssp = (1.0L - m.g) * m.sigma_s;
    sa = m.sigma_a;
    st = sa + ssp;
    alpha = ssp / st;
    D = (2.0L * sa + ssp) / (3.0L * st * st);
    str = std::sqrt(sa / D);
    const LD muC = m.eta > 1.0 ? std::sqrt(1.0L - 1.0L / (LD(m.eta) * m.eta)) : 0.0L;
    auto moment = [&](int n) {
      const LD below = std::pow(muC, n + 1) / (n + 1);
      return below + gauss20().graded(
                         [&](LD s) {
                           const LD mu = muC + (1.0L - muC) * s * s;
                           return 2.0L * (1.0L - muC) * s * std::pow(mu, n) *
                                  LD(fresnelReflectance(-double(mu), m.eta));
                         },
                         0.05L, 1.0L, 1.5L);
    };
    const LD c1 = moment(1), c2 = moment(2);
    zb = 2.0L * D * (1.0L + 3.0L * c2) / (1.0L - 2.0L * c1);
    cphi = 0.25L * (1.0L - 2.0L * c1);
    ce = 0.5L * (1.0L - 3.0L * c2);
  }

  // Better-dipole exitance C_φ φ + C_E (-n·E) of a unit isotropic source at depth z, at radius r.
  LD dipole(LD r, LD z) const {
    const LD zv = z + 2.0L * zb;
    const LD dr = std::sqrt(r * r + z * z), dv = std::sqrt(r * r + zv * zv);
    const LD er = std::exp(-str * dr), ev = std::exp(-str * dv);
    const LD phi = (er / dr - ev / dv) / (4.0L * kPiL * D);
    const LD flux = (z * (1.0L + str * dr) * er / (dr * dr * dr) +
                     zv * (1.0L + str * dv) * ev / (dv * dv * dv)) /
                    (4.0L * kPiL);
    return cphi * phi + ce * flux;
  }
};

// Henyey-Greenstein phase function of the scattering cosine.
inline LD henyeyGreensteinL(LD cosScatter, LD g) {
  const LD d = 1.0L + g * g - 2.0L * g * cosScatter;
  return (1.0L - g * g) / (4.0L * kPiL * d * std::sqrt(d));
}

// U(x) = 2π ∫_{μc}^1 p(-μ) T(μ) e^{-x/μ} dμ, x = σt t: the once-scattered light from depth t on the
// beam that leaves uncollided, with μ = μc + (1 - μc) s² for the square-root onset of T at μc.
inline LD uncollidedEscape(LD x, const ScalarMedium& m) {
  const LD muC = m.eta > 1.0 ? std::sqrt(1.0L - 1.0L / (LD(m.eta) * m.eta)) : 0.0L;
  return gauss20().graded(
      [&](LD s) {
        const LD mu = muC + (1.0L - muC) * s * s;
        return 4.0L * kPiL * (1.0L - muC) * s * henyeyGreensteinL(-mu, m.g) *
               (1.0L - LD(fresnelReflectance(-double(mu), m.eta))) * std::exp(-x / mu);
      },
      0.05L, 1.0L, 1.5L);
}

// The steady-state beam integral ∫ σt' e^{-σt' z} α'² [c(z)] [κ] E(r, z) dz at r > 0, with or
// without the photon-beam corrections: the collided fraction c(z) = 1 - σs e^{-σt z} U(σt z) /
// (σs' e^{-σt' z}) (photon_beam.cpp) and κ = 1 - e^{-2σt'(d_r + z)}.
inline LD beamIntegral(LD r, const ScalarMedium& m, bool kappa, bool escape = false) {
  const ImprovedConstants c(m);
  const LD st = LD(m.sigma_a) + m.sigma_s, ss = m.sigma_s, ssp = (1.0L - m.g) * m.sigma_s;
  auto f = [&](LD z) {
    const LD k = kappa ? -std::expm1(-2.0L * c.st * (std::sqrt(r * r + z * z) + z)) : 1.0L;
    const LD e = escape ? 1.0L - ss * std::exp(-(st - c.st) * z) * uncollidedEscape(st * z, m) / ssp
                        : 1.0L;
    return c.st * std::exp(-c.st * z) * c.alpha * c.alpha * e * k * c.dipole(r, z);
  };
  return gauss20().graded(f, 1e-3L * std::min(r, 1.0L / c.st), 80.0L / c.st);
}

// Single scattering of a normally incident pencil beam at r > 0, straight from its definition:
//   ∫_{t_c}^∞ σs e^{-σt (t + d)} p(-t/d) T(t/d) (t/d) / d² dt,  d = √(r² + t²),
// with t = t_c + u² to take the square-root onset of T at the critical angle.
inline LD singleScattering(LD r, const ScalarMedium& m) {
  const LD st = LD(m.sigma_a) + m.sigma_s, ss = m.sigma_s;
  const LD tc = m.eta > 1.0 ? r * std::sqrt(LD(m.eta) * m.eta - 1.0L) : 0.0L;
  auto f = [&](LD u) {
    const LD t = tc + u * u, d = std::sqrt(r * r + t * t), mu = t / d;
    const LD tr = 1.0L - LD(fresnelReflectance(-double(mu), m.eta));
    return 2.0L * u * ss * std::exp(-st * (t + d)) * henyeyGreensteinL(-mu, m.g) * tr * mu / (d * d);
  };
  const LD scale = std::sqrt(std::min(r, 1.0L / st));
  return gauss20().graded(f, 1e-3L * scale, std::sqrt(tc + 80.0L / st) + 1e-30L);
}

// 2π ∫_0^∞ f(r) r dr with panels growing geometrically from r_lo (the part below r_lo is taken as
// one panel) to r_hi.
inline LD radialIntegral(const std::function<LD(LD)>& f, LD r_lo, LD r_hi, LD ratio = 1.25L) {
  return gauss20().graded([&](LD r) { return 2.0L * kPiL * r * f(r); }, r_lo, r_hi, ratio);
}

// Local decay rate -d ln R / dr of a profile at r, by a central difference over ±1% of r.
template <class Profile>
double decayRate(const Profile& p, double r) {
  const double h = 0.01 * r;
  return -(std::log(p.R(r + h)) - std::log(p.R(r - h))) / (2.0 * h);
}

}  // namespace translucent::test
