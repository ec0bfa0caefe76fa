// Setups with published or analytic answers, shared by the CPU and GPU tracers' tests.
#pragma once

#include <cmath>

#include "optics/fresnel.h"
#include "reference/slab.h"

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
