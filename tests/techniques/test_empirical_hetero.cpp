// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical technique on a heterogeneous material (empirical_technique.h, "Heterogeneous
// materials"): K_d scaled per vertex by Rd(local) / Rd(representative).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "translucent/geometry/icosphere.h"
#include "translucent/optics/presets.h"
#include "render_helpers.h"
#include "translucent/techniques/empirical/empirical_technique.h"

namespace translucent::empirical {
namespace {

using gpu::testing::TempDir;
using material::LocalMedium;
using pointcloud::testing::hasPass;
using pointcloud::testing::orbited;
using pointcloud::testing::relativeMaxDifference;
using pointcloud::testing::testScene;
using pointcloud::testing::useTestCache;
using pointcloud::testing::writeObj;

class EmpiricalHeteroGpu : public gpu::testing::GpuTest {};

// Marble where material-space x < 0, Ketchup elsewhere.
class LeftRight final : public material::VolumeField {
 public:
  LocalMedium at(const glm::dvec3& q) const override {
    return LocalMedium::of(preset(q.x < 0.0 ? "marble" : "ketchup").medium());
  }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override { return {10.0, 10.0, 10.0}; }
};

// The scene's medium with LeftRight's two halves as its field.
material::Material leftRight(const scene::Scene& s) {
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium = s.medium;
  m.frame.scale = s.medium.scale;
  m.volume = std::make_shared<LeftRight>();
  m.surface_depth = 0.5;
  return m;
}

// The test sphere (radius 1, 10 mm per unit, orthographic view down −z, 2.2 units high): the
// left half (x < −0.2, a margin of a few triangles) renders exactly as the homogeneous Marble
// (its factor is 1), the right half (x > 0.2) is much redder (Ketchup reflects little green:
// Rd green / Rd red of Ketchup ≈ 0.02 against Marble's ≈ 1).
TEST_F(EmpiricalHeteroGpu, TwoMediaGiveTwoColours) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(4, 1.0), dir.path() / "sphere.obj");
  const int n = 48;
  const scene::Scene s = testScene(obj, n);
  useTestCache();
  auto t = std::make_unique<EmpiricalTechnique>();
  t->setParameter("ao", false);
  t->prepare(s, gpu::testing::context());
  EXPECT_FALSE(t->heterogeneous());
  const auto homogeneous = t->render({}).rgb;

  const material::Material m = leftRight(s);
  t->setMaterial(m);
  t->prepare(s, gpu::testing::context());
  ASSERT_TRUE(t->heterogeneous());
  const techniques::Frame f = t->render({});
  const auto& mixed = f.rgb;
  const auto& depth = f.layers.at("front_depth");

  int left = 0, right = 0;
  double leftWorst = 0.0, ratioHomogeneous = 0.0, ratioMixed = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const size_t i = size_t(y) * size_t(n) + size_t(x);
      if (depth[i * 3] == 0.0f) continue;  // background
      const double worldX = (x + 0.5 - 0.5 * n) * 2.2 / n;
      if (worldX < -0.2) {
        ++left;
        for (int c = 0; c < 3; ++c)
          leftWorst = std::max(leftWorst, std::abs(double(mixed[i * 3 + size_t(c)]) -
                                                   double(homogeneous[i * 3 + size_t(c)])));
      } else if (worldX > 0.2) {
        ++right;
        ratioHomogeneous += double(homogeneous[i * 3 + 1]) / double(homogeneous[i * 3]);
        ratioMixed += double(mixed[i * 3 + 1]) / std::max(double(mixed[i * 3]), 1e-9);
      }
    }
  ratioHomogeneous /= right;
  ratioMixed /= right;
  std::printf("empirical, two media: %d left pixels (worst difference to Marble %.3e), %d right "
              "pixels: mean green/red %.3f (homogeneous Marble %.3f)\n",
              left, leftWorst, right, ratioMixed, ratioHomogeneous);
  EXPECT_GT(left, 200);
  EXPECT_GT(right, 200);
  EXPECT_LT(leftWorst, 1e-5);
  EXPECT_LT(ratioMixed, 0.5 * ratioHomogeneous);

  // Back to the scene's material: the homogeneous image again.
  t->setMaterial(std::nullopt);
  t->prepare(s, gpu::testing::context());
  EXPECT_FALSE(t->heterogeneous());
  EXPECT_EQ(t->render({}).rgb, homogeneous);
}

// Orbiting (issue 14 §6): setCamera keeps the preparation. On the two-media sphere, the frame
// after a move carries no note (prepare() computes the per-vertex colours again and says so, as the
// fresh technique's frame shows) and renders the front, back and shade passes of any frame; its
// image equals that of a technique prepared at the new camera to 1e-6 of the peak (the same
// colours and passes; measured 0) and differs from the image before the move.
TEST_F(EmpiricalHeteroGpu, CameraMovesKeepThePerVertexColours) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj");
  const scene::Scene s = testScene(obj, 32);
  useTestCache();
  const material::Material m = leftRight(s);
  auto make = [&] {
    auto t = std::make_unique<EmpiricalTechnique>();
    t->setParameter("ao", false);
    t->setMaterial(m);
    return t;
  };
  auto noted = [](const techniques::Frame& f) {
    for (const std::string& n : f.notes)
      if (n.find("heterogeneous material") != std::string::npos) return true;
    return false;
  };
  auto moving = make();
  moving->prepare(s, gpu::testing::context());
  ASSERT_TRUE(moving->heterogeneous());
  const techniques::Frame before = moving->render({});
  EXPECT_TRUE(noted(before));
  scene::Scene moved = s;
  moved.camera = orbited(s.camera, 0.6);
  ASSERT_TRUE(moving->setCamera(moved.camera));
  const techniques::Frame a = moving->render({});
  EXPECT_TRUE(a.notes.empty());
  ASSERT_EQ(a.passes.size(), 3u);
  for (const char* pass : {"front", "back", "shade"}) EXPECT_TRUE(hasPass(a, pass)) << pass;

  auto fresh = make();
  fresh->prepare(moved, gpu::testing::context());
  const techniques::Frame b = fresh->render({});
  EXPECT_TRUE(noted(b));
  const double d = relativeMaxDifference(a.rgb, b.rgb);
  std::printf("empirical after the move: %.2g of the peak from a fresh preparation\n", d);
  EXPECT_LT(d, 1e-6);
  EXPECT_GT(relativeMaxDifference(before.rgb, a.rgb), 0.05);  // the camera did move
}

// A surface map (Marble where the atlas's u < 0.5, Ketchup elsewhere) read at the vertices' atlas
// UVs: both colours appear, each on a good share of the sphere.
class HalfAtlas final : public material::SurfaceMap {
 public:
  LocalMedium at(const glm::dvec2& uv) const override {
    return LocalMedium::of(preset(uv.x < 0.5 ? "marble" : "ketchup").medium());
  }
};

TEST_F(EmpiricalHeteroGpu, SurfaceMapGivesTwoColours) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj");
  const int n = 32;
  const scene::Scene s = testScene(obj, n);
  useTestCache();
  auto t = std::make_unique<EmpiricalTechnique>();
  t->setParameter("ao", false);
  t->prepare(s, gpu::testing::context());
  const auto homogeneous = t->render({}).rgb;
  material::Material m;
  m.kind = material::Material::Kind::Surface;
  m.medium = s.medium;
  m.frame.scale = s.medium.scale;
  m.surface = std::make_shared<HalfAtlas>();
  t->setMaterial(m);
  t->prepare(s, gpu::testing::context());
  ASSERT_TRUE(t->heterogeneous());
  const techniques::Frame f = t->render({});
  const auto& depth = f.layers.at("front_depth");
  int same = 0, redder = 0, covered = 0;
  for (size_t i = 0; i < size_t(n) * size_t(n); ++i) {
    if (depth[i * 3] == 0.0f) continue;
    ++covered;
    const double gr = double(f.rgb[i * 3 + 1]) / std::max(double(f.rgb[i * 3]), 1e-9);
    const double grHomogeneous = double(homogeneous[i * 3 + 1]) / double(homogeneous[i * 3]);
    if (f.rgb[i * 3 + 1] == homogeneous[i * 3 + 1]) ++same;
    if (gr < 0.5 * grHomogeneous) ++redder;
  }
  std::printf("empirical, surface map: %d covered pixels, %d as Marble, %d much redder\n",
              covered, same, redder);
  EXPECT_GT(same, covered / 10);
  EXPECT_GT(redder, covered / 10);
}

}  // namespace
}  // namespace translucent::empirical
