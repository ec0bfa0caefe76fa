// SPDX-License-Identifier: GPL-3.0-or-later
// Pieces the sphere-integration tests share: Gauss-Legendre quadrature for the independent
// reference integrals, and integrator options.
#pragma once

#include <cstdint>

#include "translucent/optics/quadrature.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::reference::test_support {

// ∫_a^b f by `panels` 8-point Gauss-Legendre panels.
template <class F>
double gauss(F&& f, double a, double b, int panels) {
  double sum = 0.0;
  const double h = (b - a) / panels;
  for (int p = 0; p < panels; ++p) {
    const double mid = a + (p + 0.5) * h;
    for (int k = 0; k < 8; ++k) sum += 0.5 * h * kGauss8W[k] * f(mid + 0.5 * h * kGauss8X[k]);
  }
  return sum;
}

// ∫_0^π ring(θ') dθ' on 400 one-node-panel Gauss-Legendre panels graded towards 0 (θ'_i = π
// (i/400)²), where the integrands of the sphere tests peak (the profile at x_o).
template <class F>
double gradedPolar(F&& ring) {
  constexpr double kPi = 3.14159265358979323846;
  double sum = 0.0;
  const int panels = 400;
  for (int i = 0; i < panels; ++i) {
    const double a = kPi * (static_cast<double>(i) / panels) * (static_cast<double>(i) / panels);
    const double b = kPi * (static_cast<double>(i + 1) / panels) * (static_cast<double>(i + 1) / panels);
    sum += gauss(ring, a, b, 1);
  }
  return sum;
}

// Two threads, the given sampler and seed.
inline IntegrationOptions withSampling(SurfaceSampling sampling, uint64_t seed = 1) {
  IntegrationOptions o;
  o.sampling = sampling;
  o.seed = seed;
  o.threads = 2;
  return o;
}

}  // namespace translucent::reference::test_support
