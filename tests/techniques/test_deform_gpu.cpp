// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh deformation on the GPU (techniques::GpuMesh::deform, shaders/common/deform.comp) against
// the CPU's (geometry::deformMesh, scene::loadSceneMesh), on Mesa llvmpipe here:
//   - the vertex buffer after deform() holds the CPU-deformed positions and normals (float
//     rounding: 1e-5 of the mesh's size, normals within 0.05 degrees);
//   - a technique that draws through GpuMesh (tsm) renders the scene at time T, deformed on the
//     GPU, as it renders the CPU-deformed mesh written to a file (no deformation): the same image
//     up to float rounding of the positions (a few silhouette pixels may flip);
//   - preparing again at a time where the deformation is the identity restores the rest pose;
//   - the empirical shader deforms on the GPU too (without AO, which it keeps from the rest pose,
//     the same image as the CPU-deformed mesh's) and reads its material in the rest pose, whatever
//     the time of its first preparation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "translucent/geometry/deform.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/gpu/compute.h"
#include "render_helpers.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/empirical/empirical_technique.h"
#include "translucent/techniques/tsis/tsis_technique.h"
#include "translucent/techniques/tsm/tsm_technique.h"

namespace translucent::techniques {
namespace {

using namespace translucent::pointcloud::testing;
using Type = geometry::Deformation::Type;

class DeformGpu : public gpu::testing::GpuTest {};

// An ellipsoid (semi-axes 0.45, 0.9, 0.3) about the origin: not symmetric under the twist.
geometry::TriangleMesh ellipsoid(unsigned subdivisions) {
  geometry::TriangleMesh m = geometry::makeIcosphere(subdivisions, 1.0);
  for (glm::dvec3& p : m.positions) p *= glm::dvec3(0.45, 0.9, 0.3);
  m.normals.clear();
  return m;
}

std::vector<geometry::Deformation> chain() {
  geometry::Deformation twist;
  twist.type = Type::Twist;
  twist.amount = 60.0;
  twist.period = 2.0;
  geometry::Deformation bend;
  bend.type = Type::Bend;
  bend.amount = 50.0;
  bend.period = 3.0;
  bend.origin = {0.0, -0.3, 0.0};
  geometry::Deformation wave;
  wave.type = Type::Wave;
  wave.amount = 0.03;
  wave.axis = {0.0, 0.0, 1.0};
  wave.direction = {0.0, 1.0, 0.0};
  wave.wavelength = 0.6;
  return {twist, bend, wave};
}

TEST_F(DeformGpu, TheVertexBufferHoldsTheCpuDeformedMesh) {
  const geometry::TriangleMesh rest = ellipsoid(3);
  GpuMesh gpu(rest);
  const double time = 0.4;
  gpu.deform(chain(), time);
  geometry::TriangleMesh cpu = rest;
  geometry::deformMesh(chain(), time, cpu);
  const unsigned stride = gpu.floatsPerVertex();
  const std::vector<float> v = gpu::download<float>(gpu.vertexBuffer(), rest.vertexCount() * stride);
  double worstP = 0.0, worstN = 1.0, moved = 0.0;
  for (size_t i = 0; i < rest.vertexCount(); ++i) {
    const glm::dvec3 p(v[i * stride], v[i * stride + 1], v[i * stride + 2]);
    const glm::dvec3 n(v[i * stride + 3], v[i * stride + 4], v[i * stride + 5]);
    worstP = std::max(worstP, glm::length(p - cpu.positions[i]));
    worstN = std::min(worstN, glm::dot(glm::normalize(n), cpu.normals[i]));
    moved = std::max(moved, glm::length(cpu.positions[i] - rest.positions[i]));
  }
  EXPECT_GT(moved, 0.05);  // the deformation is not a no-op at this time
  EXPECT_LT(worstP, 1e-5);
  EXPECT_GT(worstN, std::cos(0.05 * std::numbers::pi / 180.0));
  // The identity (time 0: every periodic magnitude is 0; the wave's is constant) restores the
  // rest pose apart from the wave, then without the wave exactly the rest pose.
  gpu.deform({chain()[0], chain()[1]}, 0.0);
  const std::vector<float> back = gpu::download<float>(gpu.vertexBuffer(), rest.vertexCount() * stride);
  for (size_t i = 0; i < rest.vertexCount(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(back[i * stride + size_t(c)], float(rest.positions[i][c]));
}

double meanAbs(const std::vector<float>& a) {
  double s = 0.0;
  for (float x : a) s += double(std::abs(x));
  return s / double(a.size());
}

// a − b, pixel-channel by pixel-channel (frames of one size).
std::vector<float> difference(const Frame& a, const Frame& b) {
  EXPECT_EQ(a.rgb.size(), b.rgb.size());
  std::vector<float> d(std::min(a.rgb.size(), b.rgb.size()));
  for (size_t i = 0; i < d.size(); ++i) d[i] = a.rgb[i] - b.rgb[i];
  return d;
}

// The per-frame path: the technique prepared at the rest pose and rendered, then prepared again at
// the deformed time and rendered.
struct RestThenDeformed {
  Frame rest, deformed;
};
RestThenDeformed renderRestThenDeformed(Technique& t, const scene::Scene& atRest,
                                        const scene::Scene& deformed) {
  RestThenDeformed r;
  t.prepare(atRest, gpu::testing::context());
  r.rest = t.render({});
  t.prepare(deformed, gpu::testing::context());
  r.deformed = t.render({});
  return r;
}

// The ellipsoid twisted and bent (chain()'s first two) at time 0.4, `size` pixels square: the
// scene (`deformed`), the CPU-deformed mesh as a file of its own, not deformed again (`cpu`: what
// the references load), and the rest pose (time 0, where both magnitudes are 0).
struct TwistedAndBent {
  TempDir dir;
  scene::Scene deformed, cpu, atRest;
  explicit TwistedAndBent(int size) {
    deformed = testScene(writeObj(ellipsoid(4), dir.path() / "rest.obj"), size);
    deformed.mesh_deform = {chain()[0], chain()[1]};
    deformed.time = 0.4;
    cpu = testScene(writeObj(scene::loadSceneMesh(deformed), dir.path() / "deformed.obj"), size);
    atRest = deformed;
    atRest.time = 0.0;
  }
};

// A GPU-deformed image against the image of the CPU-deformed mesh file: the same up to float
// rounding of the positions (mean difference under 1% of the mean, at most 1% of the
// pixel-channels off by more than 5%: silhouettes), and more than 10% from the rest pose's (the
// deformation is visible). Returns the mean of the CPU-deformed image.
double expectTheCpuDeformedImage(const RestThenDeformed& g, const Frame& cpu) {
  const double scale = meanAbs(cpu.rgb);
  EXPECT_GT(scale, 0.0);
  const std::vector<float> diff = difference(g.deformed, cpu);
  const size_t far = size_t(std::count_if(diff.begin(), diff.end(), [&](float x) {
    return double(std::abs(x)) > 0.05 * scale;
  }));
  EXPECT_LT(meanAbs(diff), 0.01 * scale);
  EXPECT_LE(far, diff.size() / 100);
  EXPECT_GT(meanAbs(difference(g.deformed, g.rest)), 0.1 * scale);
  return scale;
}

TEST_F(DeformGpu, TsmRendersTheGpuDeformedMeshAsTheCpuDeformedOne) {
  TempDir dir;
  const auto restObj = writeObj(ellipsoid(4), dir.path() / "rest.obj");
  scene::Scene s = testScene(restObj, 48);
  s.mesh_deform = chain();
  s.time = 0.4;
  // The CPU-deformed mesh (what the references load) as a file of its own, not deformed again.
  geometry::TriangleMesh cpuMesh = scene::loadSceneMesh(s);
  const auto cpuObj = writeObj(cpuMesh, dir.path() / "deformed.obj");
  scene::Scene c = testScene(cpuObj, 48);

  tsm::TsmTechnique gpuT, cpuT;
  scene::Scene atRest = s;
  atRest.time = 0.0;
  atRest.mesh_deform.pop_back();  // the wave is constant; without it time 0 is the rest pose
  const RestThenDeformed g = renderRestThenDeformed(gpuT, atRest, s);
  cpuT.prepare(c, gpu::testing::context());
  const double scale = expectTheCpuDeformedImage(g, cpuT.render({}));
  // Back at the rest pose: the rest image again.
  gpuT.prepare(atRest, gpu::testing::context());
  EXPECT_LT(meanAbs(difference(gpuT.render({}), g.rest)), 1e-6 * scale);
}

// The empirical shader deforms its rest-pose vertex buffer on the GPU: with AO off (AO is the rest
// pose's, precomputed once) its image at time T is the CPU-deformed mesh's up to float rounding,
// as tsm's above, and differs from the rest pose's.
TEST_F(DeformGpu, EmpiricalRendersTheGpuDeformedMeshAsTheCpuDeformedOne) {
  const TwistedAndBent e(48);
  const scene::Scene &s = e.deformed, &c = e.cpu, &atRest = e.atRest;
  empirical::EmpiricalTechnique gpuT, cpuT;
  for (auto* t : {&gpuT, &cpuT}) t->setParameter("ao", false);
  const RestThenDeformed g = renderRestThenDeformed(gpuT, atRest, s);
  cpuT.prepare(c, gpu::testing::context());
  expectTheCpuDeformedImage(g, cpuT.render({}));
}

// A heterogeneous material lives in the rest pose: the empirical shader prepared directly at a
// deformed time renders what it renders when prepared at rest and then moved to that time (the
// per-vertex colours are the rest pose's either way). Read through the deformation a second time,
// as sceneMaterial's frame would on rest-pose vertices, the first would show other media.
TEST_F(DeformGpu, EmpiricalReadsItsMaterialInTheRestPoseAtAnyTime) {
  scene::Scene s = scene::loadScene(std::string(TRANSLUCENT_DATA_DIR) + "/scenes/bunny-bend.json");
  ASSERT_FALSE(s.material.homogeneous());
  s.camera.width = 64;
  s.camera.height = 48;
  scene::Scene atRest = s;
  atRest.time = 0.0;
  ASSERT_TRUE(geometry::isIdentity(atRest.mesh_deform, atRest.time));
  ASSERT_FALSE(geometry::isIdentity(s.mesh_deform, s.time));
  empirical::EmpiricalTechnique direct, moving;
  for (auto* t : {&direct, &moving}) t->setParameter("ao", false);
  direct.prepare(s, gpu::testing::context());
  const Frame d = direct.render({});
  const RestThenDeformed m = renderRestThenDeformed(moving, atRest, s);
  const double scale = meanAbs(m.deformed.rgb);
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(meanAbs(difference(d, m.deformed)), 1e-6 * scale);
  EXPECT_GT(meanAbs(difference(m.deformed, m.rest)), 0.05 * scale);
}

// The techniques with CPU-side geometry keep it from the rest pose and move it with the surface:
// pointcloud (points at their barycentrics on the deformed triangles, areas scaled, a new octree)
// and tsis (the rest atlas, texel points and A_S/A_T on the deformed mesh). Rendered at time T
// after the rest pose, they must show the deformed surface: close to the same technique
// prepared from the CPU-deformed mesh file (which samples its own points and atlas, so only
// close: 5% of the mean radiance, or three times the technique's own frame-to-frame noise where
// that is larger: tsis's sampling pattern turns each frame, 2.5% here), and far from the rest
// pose's image (more than 10%).
template <class T>
void expectFollowsTheDeformation(const char* points_parameter, int points) {
  const TwistedAndBent e(40);
  const scene::Scene &s = e.deformed, &c = e.cpu, &atRest = e.atRest;
  T moving, direct;
  if (points_parameter) {
    moving.setParameter(points_parameter, points);
    direct.setParameter(points_parameter, points);
  }
  const RestThenDeformed g = renderRestThenDeformed(moving, atRest, s);
  direct.prepare(c, gpu::testing::context());
  const Frame r = direct.render({});
  const double scale = meanAbs(r.rgb);
  ASSERT_GT(scale, 0.0);
  const double noise = meanAbs(difference(direct.render({}), r));
  EXPECT_LT(meanAbs(difference(g.deformed, r)), std::max(0.05 * scale, 3.0 * noise));
  EXPECT_GT(meanAbs(difference(g.deformed, g.rest)), 0.1 * scale);
}

TEST_F(DeformGpu, PointcloudMovesItsPointsWithTheSurface) {
  useTestCache();
  expectFollowsTheDeformation<pointcloud::PointCloudTechnique>("points", 20000);
}

TEST_F(DeformGpu, TsisKeepsItsAtlasAndFollowsTheSurface) {
  useTestCache();
  expectFollowsTheDeformation<tsis::TsisTechnique>(nullptr, 0);
}

}  // namespace
}  // namespace translucent::techniques
