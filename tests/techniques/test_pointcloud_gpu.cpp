// SPDX-License-Identifier: GPL-3.0-or-later
// The point-cloud technique on the GPU (techniques/pointcloud/pointcloud_technique.h), on whatever
// OpenGL 4.5 implementation the machine has (Mesa llvmpipe here), at small sizes:
//   - the GPU traversal equals the CPU oracle (cpu_traversal.h) pixel by pixel;
//   - the irradiance pass: analytic values for every light type, shadows, environment lighting;
//   - the whole technique against independent references: BSSRDF integration on the lit sphere
//     (reference/sphere_integration.h) and the pencil-beam profile convolved with a lit disc;
//   - bad input fails with a clear error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "translucent/io/image_io.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/gl.h"
#include "translucent/gpu/compute.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/presets.h"
#include "translucent/reference/sphere_integration.h"
#include "render_helpers.h"
#include "translucent/lights/environment_map.h"

namespace translucent::pointcloud {
namespace {

using namespace translucent::pointcloud::testing;
using lights::EnvironmentMap;
using lights::transmittedIrradianceLambdas;
constexpr double kPi = std::numbers::pi;

class PointCloudGpu : public gpu::testing::GpuTest {};

double relativeError(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-30); }

// ---- traversal: GPU == CPU ------------------------------------------------------------------

// The bunny under the default scene's lights plus a point light, 64x64: at every covered pixel
// the GPU's B equals the CPU traversal of the same octree (with the GPU's irradiance, refit in
// double on the CPU), the same kernel table and the same G-buffer position, to 1e-3 relative
// (float against double arithmetic: ~1e-6 per term).
void expectGpuMatchesCpu(PointCloudTechnique& t, const scene::Scene& s, gpu::Context& gl) {
  t.prepare(s, gl);
  const techniques::Frame f = t.render({});
  const geometry::Octree octree = t.octreeWithGpuIrradiance();
  const RgbKernel kernel = t.cpuKernel();
  const auto positions = t.gbufferPositions();
  const auto& b = f.layers.at("exitance");
  double maxB = 0.0;
  for (float v : b) maxB = std::max(maxB, double(v));
  ASSERT_GT(maxB, 0.0);
  int covered = 0, compared = 0;
  double worst = 0.0;
  for (size_t i = 0; i < positions.size(); ++i) {
    if (positions[i].w == 0.0f) continue;
    ++covered;
    const glm::dvec3 cpu = radiantExitance(octree, glm::dvec3(positions[i]), kernel, t.traversalOptions());
    for (int c = 0; c < 3; ++c) {
      if (cpu[c] < 1e-4 * maxB) continue;  // dark pixels: float noise relative to nothing
      const double e = relativeError(b[i * 3 + size_t(c)], cpu[c]);
      worst = std::max(worst, e);
      ++compared;
      ASSERT_LT(e, 1e-3) << "pixel " << i << " channel " << c << ": GPU " << b[i * 3 + size_t(c)]
                         << ", CPU " << cpu[c];
    }
  }
  EXPECT_GT(covered, 600);
  EXPECT_GT(compared, 3 * covered / 2);
  ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST_F(PointCloudGpu, TraversalEqualsCpuOracleOnTheBunny) {
  scene::Scene s = scene::defaultScene();
  s.camera.width = 64;
  s.camera.height = 64;
  scene::Light point;
  point.emitter = reference::PointLight{{1.5, 0.5, 1.0}, 2.0};
  s.lights.push_back(point);
  auto t = technique(5000);
  expectGpuMatchesCpu(*t, s, gpu::testing::context());
  // The centroid criterion (Jensen & Buhler's) goes through the same comparison.
  t->setParameter("criterion", std::string("centroid"));
  t->setParameter("epsilon", 0.5);
  expectGpuMatchesCpu(*t, s, gpu::testing::context());
}

// A traversal of many clusters per pixel (100k points at epsilon 0.005 on the bunny: up to ~10⁵
// loop iterations a pixel). Where the driver ends long loops (llvmpipe: gpu/compute.h, LoopLimit)
// its pixels came out black (94% of the image at this setting): now that is an error naming the
// driver, the count of pixels cut and what to change. Elsewhere the frame equals the CPU
// traversal, as above.
TEST_F(PointCloudGpu, TraversalsTheDriverCutsAreAnErrorNotABlackImage) {
  scene::Scene s = scene::defaultScene();
  s.camera.width = 48;
  s.camera.height = 36;
  auto t = technique(100000);
  t->setParameter("epsilon", 0.005);
  if (!gpu::loopLimit().limited) {
    expectGpuMatchesCpu(*t, s, gpu::testing::context());
    return;
  }
  t->prepare(s, gpu::testing::context());
  try {
    t->render({});
    ADD_FAILURE() << "no error for traversals the driver cut";
  } catch (const gpu::GlError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stopped the traversal of "), std::string::npos) << what;
    EXPECT_NE(what.find("raise epsilon"), std::string::npos) << what;
  }
  // The same cloud at the default epsilon stays within the limit and renders.
  t->setParameter("epsilon", 0.1);
  const techniques::Frame f = t->render({});
  double sum = 0.0;
  for (float v : f.layers.at("exitance")) sum += double(v);
  EXPECT_GT(sum, 0.0);
}

// The .bssrdf shader kernel (dipole.bssrdf inside the traversal) gives the image of the table
// kernel (the C++ dipole tabulated with 4096 entries) to within the table's interpolation error.
TEST_F(PointCloudGpu, BssrdfShaderKernelMatchesTheTable) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 32);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(1.0, 0.0, 1.0)), 1.0};
  auto t = technique(3000);
  t->prepare(s, gpu::testing::context());
  const auto table = t->render({}).rgb;
  t->setParameter("kernel", std::string("shader"));
  const auto shader = t->render({}).rgb;
  double maxv = 0.0, worst = 0.0;
  for (float v : table) maxv = std::max(maxv, double(v));
  for (size_t i = 0; i < table.size(); ++i)
    if (double(table[i]) > 1e-3 * maxv) worst = std::max(worst, relativeError(shader[i], table[i]));
  EXPECT_GT(maxv, 0.0);
  EXPECT_LT(worst, 2e-3);
}

// A radial .bssrdf file with the table kernel is tabulated on the GPU (gpu/bssrdf_profiles.h:
// its radius and Rd from its own values): dipole.bssrdf gives the image of the C++ dipole's table
// within the two tables' float evaluation and interpolation differences.
TEST_F(PointCloudGpu, BssrdfFileTabulatedOnTheGpuMatchesTheCppTable) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 32);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(1.0, 0.0, 1.0)), 1.0};
  auto t = technique(3000);
  t->prepare(s, gpu::testing::context());
  const auto cpp = t->render({}).rgb;
  s.model = (gpu::bssrdfDirectory() / "dipole.bssrdf").string();
  t->prepare(s, gpu::testing::context());
  ASSERT_EQ(t->parameter("kernel"), techniques::ParameterValue(std::string("table")));
  const auto file = t->render({}).rgb;
  double maxv = 0.0, worst = 0.0;
  for (float v : cpp) maxv = std::max(maxv, double(v));
  for (size_t i = 0; i < cpp.size(); ++i)
    if (double(cpp[i]) > 1e-3 * maxv) worst = std::max(worst, relativeError(file[i], cpp[i]));
  EXPECT_GT(maxv, 0.0);
  EXPECT_LT(worst, 2e-3);
}

// readback = false leaves the frame on the GPU (no pixels) but times the same passes, and the
// next frame read back is the one a read-back-only sequence gives (bit for bit: same work).
TEST_F(PointCloudGpu, FramesWithoutReadBackTimeTheSamePasses) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(2, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 16);
  auto t = technique(2000);
  t->prepare(s, gpu::testing::context());
  // The first frame computes the lighting (shadow maps, irradiance); the later frames of the
  // unchanged scene keep it, so they are the ones to compare with each other.
  const techniques::Frame first = t->render({});
  const techniques::Frame full = t->render({});
  EXPECT_EQ(full.rgb, first.rgb);
  EXPECT_LT(full.passes.size(), first.passes.size());
  techniques::FrameRequest gpuOnly;
  gpuOnly.readback = false;
  const techniques::Frame kept = t->render(gpuOnly);
  EXPECT_TRUE(kept.rgb.empty());
  EXPECT_TRUE(kept.layers.empty());
  EXPECT_EQ(kept.width, 16);
  ASSERT_EQ(kept.passes.size(), full.passes.size());
  for (size_t i = 0; i < kept.passes.size(); ++i) EXPECT_EQ(kept.passes[i].name, full.passes[i].name);
  EXPECT_EQ(t->render({}).rgb, full.rgb);
}

// The two exit-radiance conventions (radiance_convention, seed Eq. 2.16) on a lit sphere, 16x16:
// the normalized frame is the Jensen frame divided by 4Cφ(1/η) = 1 - 2 C1_ext(η) in every channel
// and pixel, to 1e-6 relative (one extra float multiplication by a float-rounded constant: a few
// 1e-7), and the exitance layer B is bit for bit the same under both (same traversal).
TEST_F(PointCloudGpu, NormalizedConventionIsJensenOverTheDiffuseTransmittance) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 16);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(0.5, 0.3, 1.0)), 1.0};
  auto t = technique(2000);
  t->setParameter("radiance_convention", std::string("jensen"));
  t->prepare(s, gpu::testing::context());
  const techniques::Frame jensen = t->render({});
  t->setParameter("radiance_convention", std::string("normalized"));
  const techniques::Frame normalized = t->render({});
  ASSERT_EQ(jensen.rgb.size(), 16u * 16u * 3u);
  ASSERT_EQ(normalized.rgb.size(), jensen.rgb.size());
  EXPECT_EQ(normalized.layers.at("exitance"), jensen.layers.at("exitance"));
  const double norm = bssrdf::diffuseTransmittanceFromOutside(s.medium.eta);
  EXPECT_NEAR(norm, 0.9386, 1e-3);  // 1 - 2 C1_ext(1.3): 6.1% diffuse Fresnel reflectance
  int lit = 0;
  for (size_t i = 0; i < jensen.rgb.size(); ++i) {
    const double expected = double(jensen.rgb[i]) / norm;
    if (jensen.rgb[i] > 0.0f) ++lit;
    EXPECT_NEAR(double(normalized.rgb[i]), expected, 1e-6 * expected) << "value " << i;
  }
  EXPECT_GT(lit, 3 * 100);  // most of the disc's ~200 pixels, three channels
}

// ---- irradiance pass ------------------------------------------------------------------------

// E_i for every point of a sphere (radial normals) under each light type, against the analytic
// value E_l Ft(η, cos θ) cos θ: shadow mapping must neither darken lit points (acne) away from
// the terminator nor light points facing away.
struct SphereIrradiance : PointCloudGpu {
  TempDir dir;
  std::filesystem::path obj = writeObj(geometry::makeIcosphere(4, 1.0), dir.path() / "sphere.obj");
};

TEST_F(SphereIrradiance, DirectionalLightIsFresnelCosineWithoutAcne) {
  scene::Scene s = testScene(obj, 16);
  const glm::dvec3 l = glm::normalize(glm::dvec3(0.3, 0.5, 0.8));
  s.lights[0].emitter = reference::DirectionalLight{l, 2.0};
  s.lights[0].color = {1.0, 0.5, 0.25};
  auto t = technique(4000);
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  const auto e = t->gpuIrradiance();
  const auto& cloud = t->pointCloud();
  int lit = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const double c = glm::dot(glm::dvec3(cloud.normals[i]), l);
    const double expected = 2.0 * fresnelTransmittance(c, 1.3) * c;
    if (c > 0.15) {
      ++lit;
      EXPECT_LT(relativeError(e[i].r, expected), 2e-4) << "point " << i << " cos " << c;
      EXPECT_LT(relativeError(e[i].b, 0.25 * expected), 2e-4);
    } else if (c <= 0.0) {
      EXPECT_EQ(e[i].r, 0.0f) << "point " << i << " faces away from the light";
    }
  }
  EXPECT_GT(lit, 1000);
}

TEST_F(SphereIrradiance, PointLightFallsOffWithTheSquaredDistance) {
  scene::Scene s = testScene(obj, 16);
  const glm::dvec3 pos(1.0, 2.0, 2.5);
  s.lights[0].emitter = reference::PointLight{pos, 3.0};
  auto t = technique(4000);
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  const auto e = t->gpuIrradiance();
  const auto& cloud = t->pointCloud();
  int lit = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const glm::dvec3 d = pos - glm::dvec3(cloud.positions[i]);
    const double c = glm::dot(glm::dvec3(cloud.normals[i]), glm::normalize(d));
    const double expected = 3.0 * fresnelTransmittance(c, 1.3) * c / glm::dot(d, d);
    if (c > 0.15) {
      ++lit;
      EXPECT_LT(relativeError(e[i].g, expected), 2e-4) << "point " << i;
    } else if (c <= 0.0) {
      EXPECT_EQ(e[i].g, 0.0f);
    }
  }
  EXPECT_GT(lit, 500);
}

TEST_F(SphereIrradiance, BeamLightsOnlyItsDisc) {
  scene::Scene s = testScene(obj, 16);
  const double a = 0.3;
  s.lights[0].emitter = reference::BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, a, 1.5};
  auto t = technique(4000);
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  const auto e = t->gpuIrradiance();
  const auto& cloud = t->pointCloud();
  int inside = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const glm::dvec3 p(cloud.positions[i]);
    const double rho = std::hypot(p.x, p.y), c = double(cloud.normals[i].z);
    if (c > 0.0 && rho < a - 1e-3) {
      ++inside;
      EXPECT_LT(relativeError(e[i].r, 1.5 / (kPi * a * a) * fresnelTransmittance(c, 1.3) * c), 2e-4);
    } else if (rho > a + 1e-3 || c <= 0.0) {
      EXPECT_EQ(e[i].r, 0.0f) << "point " << i << " outside the beam";
    }
  }
  EXPECT_GT(inside, 20);
}

TEST_F(SphereIrradiance, UnoccludedEnvironmentOfConstantRadiance) {
  // L constant: E(n) = L 2π ∫0^1 Ft(η, t) t dt for every normal (λ_0 of environment.h).
  const auto map = EnvironmentMap::constant(glm::vec3(0.5f, 1.0f, 2.0f), 64, 32);
  std::vector<float> rgb = map.rgb;
  analysis::writeExr((dir.path() / "sky.exr").string(), map.width, map.height, rgb);
  scene::Scene s = testScene(obj, 16);
  s.lights[0].emitter = scene::EnvironmentLight{dir.path() / "sky.exr", 2.0, 30.0, false};
  auto t = technique(2000);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  EXPECT_TRUE(f.converged);
  const double lambda0 = transmittedIrradianceLambdas(1.3)[0];
  const auto e = t->gpuIrradiance();
  for (size_t i = 0; i < e.size(); ++i) {
    ASSERT_LT(relativeError(e[i].r, 2.0 * 0.5 * lambda0), 2e-3) << "point " << i;
    ASSERT_LT(relativeError(e[i].b, 2.0 * 2.0 * lambda0), 2e-3) << "point " << i;
  }
}

TEST_F(SphereIrradiance, OccludedEnvironmentConvergesToTheUnoccludedOnAConvexBody) {
  // A convex body does not occlude itself: the shadow-mapped directions must average to the
  // same E as the unoccluded integral. 256 quasi-random directions: the mean over points is
  // within 1%, each point within 15% (a sum of 256 Ft cos lobes over a low-discrepancy set).
  const auto map = EnvironmentMap::constant(glm::vec3(1.0f), 32, 16);
  analysis::writeExr((dir.path() / "white.exr").string(), map.width, map.height, map.rgb);
  scene::Scene s = testScene(obj, 16);
  s.lights[0].emitter = scene::EnvironmentLight{dir.path() / "white.exr", 1.0, 0.0, true};
  auto t = technique(2000);
  t->setParameter("ibl_samples", 256);
  t->setParameter("ibl_samples_per_frame", 64);
  t->setParameter("shadow_map_size", 512);
  t->prepare(s, gpu::testing::context());
  int frames = 0;
  techniques::Frame f;
  do {
    f = t->render({});
    ++frames;
    if (frames < 4) {
      EXPECT_FALSE(f.converged) << "after " << frames << " frames of 64 directions";
    }
  } while (!f.converged && frames < 10);
  EXPECT_EQ(frames, 4);
  const double expected = transmittedIrradianceLambdas(1.3)[0];
  const auto e = t->gpuIrradiance();
  double mean = 0.0;
  for (size_t i = 0; i < e.size(); ++i) {
    mean += double(e[i].g);
    EXPECT_LT(relativeError(e[i].g, expected), 0.15) << "point " << i;
  }
  mean /= double(e.size());
  EXPECT_LT(relativeError(mean, expected), 0.01);

  // Batch rendering finishes the same 256 directions in one frame, in the same order.
  auto batch = technique(2000);
  batch->setParameter("ibl_samples", 256);
  batch->setParameter("ibl_samples_per_frame", 64);
  batch->setParameter("shadow_map_size", 512);
  batch->prepare(s, gpu::testing::context());
  techniques::FrameRequest request;
  request.converge = true;
  EXPECT_TRUE(batch->render(request).converged);
  const auto e1 = batch->gpuIrradiance();
  ASSERT_EQ(e1.size(), e.size());
  for (size_t i = 0; i < e.size(); ++i) ASSERT_LT(relativeError(e1[i].g, e[i].g), 1e-6) << "point " << i;
}

TEST_F(PointCloudGpu, ShadowOfAnOccluder) {
  // A big box with a small box floating in front of it (both closed): under a light along +z,
  // points of the big box's front face behind the small box get no light; the others get
  // E_l Ft(η, 1).
  TempDir dir;
  const auto mesh = join(geometry::makeBox({-1.0, -1.0, -1.0}, {1.0, 1.0, 0.0}),
                         geometry::makeBox({-0.3, -0.3, 0.4}, {0.3, 0.3, 0.6}));
  const auto obj = writeObj(mesh, dir.path() / "boxes.obj");
  scene::Scene s = testScene(obj, 16);
  auto t = technique(8000);
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  const auto e = t->gpuIrradiance();
  const auto& cloud = t->pointCloud();
  const double full = fresnelTransmittance(1.0, 1.3);
  int shadowed = 0, lit = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const glm::dvec3 p(cloud.positions[i]);
    if (std::abs(p.z) > 1e-6 || cloud.normals[i].z < 0.99f) continue;  // the big front face only
    const double m = std::max(std::abs(p.x), std::abs(p.y));
    if (m < 0.28) {
      ++shadowed;
      EXPECT_LT(e[i].r, 1e-3 * full) << "point " << i << " behind the occluder";
    } else if (m > 0.32) {
      ++lit;
      EXPECT_LT(relativeError(e[i].r, full), 2e-4) << "point " << i;
    }
  }
  EXPECT_GT(shadowed, 30);
  EXPECT_GT(lit, 300);
}

// The four shadow lookups of seed Fig. 3.3 (issue 14 §7): without hardware PCF and with one
// lookup the shadow edge is hard (every point fully lit or fully dark: one texel's depth test);
// hardware PCF (bilinear comparison) or jittered lookups make a penumbra of partly lit points,
// wider with both. Same occluder scene as above, a coarse 128² map so that the edge spans texels.
TEST_F(PointCloudGpu, ShadowLookupVariantsOfSeedFigure3_3) {
  TempDir dir;
  const auto mesh = join(geometry::makeBox({-1.0, -1.0, -1.0}, {1.0, 1.0, 0.0}),
                         geometry::makeBox({-0.3, -0.3, 0.4}, {0.3, 0.3, 0.6}));
  const auto obj = writeObj(mesh, dir.path() / "boxes.obj");
  scene::Scene s = testScene(obj, 16);
  const double full = fresnelTransmittance(1.0, 1.3);
  int partial[2][2] = {};
  for (const bool hardware : {false, true})
    for (const int samples : {1, 16}) {
      auto t = technique(8000);
      t->setParameter("shadow_map_size", 128);
      t->setParameter("shadow_hardware_pcf", hardware);
      t->setParameter("shadow_samples", samples);
      t->setParameter("shadow_radius", 2.0);
      t->prepare(s, gpu::testing::context());
      (void)t->render({});
      const auto e = t->gpuIrradiance();
      const auto& cloud = t->pointCloud();
      int& n = partial[hardware][samples > 1];
      for (size_t i = 0; i < cloud.size(); ++i) {
        const glm::dvec3 p(cloud.positions[i]);
        if (std::abs(p.z) > 1e-6 || cloud.normals[i].z < 0.99f) continue;
        const double v = double(e[i].r) / full;
        if (v > 0.02 && v < 0.98) ++n;
      }
    }
  std::printf("points in the penumbra: none %d, hardware %d, jittered %d, both %d\n",
              partial[0][0], partial[1][0], partial[0][1], partial[1][1]);
  EXPECT_EQ(partial[0][0], 0);
  EXPECT_GT(partial[1][0], 10);
  EXPECT_GT(partial[0][1], 10);
  EXPECT_GT(partial[1][1], partial[1][0]);
}

TEST_F(PointCloudGpu, FilteredDirectionalLightProjectsTheTexture) {
  // The built-in 8x8 checker (1 and 0.05) along +z over a box face, one repeat per 0.5 units:
  // texel (floor(8 (u/0.5 + 1/2)), ...) with u = p·U, v = p·V (FilteredDirectionalLight).
  TempDir dir;
  const auto obj = writeObj(geometry::makeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.0}), dir.path() / "box.obj");
  scene::Scene s = testScene(obj, 16);
  s.lights[0].emitter = scene::FilteredDirectionalLight{{0.0, 0.0, 1.0}, 1.0, "checker", 0.5};
  auto t = technique(6000);
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  const auto e = t->gpuIrradiance();
  const auto& cloud = t->pointCloud();
  const double full = fresnelTransmittance(1.0, 1.3);
  int checked = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const glm::dvec3 p(cloud.positions[i]);
    if (std::abs(p.z) > 1e-6) continue;
    // Light along +z: U = +x, V = z × x = +y.
    const double tu = 8.0 * (p.x / 0.5 + 0.5), tv = 8.0 * (p.y / 0.5 + 0.5);
    const double fu = tu - std::floor(tu), fv = tv - std::floor(tv);
    if (std::min({fu, 1.0 - fu, fv, 1.0 - fv}) < 0.02) continue;  // on a texel edge
    const auto iu = static_cast<long>(std::floor(tu)), iv = static_cast<long>(std::floor(tv));
    const double texel = ((((iu % 8) + 8) % 8 + (((iv % 8) + 8) % 8)) % 2 == 0) ? 1.0 : 0.05;
    ++checked;
    EXPECT_LT(relativeError(e[i].g, full * texel), 2e-4) << "point " << i;
  }
  EXPECT_GT(checked, 500);
}

// ---- against independent references ---------------------------------------------------------

// The dipole on the lit sphere: the point-cloud image against BSSRDF integration over the sphere
// (reference/sphere_integration.h: Monte Carlo, exact profile, exact surface, Euclidean distance,
// the same Ft cos irradiance, pixel averages of the same orthographic camera). The light comes
// from 37° to the right of the camera, so B falls from the lit right side to the unlit left one;
// compared on 8 vertical bands of 8 pixel columns, over the pixels inside 0.9 R (away from the
// silhouette, where pixel centres and pixel averages differ), where B is above 2% of its
// maximum. The difference is the technique's: 20k blue-noise points (spacing ≈ 0.55 ℓ'), a
// faceted sphere, the ε clustering and the profile table. Tolerance per band: 2.5% plus three
// reference standard errors (≈ 0.5% each).
TEST_F(PointCloudGpu, DipoleOnTheLitSphereMatchesSphereIntegration) {
  TempDir dir;
  reference::SphereScene ss;
  ss.radius = 1.0;
  ss.light_direction = glm::normalize(glm::dvec3(0.6, 0.0, 0.8));
  ss.view_direction = {0.0, 0.0, 1.0};
  ss.width = ss.height = 64;
  const Medium medium = preset("Marble").medium(10.0);

  const auto obj = writeObj(geometry::makeIcosphere(6, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 64);
  s.medium = medium;
  s.lights[0].emitter = reference::DirectionalLight{ss.light_direction, 1.0};
  s.camera = ss.camera();
  auto t = technique(20000);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  const auto& b = f.layers.at("exitance");

  reference::IntegrationOptions io;
  io.seed = 7;
  reference::SphereIntegrator integrator(bssrdf::model("dipole"), ss, medium, io);
  integrator.addPass(128);
  const reference::McImage& ref = integrator.images().exitance;

  const double pixel = 2.0 * ss.margin / ss.width;  // image-plane size of a pixel (R = 1)
  double maxRef = 0.0, worst = 0.0;
  struct Band { double pc, ref, err; };
  std::vector<Band> bands;
  for (int band = 0; band < 8; ++band) {
    std::vector<uint32_t> pixels;
    for (int y = 0; y < 64; ++y)
      for (int x = band * 8; x < band * 8 + 8; ++x)
        if (std::hypot((x + 0.5 - 32.0) * pixel, (y + 0.5 - 32.0) * pixel) < 0.9)
          pixels.push_back(uint32_t(y * 64 + x));
    if (pixels.size() < 100) continue;
    for (int c = 0; c < 3; ++c) {
      double pc = 0.0;
      for (uint32_t p : pixels) pc += double(b[size_t(p) * 3 + size_t(c)]);
      const reference::Estimate r = ref.average(pixels, c);
      bands.push_back({pc / double(pixels.size()), r.value, r.std_error});
      maxRef = std::max(maxRef, r.value);
    }
  }
  ASSERT_GE(bands.size(), 3u * 6u);
  int compared = 0;
  for (size_t i = 0; i < bands.size(); ++i) {
    const Band& band = bands[i];
    if (band.ref < 0.02 * maxRef) continue;
    ++compared;
    worst = std::max(worst, relativeError(band.pc, band.ref));
    EXPECT_LT(std::abs(band.pc - band.ref), 0.025 * band.ref + 3.0 * band.err)
        << "band " << i / 3 << " channel " << i % 3 << ": point cloud " << band.pc
        << ", reference " << band.ref << " ± " << band.err;
  }
  EXPECT_GE(compared, 12);
  ::testing::Test::RecordProperty("worst_band_error", std::to_string(worst));
}

// Orbiting (issue 14 §6): setCamera keeps the lighting. An occluded environment goes on
// accumulating across camera moves (it converges after the same 4 frames of 64 directions as
// with a still camera, the irradiance equal to the still run's), the frames after the first
// render no shadow maps and no irradiance pass, and the image at the new camera equals a fresh
// prepare at that camera.
TEST_F(SphereIrradiance, CameraMovesKeepTheLightingAndTheEnvironmentAccumulation) {
  const auto map = EnvironmentMap::constant(glm::vec3(1.0f), 32, 16);
  analysis::writeExr((dir.path() / "white.exr").string(), map.width, map.height, map.rgb);
  scene::Scene s = testScene(obj, 16);
  s.lights[0].emitter = scene::EnvironmentLight{dir.path() / "white.exr", 1.0, 0.0, true};
  auto settings = [](PointCloudTechnique& t) {
    t.setParameter("ibl_samples", 256);
    t.setParameter("ibl_samples_per_frame", 64);
    t.setParameter("shadow_map_size", 512);
  };
  auto still = technique(2000);
  settings(*still);
  still->prepare(s, gpu::testing::context());
  for (int i = 0; i < 4; ++i) (void)still->render({});
  const auto eStill = still->gpuIrradiance();

  auto moving = technique(2000);
  settings(*moving);
  moving->prepare(s, gpu::testing::context());
  int frames = 0;
  techniques::Frame f;
  reference::Camera camera = s.camera;
  do {
    if (frames > 0) {
      camera.position = glm::dvec3(glm::rotate(glm::dmat4(1.0), 0.3, glm::dvec3(0.0, 1.0, 0.0)) *
                                   glm::dvec4(camera.position, 1.0));
      ASSERT_TRUE(moving->setCamera(camera));
    }
    f = moving->render({});
    ++frames;
    bool lightingPass = false;
    for (const auto& pass : f.passes) lightingPass = lightingPass || pass.name == "shadow maps";
    EXPECT_EQ(lightingPass, frames == 1) << "frame " << frames;
  } while (!f.converged && frames < 10);
  EXPECT_EQ(frames, 4);  // the accumulation was not restarted by the moves
  const auto eMoving = moving->gpuIrradiance();
  ASSERT_EQ(eMoving.size(), eStill.size());
  for (size_t i = 0; i < eStill.size(); ++i)
    ASSERT_LT(relativeError(eMoving[i].g, eStill[i].g), 1e-6) << "point " << i;

  // The image at the last camera: the same as a technique prepared there (with the same
  // converged lighting: converge in one frame).
  scene::Scene moved = s;
  moved.camera = camera;
  auto fresh = technique(2000);
  settings(*fresh);
  fresh->prepare(moved, gpu::testing::context());
  techniques::FrameRequest converge;
  converge.converge = true;
  const auto a = moving->render({}).layers.at("exitance");
  const auto b = fresh->render(converge).layers.at("exitance");
  ASSERT_EQ(a.size(), b.size());
  double peak = 0.0, worst = 0.0;
  for (float v : b) peak = std::max(peak, double(v));
  ASSERT_GT(peak, 0.0);
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(double(a[i]) - double(b[i])));
  EXPECT_LT(worst, 1e-5 * peak);
}

// The directional dipole (issue 14 §1) in the traversal, as its .bssrdf twin with kernel
// 'shader': each point is evaluated with the direction of the light that lit it, each cluster
// with the mean direction of its points' light and their lit normal (radiance.comp,
// PC_DIRECTIONAL). Against the CPU sphere integration of the C++ kernel with the light's true
// direction (an independent computation: Monte Carlo over the sphere, no points, no clusters),
// on bands of pixels across the terminator, the light 50° off the view axis. Also against the
// same traversal with ε = 0.005 (close to brute force: every point summed) for what clustering
// costs in accuracy and time, and against kernel 'table' (the normal-incidence profile), which
// must differ: the light's direction matters.
TEST_F(PointCloudGpu, DirectionalDipoleFollowsTheLightDirectionOnTheLitSphere) {
  TempDir dir;
  reference::SphereScene ss;
  ss.radius = 1.0;
  ss.light_direction = glm::normalize(glm::dvec3(std::sin(50.0 * kPi / 180.0), 0.0,
                                                 std::cos(50.0 * kPi / 180.0)));
  ss.view_direction = {0.0, 0.0, 1.0};
  ss.width = ss.height = 48;
  const Medium medium = preset("Marble").medium(10.0);

  const auto obj = writeObj(geometry::makeIcosphere(6, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 48);
  s.model = "directional-dipole";
  s.medium = medium;
  s.lights[0].emitter = reference::DirectionalLight{ss.light_direction, 1.0};
  s.camera = ss.camera();
  auto render = [&](const std::string& kernel, double epsilon, double& ms) {
    auto t = technique(20000);
    t->setParameter("kernel", kernel);
    t->setParameter("epsilon", epsilon);
    t->prepare(s, gpu::testing::context());
    (void)t->render({});  // builds the programs
    const techniques::Frame f = t->render({});
    ms = f.totalMs();
    return f.layers.at("exitance");
  };
  double msShader = 0.0, msBrute = 0.0, msTable = 0.0;
  const auto b = render("shader", 0.1, msShader);
  const auto brute = render("shader", 0.005, msBrute);
  const auto table = render("table", 0.1, msTable);

  reference::IntegrationOptions io;
  io.seed = 7;
  reference::SphereIntegrator integrator(bssrdf::model("directional-dipole"), ss, medium, io);
  integrator.addPass(128);
  const reference::McImage& ref = integrator.images().exitance;

  const double pixel = 2.0 * ss.margin / ss.width;
  double maxRef = 0.0;
  struct Band { double pc, brute, table, ref, err; };
  std::vector<Band> bands;
  for (int band = 0; band < 8; ++band) {
    std::vector<uint32_t> pixels;
    for (int y = 0; y < 48; ++y)
      for (int x = band * 6; x < band * 6 + 6; ++x)
        if (std::hypot((x + 0.5 - 24.0) * pixel, (y + 0.5 - 24.0) * pixel) < 0.9)
          pixels.push_back(uint32_t(y * 48 + x));
    if (pixels.size() < 60) continue;
    for (int c = 0; c < 3; ++c) {
      double pc = 0.0, br = 0.0, tb = 0.0;
      for (uint32_t p : pixels) {
        pc += double(b[size_t(p) * 3 + size_t(c)]);
        br += double(brute[size_t(p) * 3 + size_t(c)]);
        tb += double(table[size_t(p) * 3 + size_t(c)]);
      }
      const double n = double(pixels.size());
      const reference::Estimate r = ref.average(pixels, c);
      bands.push_back({pc / n, br / n, tb / n, r.value, r.std_error});
      maxRef = std::max(maxRef, r.value);
    }
  }
  ASSERT_GE(bands.size(), 3u * 6u);
  int compared = 0;
  double worst = 0.0, worstCluster = 0.0, largestTableDifference = 0.0;
  for (size_t i = 0; i < bands.size(); ++i) {
    const Band& band = bands[i];
    if (band.ref < 0.02 * maxRef) continue;
    ++compared;
    worst = std::max(worst, relativeError(band.pc, band.ref));
    worstCluster = std::max(worstCluster, relativeError(band.pc, band.brute));
    largestTableDifference = std::max(largestTableDifference, relativeError(band.table, band.pc));
    EXPECT_LT(std::abs(band.pc - band.ref), 0.03 * band.ref + 3.0 * band.err)
        << "band " << i / 3 << " channel " << i % 3 << ": point cloud " << band.pc
        << ", sphere integration " << band.ref << " ± " << band.err;
    EXPECT_LT(relativeError(band.pc, band.brute), 0.01) << "band " << i / 3 << " channel " << i % 3;
  }
  EXPECT_GE(compared, 12);
  EXPECT_GT(largestTableDifference, 0.05);
  std::printf("directional dipole on the lit sphere: worst band error %.2f%% against the sphere "
              "integration, clusters (eps 0.1) vs eps 0.005 %.2f%%, kernel 'table' differs by up "
              "to %.1f%%; frame %.1f ms (eps 0.1), %.1f ms (eps 0.005), %.1f ms (table)\n",
              100.0 * worst, 100.0 * worstCluster, 100.0 * largestTableDifference, msShader,
              msBrute, msTable);
}

// A slab lit by a narrow beam of radius a at normal incidence: the exitance on the top face is
// the profile convolved with the lit disc,
//     B(r) = Ft(η, 1) P/(π a²) ∫_disc R(|x - x'|) dA',
// by quadrature of the exact dipole R(r) (on a fine grid of r, interpolated at each pixel).
// The point cloud only sums lit points, so the slab's finite size does not enter. Compared on
// rings of pixels of width 0.04 (ring averages of both) while B is above 0.25% of B(0).
// Differences come from the ~310 points that sample the disc (their total area is exact only on
// average; the disc's edge is resolved to a point spacing) and the spacing ≈ 0.5 ℓ'; measured
// within 3%, tolerance 4% per ring.
TEST_F(PointCloudGpu, SlabUnderABeamFollowsTheProfile) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeBox({-0.5, -0.5, -0.25}, {0.5, 0.5, 0.0}), dir.path() / "slab.obj");
  scene::Scene s = testScene(obj, 64);
  s.medium.sigma_a = {1.0, 1.0, 1.0};
  s.medium.sigma_s = {50.0, 50.0, 50.0};  // ℓ' = 0.0196, ℓd = 0.081
  s.medium.g = 0.0;
  s.medium.eta = 1.3;
  s.medium.scale = 1.0;
  const double a = 0.1, power = 1.0;
  s.lights[0].emitter = reference::BeamLight{{0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, a, power};
  s.camera.view_height = 1.0;
  auto t = technique(30000);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  const auto& b = f.layers.at("exitance");

  const auto profile = bssrdf::model("dipole").profile(s.medium.channel(0));
  const double ft = fresnelTransmittance(1.0, s.medium.eta);
  auto convolution = [&](double r) {
    // Midpoint rule in polar coordinates about the disc's centre.
    const int ns = 80, nphi = 160;
    double sum = 0.0;
    for (int i = 0; i < ns; ++i) {
      const double rho = a * (i + 0.5) / ns;
      for (int j = 0; j < nphi; ++j) {
        const double phi = 2.0 * kPi * (j + 0.5) / nphi;
        sum += profile->R(std::sqrt(r * r + rho * rho - 2.0 * r * rho * std::cos(phi))) * rho;
      }
    }
    return ft * power / (kPi * a * a) * sum * (a / ns) * (2.0 * kPi / nphi);
  };
  const int grid = 300;
  const double rMax = 0.75;
  std::vector<double> table(grid + 1);
  for (int i = 0; i <= grid; ++i) table[size_t(i)] = convolution(rMax * i / grid);
  auto expected = [&](double r) {
    const double x = r / rMax * grid;
    const auto i = std::min(static_cast<size_t>(x), size_t(grid - 1));
    const double w = x - double(i);
    return (1.0 - w) * table[i] + w * table[i + 1];
  };
  const double pixel = 1.0 / 64.0;
  const double b0 = expected(0.0);
  int rings = 0;
  double worst = 0.0;
  for (int ring = 0; ring < 12; ++ring) {
    const double r0 = 0.04 * ring, r1 = r0 + 0.04;
    double sum = 0.0, want = 0.0;
    int n = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const double r = std::hypot((x + 0.5 - 32.0) * pixel, (y + 0.5 - 32.0) * pixel);
        if (r < r0 || r >= r1) continue;
        sum += double(b[size_t(y * 64 + x) * 3]);
        want += expected(r);
        ++n;
      }
    ASSERT_GT(n, 0);
    // The table ends at the radius holding 99.9% of Rd (the kernel is 0 beyond): rings far out,
    // below 0.25% of B(0), lose a visible part of their little light and are not compared.
    if (want / n < 0.0025 * b0) continue;
    ++rings;
    const double e = relativeError(sum / n, want / n);
    worst = std::max(worst, e);
    EXPECT_LT(e, 0.04) << "ring [" << r0 << ", " << r1 << "): point cloud " << sum / n
                       << ", profile convolution " << want / n;
  }
  EXPECT_GE(rings, 7);
  ::testing::Test::RecordProperty("worst_ring_error", std::to_string(worst));
}

// ---- bad input ------------------------------------------------------------------------------

std::string prepareError(PointCloudTechnique& t, const scene::Scene& s) {
  try {
    t.prepare(s, gpu::testing::context());
    (void)t.render({});
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(PointCloudGpu, BadMeshesGiveClearErrors) {
  TempDir dir;
  auto t = technique(1000);
  scene::Scene s = testScene(dir.path() / "missing.obj", 16);
  EXPECT_NE(prepareError(*t, s).find("missing.obj"), std::string::npos) << prepareError(*t, s);
  s.mesh_file = dir.write("empty.obj", "");
  EXPECT_NE(prepareError(*t, s).find("empty"), std::string::npos) << prepareError(*t, s);
  // An open surface (a single square) is not an error for points, which need no interior
  // (issue 14 §5; test_open_mesh_gpu.cpp renders one and checks the others' refusal).
  s.mesh_file = dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  EXPECT_EQ(prepareError(*t, s), "no error");
  // The technique still works after the failures.
  s.mesh_file = writeObj(geometry::makeIcosphere(2, 1.0), dir.path() / "ok.obj");
  EXPECT_EQ(prepareError(*t, s), "no error");
}

TEST_F(PointCloudGpu, BadMaterialsModelsAndParametersGiveClearErrors) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(2, 1.0), dir.path() / "sphere.obj");
  auto t = technique(1000);
  scene::Scene s = testScene(obj, 16);

  scene::Scene nan = s;
  nan.medium.sigma_a[1] = std::nan("");
  EXPECT_NE(prepareError(*t, nan).find("sigma_a"), std::string::npos) << prepareError(*t, nan);

  scene::Scene unknown = s;
  unknown.model = "dipol";
  EXPECT_NE(prepareError(*t, unknown).find("dipole"), std::string::npos) << prepareError(*t, unknown);

  // A malformed .bssrdf file (no shader section) and one whose GLSL does not compile: the
  // error names the file (and for GLSL, the line).
  scene::Scene malformed = s;
  malformed.model = dir.write("broken.bssrdf", "analytic radial\n::begin parameters\n").string();
  EXPECT_NE(prepareError(*t, malformed).find("broken.bssrdf"), std::string::npos)
      << prepareError(*t, malformed);
  scene::Scene glsl = s;
  glsl.model = dir.write("glsl.bssrdf",
                         "analytic radial no_wi no_wo\n"
                         "::begin shader\n"
                         "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                         "  return undefined_name * vec3(1.0);\n"
                         "}\n"
                         "::end shader\n")
                   .string();
  t->setParameter("kernel", std::string("shader"));
  const std::string glslError = prepareError(*t, glsl);
  EXPECT_NE(glslError.find("glsl.bssrdf:4"), std::string::npos) << glslError;

  // Parameters: NaN, out of range, wrong type, unknown name.
  auto paramError = [&](std::string_view name, const techniques::ParameterValue& v) -> std::string {
    try {
      t->setParameter(name, v);
    } catch (const ParameterError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(paramError("epsilon", std::nan("")).find("epsilon"), std::string::npos);
  EXPECT_NE(paramError("points", 10).find("[1000, 5000000]"), std::string::npos);
  EXPECT_NE(paramError("points", 1500.5).find("whole number"), std::string::npos);
  EXPECT_NE(paramError("kernel", std::string("magic")).find("table, shader"), std::string::npos);
  EXPECT_NE(paramError("specular", std::string("maybe")).find("true or false"), std::string::npos);
  EXPECT_NE(paramError("epsilom", 0.1).find("valid parameters are"), std::string::npos);

  // Lights the technique cannot do.
  t->setParameter("kernel", std::string("table"));
  scene::Scene pencil = s;
  pencil.lights[0].emitter = reference::BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.0, 1.0};
  EXPECT_NE(prepareError(*t, pencil).find("radius"), std::string::npos) << prepareError(*t, pencil);
  scene::Scene inside = s;
  inside.lights[0].emitter = reference::PointLight{{0.1, 0.0, 0.0}, 1.0};
  EXPECT_NE(prepareError(*t, inside).find("bounding sphere"), std::string::npos);
  scene::Scene noEnv = s;
  noEnv.lights[0].emitter = scene::EnvironmentLight{dir.path() / "nowhere.exr", 1.0, 0.0, false};
  EXPECT_NE(prepareError(*t, noEnv).find("nowhere.exr"), std::string::npos);
  EXPECT_EQ(prepareError(*t, s), "no error");
}

}  // namespace
}  // namespace translucent::pointcloud
