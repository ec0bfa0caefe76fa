// SPDX-License-Identifier: GPL-3.0-or-later
// Per-point profiles at texture resolution (material/profile_atlas.h; the splatting and point-cloud
// techniques' profile_storage texture): a 3D checker of Marble and Skin1 whose cells (1.5 mm) are smaller
// than the triangles of a coarse sphere (an icosphere of 320 triangles, edges ~2.7 mm) is
// resolved by the profiles kept in a texture over the surface atlas and blurred by those kept at
// the 162 vertices; both measured against the model reference, which evaluates Eq. 8 with every
// sample's and camera hit's own medium (model_reference.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <glm/geometric.hpp>

#include "translucent/compare/compare.h"
#include "translucent/compare/compare_run.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"

namespace translucent::analysis {
namespace {

TEST(ProfileTexture, ACheckerFinerThanTheMeshIsResolvedByTheTexture) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("translucent-profile-texture-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    const geometry::TriangleMesh m = geometry::makeIcosphere(2, 0.5);
    ASSERT_EQ(m.triangleCount(), 320u);
    std::ofstream f(dir / "sphere.obj");
    f.precision(17);
    for (const auto& p : m.positions) f << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (const auto& p : m.positions) {
      const glm::dvec3 n = glm::normalize(p);
      f << "vn " << n.x << ' ' << n.y << ' ' << n.z << '\n';
    }
    for (const auto& t : m.triangles)
      f << "f " << t.x + 1 << "//" << t.x + 1 << ' ' << t.y + 1 << "//" << t.y + 1 << ' ' << t.z + 1
        << "//" << t.z + 1 << '\n';
  }
  // A sphere of 5 mm radius; a cache folder of its own (atlases), removed with the folder.
  ::setenv("TRANSLUCENT_CACHE_DIR", (dir / "cache").c_str(), 1);
  const scene::Scene s = scene::parseScene(R"({
    "mesh": {"file": "sphere.obj", "normalize": false},
    "material": {"type": "checker", "cell": 1.5, "media": [{"preset": "Marble"}, {"preset": "Skin1"}],
                 "eta": 1.3, "scale": 10, "model": "dipole"},
    "lights": [{"type": "directional", "direction": [-0.4, 1.0, 0.6], "irradiance": 1.0}],
    "camera": {"type": "pinhole", "position": [0.9, 0.7, 1.2], "look_at": [0, 0, 0],
               "up": [0, 1, 0], "fov": 40, "width": 48, "height": 36}})",
                                           dir, "test scene");
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  ReferenceRequest request;
  request.kind = ReferenceKind::Model;
  request.count = 100000;
  request.seed = 1;
  request.threads = 2;
  const Reference ref = computeReference(s, mesh, request);
  const Masks masks = compareMasks(s, mesh, ref.coverage);
  ASSERT_GT(masks.interiorPixels(), 400u);

  gpu::Context gl;
  for (const char* technique : {"splatting", "pointcloud"}) {
    double error[2] = {0.0, 0.0};
    const char* storage[2] = {"vertex", "texture"};
    for (int i = 0; i < 2; ++i) {
      const std::string spec = std::string(technique) + ":profile_storage=" + storage[i];
      auto t = makeTechniqueSpec(spec, &s);
      t->prepare(s, gl);
      const TimedRender r = renderTimed(*t, spec, s, 0, 0);
      const Metrics m = compareImages(r.images.exitance, ref.exitance, masks.interior);
      error[i] = m.rel_rmse;
      std::printf("%s, profiles %s: relative RMSE %.4f, bias %+.4f against the model\n", technique,
                  i == 0 ? "at the vertices" : "in the texture", m.rel_rmse, m.bias);
      if (i == 1) {
        bool noted = false;
        for (const auto& n : r.notes)
          noted = noted || n.find("256² texture over the surface atlas") != std::string::npos;
        EXPECT_TRUE(noted) << technique;
      }
    }
    // Measured here: splatting 14.5% at the vertices, 4.1% in the texture; the point cloud (its
    // shading points' profiles; its samples carry their own) 11.8% and 4.6%. The rest is the
    // techniques' own error (irradiance, Eq. 8 between interpolated profiles, the hierarchy).
    EXPECT_LT(error[1], 0.07) << technique;
    EXPECT_LT(error[1], 0.5 * error[0]) << technique;
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

}  // namespace
}  // namespace translucent::analysis
