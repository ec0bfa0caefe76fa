// SPDX-License-Identifier: GPL-3.0-or-later
// Open meshes (issue 14 §5): the point-cloud technique renders them (points need no interior),
// the techniques that need one refuse them naming the file and the technique that would do.
// Lit and seen from above, a box without its bottom face renders as the closed box: no light
// reaches the side or bottom faces (n·L = 0 or unlit), so only the top face's points carry
// irradiance, at the same density in both clouds.
#include <gtest/gtest.h>

#include <cmath>

#include "translucent/optics/presets.h"
#include "render_helpers.h"
#include "translucent/techniques/registry.h"

namespace translucent::techniques {
namespace {

using namespace translucent::pointcloud::testing;

class OpenMeshGpu : public gpu::testing::GpuTest {};

Frame renderWith(const std::string& technique, const scene::Scene& s, int points) {
  auto t = make(technique);
  if (points > 0) t->setParameter("points", points);
  return renderConverged(*t, s);
}

TEST_F(OpenMeshGpu, PointCloudRendersAnOpenBoxAsTheClosedOneOthersRefuseIt) {
  TempDir dir;
  useTestCache();
  geometry::TriangleMesh closed = geometry::makeBox({-0.8, -0.8, -1.6}, {0.8, 0.8, 0.0});
  geometry::TriangleMesh open = closed;
  // Drop the two triangles of the bottom face z = -1.6.
  std::erase_if(open.triangles, [&](const glm::uvec3& t) {
    return open.positions[t.x].z < -1.0 && open.positions[t.y].z < -1.0 &&
           open.positions[t.z].z < -1.0;
  });
  ASSERT_EQ(open.triangles.size() + 2, closed.triangles.size());
  ASSERT_GT(open.openEdgeCount(), 0u);
  scene::Scene s = testScene(writeObj(closed, dir.path() / "closed.obj"), 24);
  s.medium = preset("Skin1").medium();
  s.medium.scale = 20.0;  // ℓd ≲ 0.2 units: the 1.6-unit box is optically deep
  // Areas: closed 2·1.6² + 4·1.6·1.6 = 15.36, open 12.8: the same point density.
  const Frame a = renderWith("pointcloud", s, 30000);
  s.mesh_file = writeObj(open, dir.path() / "open.obj");
  const Frame b = renderWith("pointcloud", s, 25000);
  bool noted = false;
  for (const auto& n : b.notes) noted = noted || n.find("the mesh is open") != std::string::npos;
  EXPECT_TRUE(noted);
  // The central 12 × 12 pixels (1.1 × 1.1 units of the 1.6-unit top face).
  double sa = 0.0, sb = 0.0;
  for (int y = 6; y < 18; ++y)
    for (int x = 6; x < 18; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t i = size_t(3 * (y * 24 + x) + c);
        sa += double(a.rgb[i]);
        sb += double(b.rgb[i]);
      }
  ASSERT_GT(sa, 0.0);
  // Two independent clouds of the same density: their discretisation differs by ~1%.
  EXPECT_NEAR(sb / sa, 1.0, 0.03);
  RecordProperty("open_over_closed", std::to_string(sb / sa));
  try {
    (void)renderWith("tsm", s, 0);
    ADD_FAILURE() << "tsm rendered an open mesh";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("open.obj"), std::string::npos) << what;
    EXPECT_NE(what.find("pointcloud technique renders open meshes"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace translucent::techniques
