// SPDX-License-Identifier: GPL-3.0-or-later
// The flat-slab set-up that the model reference's tests share (test_model_reference.cpp,
// test_environment.cpp): a wide box whose top face z = 0 is seen from straight above through a
// window at the centre, in a medium many diffusion lengths across, so that the top face is a half
// space to the profile: B is a known constant (e.g. Ft(η, 1) E Rd for a directional light along
// the normal) in every pixel, up to the pruned tail and the table's error (reported, added as
// bias) and the noise.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "translucent/geometry/mesh.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/model_reference.h"

namespace translucent::reference::testing {

// A medium per scene unit with a short diffusion length (ℓd ≈ 0.07 .. 0.15 units), so that the
// test geometry is many diffusion lengths across.
inline Medium shortRangeMedium() {
  Medium m;
  m.sigma_a = {0.5, 1.0, 2.0};
  m.sigma_s = {30.0, 40.0, 50.0};
  m.g = 0.0;
  m.eta = 1.3;
  m.scale = 1.0;
  return m;
}

inline geometry::TriangleMesh flatSlab() { return geometry::makeBox({-1.8, -1.8, -0.5}, {1.8, 1.8, 0.0}); }

// Orthographic, straight down onto the centre of the top face.
inline Camera flatSlabCamera(double viewHeight = 1.2, int pixels = 4) {
  Camera cam;
  cam.projection = Camera::Projection::Orthographic;
  cam.position = {0.0, 0.0, 3.0};
  cam.look_at = {0.0, 0.0, 0.0};
  cam.view_height = viewHeight;
  cam.width = cam.height = pixels;
  return cam;
}

// Every pixel within 4 standard errors (plus the bias bound) of expected[c], and the pixels' mean
// within 4 of its own. The pixels are 0.3 units apart, ~10 reduced mean free paths, where the
// noise comes from (the profile's peak): their errors are nearly independent, so their mean is
// tested to ~se/4, with a factor 1.5 for the correlation the shared tails leave; that standard
// error must be below `power` x expected (the test can detect an error of that size).
inline void expectFlatSlab(const ModelReferenceImages& img, const Camera& cam,
                           const std::array<double, 3>& expected, double power,
                           const std::string& what) {
  // Every pixel is more than r_max inside the top face's edges.
  ASSERT_LT(img.prune_radius + std::sqrt(2.0) * 0.5 * cam.view_height, 1.8)
      << what << ": the slab is too small for this medium";
  const size_t n = size_t(cam.width * cam.height);
  for (size_t c = 0; c < 3; ++c) {
    const double bias = (img.tail_fraction[c] + img.table_error) * expected[c];
    double sum = 0.0, var = 0.0;
    for (size_t p = 0; p < n; ++p) {
      ASSERT_EQ(img.coverage[p], 1.0f);
      const double b = img.exitance[3 * p + c], se = img.exitance_se[3 * p + c];
      EXPECT_GT(se, 0.0);
      EXPECT_NEAR(b, expected[c], 4.0 * se + bias)
          << what << " channel " << c << " pixel " << p << " se " << se;
      sum += b;
      var += se * se;
    }
    const double seMean = 1.5 * std::sqrt(var) / double(n);
    EXPECT_LT(seMean, power * expected[c]) << what << " channel " << c << ": the test has power";
    EXPECT_NEAR(sum / double(n), expected[c], 4.0 * seMean + bias) << what << " channel " << c;
  }
}

}  // namespace translucent::reference::testing
