// SPDX-License-Identifier: GPL-3.0-or-later
// The exit-convention study (analysis/exit_convention_study.h): its pixel selection on the lit
// sphere against the analytic n·v, and its bookkeeping on images whose cone radiance is a known
// multiple of the cone-averaged Jensen law.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "translucent/analysis/exit_convention_study.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/sphere.h"

namespace translucent::analysis {
namespace {

using bssrdf::ExitConvention;

// On the unit sphere seen orthographically, the centre of pixel (i, j) at image-plane distance r
// from the axis sees n·v = sqrt(1 - r²). Kept pixels carry that value (to the ray-sphere
// rounding); a pixel is dropped exactly when one of its five samples misses or has n·v <= 0.5,
// so every pixel whose whole square lies at r < 0.85 (n·v > 0.527) is kept and none with its
// centre at r > sqrt(0.75).
TEST(ExitConventionStudy, InteriorPixelsOfTheSphereHaveTheAnalyticCosine) {
  reference::SphereScene s;
  s.width = s.height = 40;
  const reference::Camera cam = s.camera();
  const reference::CameraModel model(cam);
  const reference::SphereBody body(1.0);
  const auto cosines = interiorViewCosines(body, model);
  ASSERT_EQ(cosines.size(), 1600u);
  const double pixel = cam.view_height / cam.height;
  int kept = 0;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const double x = (i + 0.5 - 20.0) * pixel, y = (20.0 - j - 0.5) * pixel;
      const double r = std::hypot(x, y);
      const double mu = cosines[size_t(j) * 40 + size_t(i)];
      if (mu > 0.0) {
        ++kept;
        EXPECT_NEAR(mu, std::sqrt(1.0 - r * r), 1e-9) << i << ", " << j;
        EXPECT_LT(r, std::sqrt(0.75));
      }
      if (r + pixel * std::sqrt(0.5) < 0.85) {
        EXPECT_GT(mu, 0.0) << i << ", " << j;
      }
    }
  EXPECT_GT(kept, 800);  // ~π 0.866² / pixel² ≈ 860, less the rim
}

// Images built so that cone = c · κ(μ) · radiance in every pixel: the study must give ratio c for
// Jensen and c (1 - 2 C1_ext) for normalized in every bin (κ tabulated: 1e-6), count the pixels
// of each bin, and skip excluded pixels.
TEST(ExitConventionStudy, RatiosOfKnownImages) {
  const int w = 30, h = 10;
  const double eta = 1.3, coneDeg = 15.0, cone = coneDeg * std::numbers::pi / 180.0, c = 1.07;
  reference::CameraImages images;
  images.exitance = reference::McImage(w, h, 1, reference::McImage::Statistics::PerPhoton);
  images.radiance = images.cone_radiance = images.exitance;
  std::vector<double> mu(size_t(w) * size_t(h), 0.0);
  for (int p = 0; p < w * h; ++p) {
    if (p % 7 == 3) continue;  // excluded pixels (μ = 0) hold values that must not count
    mu[size_t(p)] = 0.5 + 0.5 * (p + 0.5) / (w * h);
  }
  for (int p = 0; p < w * h; ++p) {
    const double m = mu[size_t(p)] > 0.0 ? mu[size_t(p)] : 0.7;
    const double r = 1.0 + 0.3 * std::sin(p);  // any positive radiance pattern
    const double kappa = bssrdf::coneAveragedExitRadianceFactor(ExitConvention::Jensen, eta, m, cone) /
                         bssrdf::exitRadianceFactor(ExitConvention::Jensen, eta, m);
    const double coneValue = mu[size_t(p)] > 0.0 ? c * kappa * r : 100.0 * r;
    images.radiance.add(size_t(p), r);
    images.cone_radiance.add(size_t(p), coneValue);
    images.exitance.add(size_t(p), r * std::numbers::pi);
  }
  for (auto* img : {&images.exitance, &images.radiance, &images.cone_radiance}) img->addCount(0, 1000);
  const double etas[] = {eta};
  const auto study = studyExitConventions(images, mu, etas, coneDeg);
  ASSERT_EQ(study.size(), 1u);
  const double norm = bssrdf::diffuseTransmittanceFromOutside(eta);
  size_t total = 0;
  for (const auto& bin : study[0].bins) {
    ASSERT_GT(bin.pixels, 0u);
    total += bin.pixels;
    EXPECT_NEAR(bin.ratio[0].value, c, 1e-6 * c) << bin.cos_lo;
    EXPECT_NEAR(bin.ratio[1].value, c * norm, 1e-6 * c) << bin.cos_lo;
    EXPECT_GT(bin.ratio[0].std_error, 0.0);
  }
  const size_t expected = size_t(w * h) - size_t((w * h + 3) / 7);
  EXPECT_EQ(total, expected);
  EXPECT_EQ(study[0].all.pixels, expected);
  EXPECT_NEAR(study[0].all.ratio[0].value, c, 1e-6 * c);

  // Bad input names what is wrong.
  ExitConventionStudyOptions bad;
  bad.cos_edges = {0.5, 0.4};
  EXPECT_THROW((void)studyExitConventions(images, mu, etas, coneDeg, bad), ParameterError);
  EXPECT_THROW((void)studyExitConventions(images, mu, etas, 0.0), ParameterError);
  EXPECT_THROW((void)studyExitConventions(images, std::vector<double>(3, 0.7), etas, coneDeg),
               ParameterError);
}

}  // namespace
}  // namespace translucent::analysis
