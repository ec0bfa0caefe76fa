// SPDX-License-Identifier: GPL-3.0-or-later
// The point-cloud technique on a heterogeneous material (pointcloud_technique.h, "Heterogeneous
// materials"; shaders/pointcloud/hetero.glsl) on whatever OpenGL 4.5 implementation the machine
// has (Mesa llvmpipe here), small sizes:
//   - the GPU's B equals the CPU traversal with Eq. 8 (cpu_traversal.h) pixel by pixel;
//   - a two-medium sphere looks like each medium where that medium is;
//   - a homogeneous material still takes the old path, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <memory>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/optics/presets.h"
#include "render_helpers.h"

namespace translucent::pointcloud {
namespace {

using namespace translucent::pointcloud::testing;
using material::LocalMedium;

class PointCloudHeteroGpu : public gpu::testing::GpuTest {};

// Two media either side of the material-space plane (1, 0.5, 0.2)·q = d [mm] (not an octree
// splitting plane, so clusters straddle it).
class HalfSpaces final : public material::VolumeField {
 public:
  HalfSpaces(const Medium& left, const Medium& right, double d)
      : left_(LocalMedium::of(left)), right_(LocalMedium::of(right)), d_(d) {}
  double side(const glm::dvec3& q) const { return q.x + 0.5 * q.y + 0.2 * q.z - d_; }
  LocalMedium at(const glm::dvec3& q) const override { return side(q) < 0.0 ? left_ : right_; }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override {
    Rgb m{};
    for (size_t c = 0; c < 3; ++c) m[c] = std::max(left_.sigmaT()[c], right_.sigmaT()[c]);
    return m;
  }

 private:
  LocalMedium left_, right_;
  double d_;
};

// The test scene's sphere (radius 1, 10 mm per unit): Marble on the left, `right` on the right.
material::Material twoMedia(const scene::Scene& s, const char* right, double d = 1.7) {
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium = s.medium;
  m.frame.scale = s.medium.scale;
  m.volume = std::make_shared<HalfSpaces>(preset("marble").medium(), preset(right).medium(), d);
  m.surface_depth = 0.5;
  return m;
}

scene::Scene sphereScene(const TempDir& dir, int size) {
  const auto obj = writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, size);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(0.3, 0.2, 1.0)), 1.0};
  return s;
}

// At every covered pixel the GPU's B equals the CPU traversal (Eq. 8, cpu_traversal.h) of the
// same octree with the GPU's irradiance (refit in double), the node representatives refit on the
// CPU, and the shading profile from the G-buffer's triangle and position, to 2e-3 relative
// (float against double).
double expectGpuMatchesCpu(PointCloudTechnique& t) {
  const techniques::Frame f = t.render({});
  const geometry::Octree octree = t.octreeWithGpuIrradiance();
  HeteroProfiles profiles = heteroProfiles(octree, t.cloudProfiles());
  refitNodeProfiles(octree, profiles);
  const auto positions = t.gbufferPositions();
  const auto& b = f.layers.at("exitance");
  double maxB = 0.0;
  for (float v : b) maxB = std::max(maxB, double(v));
  EXPECT_GT(maxB, 0.0);
  int covered = 0, compared = 0;
  double worst = 0.0;
  for (size_t i = 0; i < positions.size(); ++i) {
    if (positions[i].w == 0.0f) continue;
    ++covered;
    const auto triangle = static_cast<uint32_t>(positions[i].w + 0.5f) - 1u;
    const glm::dvec3 x(positions[i]);
    const auto shading = shadingProfile(t.mesh(), t.vertexProfiles(), triangle, x);
    const glm::dvec3 cpu = radiantExitance(octree, x, profiles, shading, t.traversalOptions());
    for (int c = 0; c < 3; ++c) {
      if (cpu[c] < 1e-4 * maxB) continue;
      const double e = std::abs(double(b[i * 3 + size_t(c)]) - cpu[c]) / cpu[c];
      worst = std::max(worst, e);
      ++compared;
      // Float (GPU) against double (CPU) on float inputs: exp of sums of ~10 ln P.
      EXPECT_LT(e, 2e-3) << "pixel " << i << " channel " << c << ": GPU " << b[i * 3 + size_t(c)]
                         << ", CPU " << cpu[c];
      if (e >= 2e-3) return worst;
    }
  }
  std::printf("heterogeneous GPU vs CPU: %d covered pixels, %d channel values compared, worst "
              "relative difference %.3e\n", covered, compared, worst);
  EXPECT_GT(covered, 400);
  EXPECT_GT(compared, 2 * covered);
  return worst;
}

TEST_F(PointCloudHeteroGpu, TraversalEqualsCpuOracle) {
  TempDir dir;
  const scene::Scene s = sphereScene(dir, 32);
  auto t = technique(3000);
  t->setMaterial(twoMedia(s, "ketchup"));
  t->prepare(s, gpu::testing::context());
  ASSERT_TRUE(t->heterogeneous());
  RecordProperty("worst_relative_error", std::to_string(expectGpuMatchesCpu(*t)));
}

// A surface map (Marble where the atlas's u < 0.5, Ketchup elsewhere): the points read it at
// their atlas UV; the GPU still equals the CPU, and both media occur among the points.
class HalfAtlas final : public material::SurfaceMap {
 public:
  LocalMedium at(const glm::dvec2& uv) const override {
    return LocalMedium::of(preset(uv.x < 0.5 ? "marble" : "ketchup").medium());
  }
};

TEST_F(PointCloudHeteroGpu, SurfaceMapTraversalEqualsCpuOracle) {
  TempDir dir;
  const scene::Scene s = sphereScene(dir, 32);
  auto t = technique(3000);
  material::Material m;
  m.kind = material::Material::Kind::Surface;
  m.medium = s.medium;
  m.frame.scale = s.medium.scale;
  m.surface = std::make_shared<HalfAtlas>();
  t->setMaterial(m);
  t->prepare(s, gpu::testing::context());
  ASSERT_TRUE(t->heterogeneous());
  const auto& p = t->cloudProfiles();
  const double marble0 = p.node(0, 1, 0);
  int other = 0;
  for (size_t i = 0; i < p.size(); ++i) other += p.node(i, 1, 0) != marble0 ? 1 : 0;
  EXPECT_GT(other, 300);
  EXPECT_LT(other, 2700);
  RecordProperty("worst_relative_error", std::to_string(expectGpuMatchesCpu(*t)));
}

// Marble | Ketchup: away from the boundary (more than 3 mm), each half of the
// image is closer to the homogeneous render of its own medium than to the other's.
TEST_F(PointCloudHeteroGpu, TwoMediaLookLikeEachMediumWhereItIs) {
  TempDir dir;
  scene::Scene s = sphereScene(dir, 32);
  auto t = technique(3000);
  t->prepare(s, gpu::testing::context());
  const auto marble = t->render({}).layers.at("exitance");
  scene::Scene milk = s;
  milk.medium = preset("ketchup").medium(s.medium.scale);
  t->prepare(milk, gpu::testing::context());
  const auto skim = t->render({}).layers.at("exitance");
  const material::Material m = twoMedia(s, "ketchup", 0.0);
  t->setMaterial(m);
  t->prepare(s, gpu::testing::context());
  ASSERT_TRUE(t->heterogeneous());
  const techniques::Frame f = t->render({});
  const auto& mixed = f.layers.at("exitance");
  const auto positions = t->gbufferPositions();
  const auto& field = dynamic_cast<const HalfSpaces&>(*m.volume);
  const double margin = 3.0;  // mm (the sphere is 20 mm across)
  int left = 0, right = 0, closer = 0;
  for (size_t i = 0; i < positions.size(); ++i) {
    if (positions[i].w == 0.0f) continue;
    const double side = field.side(m.frame.toMaterial(glm::dvec3(positions[i])));
    if (std::abs(side) < margin) continue;
    double toMarble = 0.0, toSkim = 0.0;
    for (int c = 0; c < 3; ++c) {
      const size_t k = i * 3 + size_t(c);
      toMarble += std::abs(double(mixed[k]) - double(marble[k]));
      toSkim += std::abs(double(mixed[k]) - double(skim[k]));
    }
    ++(side < 0.0 ? left : right);
    if ((side < 0.0) == (toMarble < toSkim)) ++closer;
  }
  std::printf("two media: %d marble-side and %d ketchup-side pixels, %d closer to their own medium\n",
              left, right, closer);
  EXPECT_GT(left, 30);
  EXPECT_GT(right, 30);
  EXPECT_GE(closer, (left + right) * 95 / 100);
}

// Back to the scene's (homogeneous) material: the same image as a technique that never saw a
// heterogeneous one, bit for bit.
TEST_F(PointCloudHeteroGpu, HomogeneousPathIsUnchanged) {
  TempDir dir;
  const scene::Scene s = sphereScene(dir, 24);
  auto fresh = technique(2000);
  fresh->prepare(s, gpu::testing::context());
  const auto expected = fresh->render({}).rgb;
  auto t = technique(2000);
  t->setMaterial(twoMedia(s, "ketchup"));
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  t->setMaterial(std::nullopt);
  t->prepare(s, gpu::testing::context());
  EXPECT_FALSE(t->heterogeneous());
  EXPECT_EQ(t->render({}).rgb, expected);
}

// The bunny of the default scene, 5000 points, 48²: pass times of the homogeneous and the
// heterogeneous path (printed for the record; llvmpipe here, so only a rough ratio), and a finite,
// lit heterogeneous image.
TEST_F(PointCloudHeteroGpu, PassTimesOnTheBunny) {
  scene::Scene s = scene::defaultScene();
  s.camera.width = 48;
  s.camera.height = 48;
  auto t = technique(5000);
  const auto times = [&](const char* what) {
    std::map<std::string, double> ms;
    techniques::Frame f;
    for (int k = 0; k < 2; ++k) {
      f = t->render({});
      for (const auto& p : f.passes) ms[p.name] += p.ms / 2.0;
    }
    std::printf("%s:", what);
    for (const auto& [name, v] : ms) std::printf(" %s %.2f ms", name.c_str(), v);
    std::printf("\n");
    return f;
  };
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  times("bunny homogeneous");
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium = s.medium;
  m.frame.scale = s.medium.scale;
  m.volume = std::make_shared<HalfSpaces>(preset("marble").medium(), preset("ketchup").medium(), 0.0);
  m.surface_depth = 0.5;
  t->setMaterial(m);
  t->prepare(s, gpu::testing::context());
  ASSERT_TRUE(t->heterogeneous());
  (void)t->render({});
  const techniques::Frame f = times("bunny heterogeneous (n = 16)");
  double sum = 0.0;
  for (float v : f.rgb) {
    ASSERT_TRUE(std::isfinite(v));
    sum += double(v);
  }
  EXPECT_GT(sum, 0.0);
}

TEST_F(PointCloudHeteroGpu, ShaderKernelIsRejected) {
  TempDir dir;
  const scene::Scene s = sphereScene(dir, 16);
  auto t = technique(1000);
  t->setParameter("kernel", std::string("shader"));
  t->setMaterial(twoMedia(s, "ketchup"));
  EXPECT_THROW(t->prepare(s, gpu::testing::context()), ParameterError);
}

}  // namespace
}  // namespace translucent::pointcloud
