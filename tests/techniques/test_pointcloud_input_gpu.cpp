// SPDX-License-Identifier: GPL-3.0-or-later
// A point-cloud file as the scene's mesh (the explorer paper renders point-cloud files of
// positions, normals and areas directly): the point-cloud technique takes the file's points as
// its samples and draws the surface reconstructed through them, so a file written from a mesh
// renders as that mesh does when the technique samples the same points itself. The techniques
// that need triangles render the reconstructed surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render_helpers.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/techniques/registry.h"

namespace translucent::techniques {
namespace {

using namespace translucent::pointcloud::testing;

class PointCloudInputGpu : public gpu::testing::GpuTest {};

constexpr const char* kBunny = "/usr/share/glmark2/models/bunny.obj";

// The bunny as in data/scenes/bunny.json: normalised, Marble at 25 mm per unit, lit from the
// upper left, 64×48 pixels.
scene::Scene bunnyScene(const std::filesystem::path& file) {
  scene::Scene s = testScene(file, 64);
  s.mesh_normalize = true;
  s.medium = Medium::fromReduced({0.0021, 0.0041, 0.0071}, {2.19, 2.62, 3.00}, 0.0, 1.5, 25.0);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(-0.3, 0.9, -0.6)), 5.0};
  s.camera.projection = reference::Camera::Projection::Pinhole;
  s.camera.position = {0.15, 0.2, 2.1};
  s.camera.fov = 35.0;
  s.camera.height = 48;
  return s;
}

TEST_F(PointCloudInputGpu, AFileOfAMeshsPointsRendersAsTheMesh) {
  TempDir dir;
  useTestCache();
  constexpr int kPoints = 20000;
  // The points the technique samples on the placed bunny (same count, seed and method), written
  // from the bunny as read: normalisation is a similarity, so the samples are the same points.
  geometry::SamplingOptions opt;
  opt.count = kPoints;
  opt.seed = 1;
  const auto file = dir.path() / "bunny-points.ply";
  geometry::writePointCloudPly(geometry::samplePointCloud(geometry::loadMesh(kBunny), opt), file);

  auto fromMesh = make("pointcloud");
  fromMesh->setParameter("points", kPoints);
  const Frame a = renderConverged(*fromMesh, bunnyScene(kBunny));
  auto fromFile = make("pointcloud");
  const Frame b = renderConverged(*fromFile, bunnyScene(file));
  bool noted = false;
  for (const auto& n : b.notes)
    noted = noted || n.find("the 20000 points of the mesh file") != std::string::npos;
  EXPECT_TRUE(noted);

  // Coverage: the reconstructed silhouette is the mesh's within a pixel here and there.
  size_t both = 0, one = 0;
  double diff2 = 0.0, ref2 = 0.0, sa = 0.0, sb = 0.0;
  for (size_t p = 0; p < a.rgb.size() / 3; ++p) {
    const bool ca = a.rgb[3 * p] + a.rgb[3 * p + 1] + a.rgb[3 * p + 2] > 0.0f;
    const bool cb = b.rgb[3 * p] + b.rgb[3 * p + 1] + b.rgb[3 * p + 2] > 0.0f;
    if (ca != cb) ++one;
    if (!(ca && cb)) continue;
    ++both;
    for (int c = 0; c < 3; ++c) {
      const double x = b.rgb[3 * p + size_t(c)], y = a.rgb[3 * p + size_t(c)];
      diff2 += (x - y) * (x - y);
      ref2 += y * y;
      sa += y;
      sb += x;
    }
  }
  ASSERT_GT(both, 600u);
  EXPECT_LE(one, both / 50) << one << " pixels covered by one image only, " << both << " by both";
  // The same irradiance samples: the images differ only where the G-buffer does (the
  // reconstructed triangles and their interpolated normals against the mesh's). Measured here:
  // relative RMSE 3.5%, mean ratio 1.003, 4 of 902 pixels covered by one image only.
  std::printf("file vs mesh: relative RMSE %.4f, mean ratio %.4f, %zu of %zu pixels covered by "
              "one image only\n", std::sqrt(diff2 / ref2), sb / sa, one, both);
  EXPECT_LT(std::sqrt(diff2 / ref2), 0.06);
  EXPECT_NEAR(sb / sa, 1.0, 0.015);

  // A technique that needs triangles (and a closed surface) renders the reconstruction.
  auto tsis = make("tsis");
  const Frame c = renderConverged(*tsis, bunnyScene(file));
  double sc = 0.0;
  for (float v : c.rgb) sc += double(v);
  EXPECT_GT(sc, 0.5 * sa);
}

}  // namespace
}  // namespace translucent::techniques
