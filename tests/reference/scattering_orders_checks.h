// SPDX-License-Identifier: GPL-3.0-or-later
// Checks of the scattering-order split (slab.h: ScatteringOrder) shared by the CPU and GPU tests
// of the mesh tracer.
#pragma once

#include <gtest/gtest.h>

#include <cmath>

#include "translucent/reference/mesh_tracer.h"
#include "mesh_test_scenes.h"

namespace translucent::reference::test_support {

// A pencil beam along -z through the three cubes in a row (mesh_test_scenes.h), η = 1, σa 0.1,
// σs 0.3, g = 0.5, seen from the side; the images split by order.
inline MeshPathTracer threeCubesTracer(TracerOptions options) {
  options.split_orders = true;
  const Light beam{BeamLight{{0.05, 0.1, 5.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
  return MeshPathTracer(threeCubes(), ScalarMedium{0.1, 0.3, 0.5, 1.0}, {beam},
                        orthographic({3.0, 0.0, 0.0}, 5.0, 16), 10.0, options);
}

// After `photons` photons: a photon leaves each cube it crosses unscattered (no Fresnel at
// η = 1), so the unscattered exits sum to T + T² + T³, T = e^{-σt}, exactly on average; a photon
// that crossed a gap and scattered in the next cube leaves that cube as single or multiple light
// (a later exit of the same photon in another order). The orders' fluxes and images add up to
// the totals (to rounding), and every order is present.
inline void expectThreeCubesOrders(MeshPathTracer& t, uint64_t photons) {
  const TransportStats st = t.addPass(photons);
  const uint64_t n = st.photons[0];
  const double T = std::exp(-0.4);
  auto byOrder = [&](ScatteringOrder o) {
    return st.exited_by_order[static_cast<size_t>(o)][0].estimate(n);
  };
  const Estimate u = byOrder(ScatteringOrder::Unscattered);
  EXPECT_NEAR(u.value, T + T * T + T * T * T, 4.0 * u.std_error) << u.value << " ± " << u.std_error;
  EXPECT_LT(u.std_error, 0.01);
  double sum = 0.0;
  for (ScatteringOrder o : kAllScatteringOrders) {
    EXPECT_GT(byOrder(o).value, 0.0) << toString(o);
    sum += byOrder(o).value;
  }
  EXPECT_NEAR(sum, st.exited[0].estimate(n).value, 1e-12);
  const McImage& total = t.images().exitance;
  double orders[3] = {0.0, 0.0, 0.0};
  for (int y = 0; y < total.height(); ++y)
    for (int x = 0; x < total.width(); ++x) {
      double pixel = 0.0;
      for (ScatteringOrder o : kAllScatteringOrders) {
        const double v = t.orderImages(o).exitance.pixel(x, y, 0).value;
        pixel += v;
        orders[static_cast<size_t>(o)] += v;
      }
      EXPECT_NEAR(pixel, total.pixel(x, y, 0).value, 1e-12 * (1.0 + total.pixel(x, y, 0).value));
    }
  // Unscattered light leaves along the beam, edge-on to this camera; the sides glow with the rest.
  EXPECT_GT(orders[1], 0.0);
  EXPECT_GT(orders[2], 0.0);
}

}  // namespace translucent::reference::test_support
