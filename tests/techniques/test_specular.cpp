// SPDX-License-Identifier: GPL-3.0-or-later
// The shared specular highlight (techniques/common/specular.h) in every technique that offers
// it: the frame with `specular` on minus the frame with it off, on the flat top of a box under a
// tilted sun seen from above, against the closed form of the GGX reflection (Walter et al. 2007;
// techniques::specularRadiance), pixel by pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/registry.h"
#include "render_helpers.h"

namespace translucent::techniques {
namespace {

using pointcloud::testing::TempDir;
using pointcloud::testing::testScene;
using pointcloud::testing::useTestCache;
using pointcloud::testing::writeObj;

class SpecularGpu : public gpu::testing::GpuTest {};

bool hasParameter(const Technique& t, const std::string& name) {
  for (const ParameterInfo& p : t.parameters())
    if (p.name == name) return true;
  return false;
}

TEST_F(SpecularGpu, EveryTechniqueAddsTheClosedFormHighlight) {
  TempDir dir;
  useTestCache();
  const int n = 24;
  // A unit sphere seen from above (orthographic, view height 2.2): at pixel (u, v) of the disc
  // the normal is (u, v, sqrt(1 - u² - v²)); the shading normals interpolated over the
  // icosphere's facets (4 subdivisions) follow it to ~1e-3, which moves a highlight of roughness
  // 0.35 by well under 2%.
  geometry::TriangleMesh sphere = geometry::makeIcosphere(4, 1.0);
  sphere.orientOutwards();
  scene::Scene s = testScene(writeObj(sphere, dir.path() / "sphere.obj"), n);
  const glm::dvec3 l = glm::normalize(glm::dvec3(0.3, 0.1, 1.0));
  s.lights[0].emitter = reference::DirectionalLight{l, 1.5};
  const double roughness = 0.35;
  int tested = 0;
  for (const std::string& name : names()) {
    if (!hasParameter(*make(name), "specular")) continue;  // empirical: its own term (Eq. 3.9)
    SCOPED_TRACE(name);
    // Two fresh instances render their first frame: the Monte Carlo techniques (tsis, lss)
    // rotate their samples from frame to frame, so only first frames share their subsurface part.
    const auto first = [&](bool specular) {
      auto t = make(name);
      if (name == "transfer") t->setParameter("scattering", std::string("single"));
      t->setParameter("roughness", roughness);
      t->setParameter("specular", specular);
      t->prepare(s, gpu::testing::context());
      return t->render({});
    };
    const Frame off = first(false);
    const Frame on = first(true);
    ASSERT_EQ(off.rgb.size(), on.rgb.size());
    int pixels = 0, bad = 0;
    double worst = 0.0, peak = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        // Pixel centre on the disc, y up (rows from the top).
        const double u = ((x + 0.5) / n - 0.5) * 2.2, v = (0.5 - (y + 0.5) / n) * 2.2;
        if (u * u + v * v > 0.8) continue;  // clear of the silhouette (partial pixels, grazing)
        const glm::dvec3 nrm(u, v, std::sqrt(1.0 - u * u - v * v));
        const double expected = specularRadiance(nrm, {0.0, 0.0, 1.0}, l, 1.5, roughness, s.medium.eta);
        peak = std::max(peak, expected);
        for (int c = 0; c < 3; ++c) {
          const size_t i = (size_t(y) * n + size_t(x)) * 3 + size_t(c);
          const double got = double(on.rgb[i]) - double(off.rgb[i]);
          worst = std::max(worst, std::abs(got - expected) / std::max(expected, 1e-3));
          bad += std::abs(got - expected) > 0.02 * expected + 1e-5;
          ++pixels;
        }
      }
    std::printf("%s: specular within %.3g%% of the closed form over %d pixel-channels\n", name.c_str(),
                100.0 * worst, pixels);
    EXPECT_EQ(bad, 0);
    EXPECT_GT(peak, 0.01);  // the highlight is in view (F ≈ 2% near normal incidence)
    EXPECT_GT(pixels, 600);
    ++tested;
  }
  EXPECT_GE(tested, 7);  // pointcloud, tsis, tsm, lss, splatting, shah, transfer
}

}  // namespace
}  // namespace translucent::techniques
