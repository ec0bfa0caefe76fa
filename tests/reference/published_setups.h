// SPDX-License-Identifier: GPL-3.0-or-later
// Setups with published or analytic answers, shared by the CPU and GPU tracers' tests.
#pragma once

#include <cmath>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/slab.h"

namespace translucent::reference::test_support {

// The MCML benchmark slab (Wang, Jacques & Zheng 1995, Table 2): n = 1 everywhere,
// μa = 10/cm, μs = 90/cm, g = 0.75, d = 0.02 cm. Published: Rd = 0.09734 ± 0.00035,
// Tt = 0.66096 ± 0.00020 (van de Hulst: 0.09739, 0.66096); Tu = e^{-2}.
inline SlabSetup mcmlSlab() {
  SlabSetup s;
  s.sigma_a = 10.0;
  s.sigma_s = 90.0;
  s.g = 0.75;
  s.thickness = 0.02;
  return s;
}

// An oblique beam (θ = 60° in air, φ = 0.7) into a finite, strongly forward-scattering slab
// n = 1.5 between air (σa 0.6, σs 0.4, g 0.9, d 0.5): the unscattered light crosses at the
// refracted angle θt and bounces between the faces, each reflecting F = F(cos θt) from inside.
// Its closed forms (geometric series of round trips, τ = σt d / cos θt):
//   transmitted Tu = (1 - Rsp)(1 - F) e^{-τ} / (1 - F² e^{-2τ}),
//   reflected   R0 = (1 - Rsp) F e^{-2τ} (1 - F) / (1 - F² e^{-2τ}).
struct InterreflectingSlab {
  SlabSetup setup;
  double rsp, unscattered_transmittance, unscattered_reflectance;
};
inline InterreflectingSlab interreflectingSlab() {
  InterreflectingSlab c;
  SlabSetup& s = c.setup;
  s.sigma_a = 0.6;
  s.sigma_s = 0.4;
  s.g = 0.9;
  s.thickness = 0.5;
  s.n_inside = 1.5;
  s.theta = 60.0 * 3.14159265358979323846 / 180.0;
  s.phi = 0.7;
  const double cosI = std::cos(s.theta);
  const double cosT = refractedCosine(cosI, 1.5);
  c.rsp = fresnelReflectance(cosI, 1.5);
  const double F = fresnelReflectance(cosT, 1.0 / 1.5);
  const double e1 = std::exp(-s.thickness / cosT), e2 = e1 * e1;
  c.unscattered_transmittance = (1.0 - c.rsp) * (1.0 - F) * e1 / (1.0 - F * F * e2);
  c.unscattered_reflectance = (1.0 - c.rsp) * F * e2 * (1.0 - F) / (1.0 - F * F * e2);
  return c;
}

// 2 ∫0^1 Ft(μ; η) μ dμ: the fraction of a collimated beam's flux on a sphere that enters it
// (the sphere's cross-section πR² sees every incidence cosine μ with density 2μ).
inline double sphereEnteringFraction(double eta) {
  const int n = 20000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double mu = (i + 0.5) / n;
    sum += 2.0 * mu * fresnelTransmittance(mu, eta) / n;
  }
  return sum;
}

}  // namespace translucent::reference::test_support
