// SPDX-License-Identifier: GPL-3.0-or-later
// The single-scattering part of the searchlight problem in closed form (up to a deterministic
// quadrature): what the tracers' order split (slab.h: ScatteringOrder::Single) must reproduce.
//
// A pencil beam enters a semi-infinite medium along the normal (weight 1 - Rsp, not included
// here: everything below is per unit flux entering). Its first collision lies at depth z with
// density σt e^{-σt z}; it scatters with probability α into direction ω (Henyey-Greenstein about
// the beam, +z), and is single-scattered light when it flies straight back to the surface (no
// second collision: e^{-σt z/μ}, μ the cosine of ω with the upward normal) and is transmitted
// there (1 - F(μ), Fresnel from inside). A photon reflected at the surface flies down again and
// must collide before it can come back, so it is never single-scattered light. Hence (seed
// Eq. 2.39 integrated over the surface, with p = hg(cos)/(2π))
//     R1 = α ∫_0^1 hg(-μ) (1 - F(μ)) μ/(1 + μ) dμ                       (z integrated out)
// and the share leaving through the annulus a <= r < b, where a photon scattered at depth z in
// direction μ leaves at r = z tan θ:
//     R1[a, b) = α ∫_0^∞ e^{-u} du ∫_{μ(u, b)}^{μ(u, a)} hg(-μ) (1 - F(μ)) e^{-u/μ} dμ,
// u = σt z, μ(u, r) = u / sqrt(u² + (σt r)²). For isotropic scattering and η = 1, R1 = α(1 - ln 2)/2.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>

#include "translucent/optics/fresnel.h"
#include "translucent/optics/quadrature.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/slab.h"

namespace translucent::reference::test_support {

// The semi-infinite medium of the single-scattering checks: α = 0.8, σt = 2, forward scattering
// (g = 0.5) under a Fresnel boundary (η = 1.3).
inline SlabSetup singleScatteringHalfSpace() {
  SlabSetup s;
  s.sigma_a = 0.4;
  s.sigma_s = 1.6;
  s.g = 0.5;
  s.n_inside = 1.3;
  return s;
}

// ∫_lo^hi f by `panels` panels of 8-point Gauss-Legendre.
inline double gaussPanels(const std::function<double(double)>& f, double lo, double hi, int panels) {
  double sum = 0.0;
  const double h = (hi - lo) / panels;
  for (int p = 0; p < panels; ++p) {
    const double mid = lo + (p + 0.5) * h;
    for (int k = 0; k < 8; ++k) sum += kGauss8W[k] * f(mid + 0.5 * h * kGauss8X[k]);
  }
  return 0.5 * h * sum;
}

// ∫_lo^hi f as gaussPanels, with a panel edge at `kink` when it lies inside (where f's
// derivative jumps: the critical angle of total internal reflection).
inline double gaussPanelsSplit(const std::function<double(double)>& f, double lo, double hi,
                               double kink, int panels) {
  if (!(kink > lo && kink < hi)) return gaussPanels(f, lo, hi, panels);
  return gaussPanels(f, lo, kink, panels) + gaussPanels(f, kink, hi, panels);
}

// The cosine below which light inside cannot leave (total internal reflection; 0 for η <= 1).
inline double criticalCosine(double eta) {
  return eta > 1.0 ? std::sqrt(1.0 - 1.0 / (eta * eta)) : 0.0;
}

// The integrand's angular factor hg(-μ) (1 - F(μ)) for an upward direction μ in (0, 1].
inline double singleExitFactor(double mu, double g, double eta) {
  const double transmitted = eta == 1.0 ? 1.0 : 1.0 - fresnelReflectance(mu, 1.0 / eta);
  return hgCosineDensity(-mu, g) * transmitted;
}

// R1 per unit entering flux.
inline double singleScatteringRd(double albedo, double g, double eta) {
  return albedo * gaussPanelsSplit(
                      [&](double mu) { return singleExitFactor(mu, g, eta) * mu / (1.0 + mu); },
                      0.0, 1.0, criticalCosine(eta), 64);
}

// R1[a, b) per unit entering flux (b = infinity allowed); radii in units of 1/σt times sigma_t.
inline double singleScatteringAnnulus(double albedo, double sigma_t, double g, double eta,
                                      double a, double b) {
  // u = -ln(1 - v) turns e^{-u} du into dv on [0, 1); the μ integral runs in ln μ, where the
  // factor e^{-u/μ} is smooth even for small u.
  auto inner = [&](double v) {
    const double u = -std::log1p(-v);
    const double muHi = a > 0.0 ? u / std::hypot(u, sigma_t * a) : 1.0;
    const double muLo = std::isfinite(b) ? u / std::hypot(u, sigma_t * b) : 0.0;
    const double tHi = std::log(muHi), tLo = std::log(std::max(muLo, 1e-300));
    if (!(tHi > tLo)) return 0.0;
    // Below the critical cosine nothing leaves; far below tHi, e^{-u/μ} μ is below 1e-20.
    const double lo = std::max({tLo, tHi - 60.0, std::log(std::max(criticalCosine(eta), 1e-300))});
    if (!(tHi > lo)) return 0.0;
    return gaussPanels(
        [&](double t) {
          const double mu = std::exp(t);
          return singleExitFactor(mu, g, eta) * std::exp(-u / mu) * mu;
        },
        lo, tHi, 48);
  };
  return albedo * gaussPanels(inner, 0.0, 1.0 - 1e-15, 96);
}

}  // namespace translucent::reference::test_support
