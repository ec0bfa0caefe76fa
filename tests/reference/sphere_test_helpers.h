// Pieces the sphere-integration tests share: Gauss-Legendre quadrature for the independent
// reference integrals, and integrator options.
#pragma once

#include <cstdint>

#include "reference/sphere_integration.h"

namespace translucent::reference::test_support {

inline constexpr double kGLx[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                   -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                   0.7966664774136267,  0.9602898564975363};
inline constexpr double kGLw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                   0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                   0.2223810344533745, 0.1012285362903763};

// ∫_a^b f by `panels` 8-point Gauss-Legendre panels.
template <class F>
double gauss(F&& f, double a, double b, int panels) {
  double sum = 0.0;
  const double h = (b - a) / panels;
  for (int p = 0; p < panels; ++p) {
    const double mid = a + (p + 0.5) * h;
    for (int k = 0; k < 8; ++k) sum += 0.5 * h * kGLw[k] * f(mid + 0.5 * h * kGLx[k]);
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
