// SPDX-License-Identifier: GPL-3.0-or-later
// The walk from surface entries (src/translucent/reference/surface_transfer.h) and its exit
// records' internal-reflection mark (ExitRecord::reflected), against closed forms in a box whose
// opposite faces are parallel: a narrow beam at normal incidence in a medium that practically
// does not scatter meets the far face, and every face after it, at normal incidence.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <mutex>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/surface_transfer.h"

namespace translucent::reference {
namespace {

struct Sums {
  // [reflected][order]: exiting weight per entered flux
  std::array<std::array<double, kScatteringOrders>, 2> w{};
};

Sums traceBeam(double eta, double sigmaS, uint64_t photons) {
  const auto box = geometry::makeBox({-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0});
  const MeshBody body(box, "box");
  ScalarMedium m;
  m.sigma_a = 0.0;
  m.sigma_s = sigmaS;
  m.eta = eta;
  const std::vector<ScalarMedium> channels{m};
  SurfaceEntry e;
  e.position = {0.0, 0.0, 1.0};
  e.normal = {0.0, 0.0, 1.0};
  e.radius = 1e-3;
  SurfaceTransferOptions o;
  o.photons = photons;
  o.seed = 3;
  o.threads = 2;
  Sums s;
  std::mutex lock;  // one entry: its exits come from one thread, the lock only documents it
  const SurfaceTransferStats stats = traceSurfaceEntries(
      body, channels, nullptr, std::span<const SurfaceEntry>(&e, 1), o,
      [&](size_t, const ExitRecord& x) {
        const std::lock_guard<std::mutex> g(lock);
        s.w[x.reflected ? 1 : 0][static_cast<size_t>(x.order)] += x.weight;
      });
  EXPECT_EQ(stats.entries_done, 1u);
  for (auto& row : s.w)
    for (double& v : row) v /= stats.entered[0][0];
  return s;
}

// η = 2, almost no scattering (σs 10⁻⁶ over a 2-unit path): the far face passes Ft(0) = 1 - R0,
// R0 = ((η - 1)/(η + 1))² = 1/9, without a reflection; everything else is reflected first and,
// with no absorption, leaves later, marked. Bounds: 5 binomial standard errors.
TEST(SurfaceTransfer, ExitsAfterAnInternalReflectionAreMarked) {
  const uint64_t photons = 1u << 16;
  const Sums s = traceBeam(2.0, 1e-6, photons);
  const double r0 = (1.0 / 3.0) * (1.0 / 3.0);
  const double se = std::sqrt(r0 * (1.0 - r0) / double(photons));
  const auto unscattered = static_cast<size_t>(ScatteringOrder::Unscattered);
  EXPECT_NEAR(s.w[0][unscattered], 1.0 - r0, 5.0 * se);
  EXPECT_NEAR(s.w[1][unscattered], r0, 5.0 * se);
  EXPECT_NEAR(1.0 - fresnelReflectance(1.0, 2.0), 1.0 - r0, 1e-12);
  // The scattered light is 10⁻⁶ of it.
  for (size_t k = 0; k < 2; ++k)
    EXPECT_LT(s.w[k][static_cast<size_t>(ScatteringOrder::Single)] +
                  s.w[k][static_cast<size_t>(ScatteringOrder::Multiple)], 1e-3);
}

// Index-matched (η = 1) there is no reflection at all: nothing is marked, whatever the order.
TEST(SurfaceTransfer, NothingIsMarkedWithoutARefractiveBoundary) {
  const Sums s = traceBeam(1.0, 2.0, 1u << 12);
  double unmarked = 0.0;
  for (size_t k = 0; k < kScatteringOrders; ++k) {
    EXPECT_EQ(s.w[1][k], 0.0) << k;
    unmarked += s.w[0][k];
  }
  EXPECT_NEAR(unmarked, 1.0, 1e-9);  // no absorption: every photon leaves
}

}  // namespace
}  // namespace translucent::reference
