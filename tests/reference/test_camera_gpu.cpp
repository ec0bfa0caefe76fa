// SPDX-License-Identifier: GPL-3.0-or-later
// The camera method's GPU walk (reference/gpu/camera_gpu.h, shaders/reference/camera_walk.comp)
// against the CPU's camera method (camera_paths.h), pixel by pixel (z maps of the true radiance,
// the exitance and the diffusion radiance, and of the single-scattered exitance): a sphere under
// a sun, a point light and a beam; the bunny (non-convex: flights in air, re-entries, shadow
// rays through several parts) of a little-absorbing medium whose long paths are suspended and
// resumed on llvmpipe; a cone average; a heterogeneous sphere (delta and ratio tracking);
// through a refractive boundary (a sphere, the bunny, a thin plate per order, the half-space's
// closed form); environment lights; the same images whatever the pass split; the refusal of a
// field without a GLSL twin. GL runs on whatever EGL offers (llvmpipe here): small images, bounds from the
// standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gpu/gpu_test.h"
#include "image_zmap.h"
#include "mesh_test_scenes.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/lights/environment_map.h"
#include "translucent/material/checker.h"
#include "translucent/material/medium_desc.h"
#include "translucent/optics/presets.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/gpu/camera_gpu.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/gpu/mesh_gpu.h"

namespace translucent::reference {
namespace {

using gpu::testing::GpuTest;
using test_support::bonferroniZ;
constexpr double kPi = 3.14159265358979323846;
using test_support::ZMap;
using test_support::zmap;
using test_support::meanAndError;

class CameraGpu : public GpuTest {};

// The GPU camera walk on `t`, and at η ≠ 1 its light-traced complement in the light method's GPU
// walk (as useDevice does).
void useGpu(CameraPathTracer& t, const geometry::TriangleMesh& mesh) {
  t.setWalker(makeGpuCameraWalker(gpu::testing::context(), mesh),
              t.hasComplement() ? makeGpuMeshWalker(gpu::testing::context(), mesh) : nullptr);
}

material::Material volume(std::shared_ptr<const material::VolumeField> field) {
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium.eta = 1.0;
  m.medium.scale = 1.0;
  m.volume = std::move(field);
  return m;
}

// A field without a GLSL twin.
struct OpaqueField final : material::VolumeField {
  material::LocalMedium at(const glm::dvec3&) const override { return {{0.1, 0.1, 0.1}, {1.0, 1.0, 1.0}, 0.0}; }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override { return {1.1, 1.1, 1.1}; }
};

Medium medium(const Rgb& sigma_a, const Rgb& sigma_s, double g) {
  return test_support::indexMatched(sigma_a, sigma_s, g);
}

Camera cameraAt(const glm::dvec3& position, int size) {
  return test_support::pinholeAtOrigin(position, size);
}

const geometry::TriangleMesh& bunny() { return test_support::unitBunny(); }

// Mean z² within 6 of its standard deviations sqrt(2/N) of 1 and no value beyond the
// Bonferroni-corrected 1% threshold, over at least `minValues` pixel values; and per channel the
// image means within 4 standard errors (far more sensitive to a small bias than the pixels).
void expectAgree(const McImage& g, const McImage& c, int minValues, const std::string& what) {
  std::vector<uint32_t> all(static_cast<size_t>(g.width() * g.height()));
  for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  for (int ch = 0; ch < g.channels(); ++ch) {
    const Estimate a = g.average(all, ch), b = c.average(all, ch);
    EXPECT_GT(a.value, 0.0) << what;
    EXPECT_NEAR(a.value, b.value, 4.0 * std::hypot(a.std_error, b.std_error))
        << what << " channel " << ch << ": image mean GPU " << a.value << " ± " << a.std_error
        << ", CPU " << b.value << " ± " << b.std_error;
  }
  const ZMap m = zmap(g, c);
  EXPECT_GT(m.n, minValues) << what;
  EXPECT_NEAR(m.meanZ2, 1.0, 6.0 * std::sqrt(2.0 / std::max(m.n, 1)))
      << what << ": mean z² over " << m.n << " pixel values";
  EXPECT_LT(m.maxAbs, bonferroniZ(m.n, 0.01)) << what << ": largest |z| over " << m.n;
}

void expectImagesAgree(const CameraPathTracer& g, const CameraPathTracer& c, int minValues) {
  expectAgree(g.images().cone_radiance, c.images().cone_radiance, minValues, "radiance to the camera");
  expectAgree(g.images().exitance, c.images().exitance, minValues, "exitance");
  expectAgree(g.images().radiance, c.images().radiance, minValues, "diffusion radiance");
  if (g.splitsOrders() && c.splitsOrders()) {
    expectAgree(g.orderImages(ScatteringOrder::Single).exitance,
                c.orderImages(ScatteringOrder::Single).exitance, minValues, "single-scattered exitance");
    expectAgree(g.orderImages(ScatteringOrder::Multiple).cone_radiance,
                c.orderImages(ScatteringOrder::Multiple).cone_radiance, minValues,
                "multiply scattered radiance to the camera");
  }
}

// The CPU's and the GPU's camera paths of one scene, different seeds (independent estimates).
void expectGpuMatchesCpu(const geometry::TriangleMesh& mesh, const Medium& m,
                         const std::vector<Light>& lights, const Camera& camera,
                         CameraPathOptions o, uint64_t samples, int minValues) {
  o.threads = 2;
  o.split_orders = true;
  o.seed = 3;
  CameraPathTracer cpu(mesh, m, lights, camera, o);
  cpu.addPass(samples);
  o.seed = 4;
  CameraPathTracer gpu(mesh, m, lights, camera, o);
  useGpu(gpu, mesh);
  EXPECT_NE(gpu.device().find("gpu ("), std::string::npos) << gpu.device();
  gpu.addPass(samples);
  EXPECT_EQ(gpu.stats().samples, samples);
  EXPECT_GT(gpu.stats().scattering_events, 0u);
  EXPECT_GT(gpu.stats().shadow_rays, 0u);
  expectImagesAgree(gpu, cpu, minValues);
}

TEST_F(CameraGpu, SphereUnderASunAPointLightAndABeamMatchesTheCpu) {
  const auto mesh = geometry::makeIcosphere(3);
  const std::vector<Light> lights = test_support::threeLightTypes();
  expectGpuMatchesCpu(mesh, medium({0.5, 1.0, 2.0}, {4.0, 4.0, 4.0}, 0.2), lights,
                      cameraAt({0.0, 0.5, 3.5}, 10), {}, 64, 150);
}

// The bunny (non-convex: flights in air and re-entries, shadow rays through several parts)
// lit from behind (its light through the ears) and from the front.
TEST_F(CameraGpu, BunnyMatchesTheCpu) {
  const std::vector<Light> lights = {
      Light{DirectionalLight{glm::normalize(glm::dvec3(-0.2, 0.3, -1.0)), 1.0}, {1.0, 1.0, 1.0}},
      Light{PointLight{{0.8, 1.5, 1.8}, 1.0}, {1.0, 0.8, 0.6}}};
  expectGpuMatchesCpu(bunny(), medium({0.2, 0.5, 1.0}, {10.0, 10.0, 10.0}, 0.0), lights,
                      cameraAt({0.0, 0.3, 3.2}, 12), {}, 32, 90);
}

// A cube 200 mean free paths across without absorption, seen face on: a path that enters scatters
// about as many times as the slab is thick in mean free paths before it leaves (a random walk
// between two walls), each collision with a shadow ray through the BVH: far beyond what
// llvmpipe's loop limit lets one dispatch do, so every long path is suspended and resumed. Cut
// short, its light would be lost; resumed, the collisions per path and the images are the CPU's.
TEST_F(CameraGpu, LongPathsAreSuspendedAndResumedNotCutShort) {
  const auto cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const ScalarMedium m{0.0, 200.0, 0.0, 1.0};
  const std::vector<Light> lights = {
      Light{DirectionalLight{glm::normalize(glm::dvec3(0.3, 0.2, 1.0)), 1.0}, {1.0, 1.0, 1.0}}};
  Camera camera = test_support::orthographic({0.0, 0.0, 3.0}, 0.9, 8);
  CameraPathOptions o;
  o.threads = 2;
  o.seed = 5;
  CameraPathTracer cpu(cube, m, lights, camera, o);
  o.seed = 6;
  CameraPathTracer gpu(cube, m, lights, camera, o);
  useGpu(gpu, cube);
  std::vector<double> g, c;
  for (int p = 0; p < 8; ++p) {
    const CameraPathStats a = gpu.addPass(4), b = cpu.addPass(4);
    g.push_back(static_cast<double>(a.scattering_events) / static_cast<double>(a.paths));
    c.push_back(static_cast<double>(b.scattering_events) / static_cast<double>(b.paths));
  }
  EXPECT_EQ(gpu.stats().paths, cpu.stats().paths);  // every camera ray hits: two paths each
  const auto [gm, ge] = meanAndError(g);
  const auto [cm, ce] = meanAndError(c);
  EXPECT_GT(cm, 50.0);
  EXPECT_NEAR(gm, cm, 5.0 * std::hypot(ge, ce)) << "collisions per path: GPU " << gm << " ± " << ge
                                                << ", CPU " << cm << " ± " << ce;
  expectAgree(gpu.images().exitance, cpu.images().exitance, 50, "exitance");
  expectAgree(gpu.images().cone_radiance, cpu.images().cone_radiance, 50, "radiance to the camera");
}

TEST_F(CameraGpu, ConeAverageMatchesTheCpu) {
  const auto cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const std::vector<Light> lights = {
      Light{DirectionalLight{glm::normalize(glm::dvec3(-0.3, 1.0, 0.5)), 1.0}, {1.0, 1.0, 1.0}},
      Light{BeamLight{{0.2, 0.1, 3.0}, {0.0, 0.0, -1.0}, 0.3, 0.5}, {1.0, 1.0, 1.0}}};
  CameraPathOptions o;
  o.cone_half_angle = 15.0;
  Medium m = medium({0.5, 1.0, 2.0}, {3.0, 3.0, 3.0}, 0.5);
  expectGpuMatchesCpu(cube, m, lights, cameraAt({1.6, 1.2, 2.2}, 10), o, 64, 100);
}

// A 3D checker of two media (σt 2-4 and 3-9 per unit, g 0.2 and 0.75) in the unit sphere, the
// material frame rotated and moved: delta tracking for the flights, ratio tracking for the
// shadow rays, the local albedo and g at each collision; the true radiance and a cone average.
TEST_F(CameraGpu, HeterogeneousSphereMatchesTheCpu) {
  const auto mesh = geometry::makeIcosphere(3);
  material::CheckerDesc desc;
  desc.cell = {0.7, 0.5, 0.9};
  desc.media = {material::mediumDesc({0.3, 0.1, 0.05}, {2.0, 3.0, 4.0}, 0.2),
                material::mediumDesc({0.02, 0.03, 0.4}, {9.0, 6.0, 2.5}, 0.75)};
  material::Material mat = volume(std::make_shared<material::CheckerField>(desc));
  const double a = 0.5;
  mat.frame.rotation = glm::dmat3(std::cos(a), 0.0, -std::sin(a), 0.0, 1.0, 0.0, std::sin(a), 0.0, std::cos(a));
  mat.frame.translate = {0.1, -0.2, 0.15};
  const std::vector<Light> lights = {
      Light{DirectionalLight{glm::normalize(glm::dvec3(0.4, 0.2, 1.0)), 1.0}, {1.0, 1.0, 1.0}},
      Light{PointLight{{1.2, -1.5, 1.4}, 1.5}, {0.8, 0.8, 1.0}}};
  const Camera camera = cameraAt({0.0, -2.0, 3.5}, 10);
  for (const double cone : {0.0, 10.0}) {
    SCOPED_TRACE(::testing::Message() << "cone " << cone);
    CameraPathOptions o;
    o.threads = 2;
    o.split_orders = true;
    o.cone_half_angle = cone;
    o.seed = 8;
    CameraPathTracer cpu(mesh, mat, lights, camera, o);
    const uint64_t samples = cone > 0.0 ? 64 : 256;
    cpu.addPass(samples);
    o.seed = 9;
    CameraPathTracer gpu(mesh, mat, lights, camera, o);
    useGpu(gpu, mesh);
    gpu.addPass(samples);
    expectImagesAgree(gpu, cpu, 100);
    EXPECT_EQ(gpu.majorantViolations(), 0u);
  }
}

// Through a refractive boundary (η = 1.3): the camera rays refracted in with Ft / η², Fresnel
// reflection or refraction wherever a path meets the boundary, the refracted connections of every
// facet to every light searched on the device (a sun, a point light by the Fermat solve, a beam),
// the unscattered light refracted out at the visible point; the light-traced complement in the
// light method's GPU walk (TracerOptions::after_specular_only) against the CPU's.
TEST_F(CameraGpu, RefractiveSphereUnderASunAPointLightAndABeamMatchesTheCpu) {
  const auto mesh = geometry::makeIcosphere(3);
  Medium m = medium({0.5, 1.0, 2.0}, {4.0, 4.0, 4.0}, 0.2);
  m.eta = 1.3;
  const std::vector<Light> lights = test_support::threeLightTypes();
  CameraPathOptions o;
  o.cone_half_angle = 0.0;
  expectGpuMatchesCpu(mesh, m, lights, cameraAt({0.0, 0.5, 3.5}, 10), o, 96, 150);
}

// The bunny at η = 1.3 (connections through several facets, paths through the ears), lit from
// behind and from the front.
TEST_F(CameraGpu, RefractiveBunnyMatchesTheCpu) {
  Medium m = medium({0.2, 0.5, 1.0}, {10.0, 10.0, 10.0}, 0.0);
  m.eta = 1.3;
  const std::vector<Light> lights = {
      Light{DirectionalLight{glm::normalize(glm::dvec3(-0.2, 0.3, -1.0)), 1.0}, {1.0, 1.0, 1.0}},
      Light{PointLight{{0.8, 1.5, 1.8}, 1.0}, {1.0, 0.8, 0.6}}};
  expectGpuMatchesCpu(bunny(), m, lights, cameraAt({0.0, 0.3, 3.2}, 12), {}, 48, 90);
}

// A thin refractive plate (optical depth 0.2) between a point light and the camera: the light
// refracted in and out unscattered (the Fermat solve, the refracted pencil's irradiance, Ft on
// both sides) and single scattering dominate, and the camera method's estimates of both have
// little noise: the GPU's images per scattering order against the CPU's at 0.1% (unscattered) and
// 2.5% (single) errors of their means (dropping the Ft of the exit, or a 5% error in the
// refracted pencil's width, moved the unscattered mean by 20 standard errors).
TEST_F(CameraGpu, PointLightThroughAThinRefractivePlateMatchesTheCpuPerOrder) {
  const auto plate = geometry::makeBox({-1.0, -1.0, -0.1}, {1.0, 1.0, 0.1});
  const ScalarMedium m{0.5, 0.5, 0.3, 1.3};
  const std::vector<Light> lights = {Light{PointLight{{0.3, 0.2, -1.0}, 2.0}, {1.0, 1.0, 1.0}}};
  Camera camera = test_support::orthographic({0.0, 0.0, 3.0}, 1.6, 8);
  CameraPathOptions o;
  o.threads = 2;
  o.split_orders = true;
  o.complement_photons = 0;  // the same light on both sides: the orders' images compared
  o.seed = 21;
  CameraPathTracer cpu(plate, m, lights, camera, o);
  cpu.addPass(128);
  o.seed = 22;
  CameraPathTracer gpu(plate, m, lights, camera, o);
  useGpu(gpu, plate);
  gpu.addPass(128);
  for (const ScatteringOrder k : {ScatteringOrder::Unscattered, ScatteringOrder::Single}) {
    const std::string name = k == ScatteringOrder::Single ? "single-scattered" : "unscattered";
    expectAgree(gpu.orderImages(k).exitance, cpu.orderImages(k).exitance, 50, name + " exitance");
    expectAgree(gpu.orderImages(k).radiance, cpu.orderImages(k).radiance, 50, name + " diffusion radiance");
    std::vector<uint32_t> all(64);
    for (uint32_t i = 0; i < 64; ++i) all[i] = i;
    const Estimate e = gpu.orderImages(k).exitance.average(all, 0);
    EXPECT_LT(e.std_error, 0.03 * e.value) << name;
  }
}

// The Marble bunny (25 mm per unit: dense) at η = 1.3 under two suns, as the explorer's default
// scene: a collision's refracted connections list hundreds of facets, so that paths are suspended
// often; two runs of the same seed agree bit for bit (with too large a budget per dispatch,
// llvmpipe cut some paths silently: runs differed, 185,458 and 190,776 collisions here, and lost
// about 6% of them).
TEST_F(CameraGpu, RefractiveBunnyIsTheSameOnEveryRun) {
  const Preset& marble = preset("Marble");
  Medium m = Medium::fromReduced(marble.sigma_a, marble.sigma_s_prime, marble.g, marble.eta);
  m.scale = 25.0;
  const std::vector<Light> lights = {
      Light{DirectionalLight{glm::normalize(glm::dvec3(-0.3, 0.9, -0.6)), 5.0}, {1.0, 0.85, 0.7}},
      Light{DirectionalLight{glm::normalize(glm::dvec3(0.6, 0.2, 1.0)), 0.12}, {0.7, 0.8, 1.0}}};
  Camera camera = cameraAt({0.15, 0.2, 2.1}, 16);
  camera.fov = 35.0;
  CameraPathOptions o;
  o.seed = 1;
  o.complement_photons = 0;
  std::vector<CameraImages> images;
  std::vector<uint64_t> collisions;
  for (int run = 0; run < 2; ++run) {
    CameraPathTracer t(bunny(), m, lights, camera, o);
    useGpu(t, bunny());
    t.addPass(4);
    images.push_back(t.images());
    collisions.push_back(t.stats().scattering_events);
  }
  EXPECT_EQ(collisions[0], collisions[1]);
  EXPECT_GT(collisions[0], 0u);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(images[0].exitance.pixel(x, y, c).value, images[1].exitance.pixel(x, y, c).value);
        ASSERT_EQ(images[0].cone_radiance.pixel(x, y, c).value,
                  images[1].cone_radiance.pixel(x, y, c).value);
      }
}

// A sun on a half-space (a wide box, seen obliquely by an orthographic camera) at η = 1.3: the
// single-scattered radiance has a closed form in every pixel (Hanrahan & Krueger 1993, the sun
// and the camera ray refracted): Ft(θo) / η² α p(d_c·d_l) E Ft(θl) cos θl / (cos θt,l + cos θt,o).
TEST_F(CameraGpu, SunOnARefractiveHalfSpaceGivesTheClosedFormSingleScattering) {
  const auto box = geometry::makeBox({-6.0, -6.0, -3.0}, {6.0, 6.0, 0.0});
  const ScalarMedium m{2.0, 2.0, 0.4, 1.3};
  const double eta = 1.3;
  const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, 0.2, 1.0));
  Camera camera = test_support::orthographic({0.0, -10.0, 10.0}, 2.0, 8);
  camera.up = {0.0, 0.0, 1.0};
  const glm::dvec3 d = glm::normalize(glm::dvec3(0.0, 10.0, -10.0));
  auto refracted = [&](const glm::dvec3& w, double& cosI, double& cosT) {
    cosI = -w.z;
    cosT = std::sqrt(1.0 - (1.0 - cosI * cosI) / (eta * eta));
    return glm::normalize(w / eta + (cosI / eta - cosT) * glm::dvec3(0.0, 0.0, 1.0));
  };
  double cosIo = 0.0, cosTo = 0.0, cosIl = 0.0, cosTl = 0.0;
  const glm::dvec3 dc = refracted(d, cosIo, cosTo), dl = refracted(-sun, cosIl, cosTl);
  auto ft = [&](double c) {  // Fresnel's equations for unpolarised light from air
    const double ct = std::sqrt(1.0 - (1.0 - c * c) / (eta * eta));
    const double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
  };
  const double g = 0.4, mu = glm::dot(dc, -dl);
  const double phase = 0.5 * (1.0 - g * g) / std::pow(1.0 + g * g - 2.0 * g * mu, 1.5) / (2.0 * kPi);
  const double exact = ft(cosIo) / (eta * eta) * 0.5 * phase * 1.5 * ft(cosIl) * cosIl / (cosTl + cosTo);
  CameraPathOptions o;
  o.seed = 55;
  o.split_orders = true;
  o.exitance = false;
  o.complement_photons = 0;  // a flat top: no light meets the boundary again before it scatters
  CameraPathTracer t(box, m, {Light{DirectionalLight{sun, 1.5}, {1.0, 1.0, 1.0}}}, camera, o);
  useGpu(t, box);
  t.addPass(512);
  const McImage& single = t.orderImages(ScatteringOrder::Single).cone_radiance;
  const double bound = bonferroniZ(64, 0.01);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const Estimate e = single.pixel(x, y, 0);
      ASSERT_GT(e.std_error, 0.0);
      EXPECT_LT(std::abs(e.value - exact) / e.std_error, bound)
          << "pixel " << x << "," << y << ": " << e.value << " ± " << e.std_error << ", exact " << exact;
    }
  std::vector<uint32_t> all(64);
  for (uint32_t i = 0; i < 64; ++i) all[i] = i;
  const Estimate mean = single.average(all, 0);
  EXPECT_NEAR(mean.value, exact, 3.5 * mean.std_error) << mean.value << " ± " << mean.std_error;
  EXPECT_LT(mean.std_error, 0.01 * exact);
}

// Each path draws from its own stream (the sample's index), so the pass split changes only the
// order of the sums: equal to rounding, as on the CPU; and a run is a function of its seed.
class CameraGpuDeterminism : public GpuTest, public ::testing::WithParamInterface<double> {};

TEST_P(CameraGpuDeterminism, SameSeedSameImagesWhateverThePassSplit) {
  const auto cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const std::vector<Light> lights = {
      Light{PointLight{{1.5, 0.5, 1.0}, 0.4}, {1.0, 0.7, 0.5}}};
  Medium m = medium({0.5, 1.0, 2.0}, {3.0, 3.0, 3.0}, 0.0);
  m.eta = GetParam();
  const Camera camera = cameraAt({1.6, 1.2, 2.2}, 8);
  std::vector<CameraImages> images;
  for (const int run : {0, 1, 2}) {
    CameraPathOptions o;
    o.seed = 17;
    CameraPathTracer t(cube, m, lights, camera, o);
    useGpu(t, cube);
    if (run < 2) {
      t.addPass(16);
    } else {
      t.addPass(4);
      t.addPass(12);
    }
    EXPECT_EQ(t.stats().samples, 16u);
    images.push_back(t.images());
  }
  double total = 0.0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) {
        const Estimate a = images[0].exitance.pixel(x, y, c), b = images[1].exitance.pixel(x, y, c);
        const Estimate p = images[0].cone_radiance.pixel(x, y, c);
        ASSERT_EQ(a.value, b.value);
        ASSERT_EQ(a.std_error, b.std_error);
        ASSERT_EQ(p.value, images[1].cone_radiance.pixel(x, y, c).value);
        const Estimate e = images[2].exitance.pixel(x, y, c);
        ASSERT_NEAR(a.value, e.value, 1e-12 * std::abs(a.value));
        ASSERT_NEAR(a.std_error, e.std_error, 1e-9 * a.std_error);
        ASSERT_NEAR(p.value, images[2].cone_radiance.pixel(x, y, c).value, 1e-12 * std::abs(p.value));
        total += p.value;
      }
  EXPECT_GT(total, 0.0);
}
INSTANTIATE_TEST_SUITE_P(Eta, CameraGpuDeterminism, ::testing::Values(1.0, 1.3));

// Environment lights: next-event estimation by the map's sampler per channel combined with the
// escaping paths by the balance heuristic (η = 1), the escaping paths alone through a refractive
// boundary (η = 1.3, refracted out with η²), the unscattered sky seen through the body; a map
// brighter towards one side and coloured, rotated, with a sun.
TEST_F(CameraGpu, EnvironmentLightsMatchTheCpu) {
  const auto mesh = geometry::makeIcosphere(3);
  auto map = std::make_shared<lights::EnvironmentMap>();
  map->width = 32;
  map->height = 16;
  for (int y = 0; y < map->height; ++y)
    for (int x = 0; x < map->width; ++x) {
      const float sky = 0.2f + 2.0f * static_cast<float>(x) / 32.0f * (y < 6 ? 1.0f : 0.1f);
      map->rgb.insert(map->rgb.end(), {sky, 0.8f * sky, 0.5f * sky + 0.1f});
    }
  const std::vector<Light> lights = {
      Light{EnvironmentLight::make(map, 30.0, 0.7), {1.0, 0.9, 1.0}},
      Light{DirectionalLight{glm::normalize(glm::dvec3(0.4, 0.3, 1.0)), 1.0}, {1.0, 0.9, 0.8}}};
  for (const double eta : {1.0, 1.3}) {
    SCOPED_TRACE(::testing::Message() << "eta " << eta);
    Medium m = medium({0.5, 1.0, 2.0}, {2.0, 2.0, 2.0}, 0.3);
    m.eta = eta;
    expectGpuMatchesCpu(mesh, m, lights, cameraAt({0.0, 0.5, 3.5}, 10), {}, 96, 150);
  }
}

// A field without a GLSL twin: useDevice refuses it with "gpu" naming why, and keeps the CPU with
// "auto".
TEST_F(CameraGpu, RefusesAFieldWithoutAGlslTwin) {
  const auto cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const Camera camera = cameraAt({1.6, 1.2, 2.2}, 4);
  const Light sun{DirectionalLight{{0.0, 0.0, 1.0}, 1.0}, {1.0, 1.0, 1.0}};
  CameraPathTracer c(cube, volume(std::make_shared<OpaqueField>()), {sun}, camera, {});
  const TraceDevice dev{Device::Gpu, nullptr};
  try {
    useDevice(dev, "gpu", c, cube, "cube");
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("--device gpu: "), std::string::npos) << e.what();
  }
  useDevice(dev, "auto", c, cube, "cube");
  EXPECT_EQ(c.device(), "cpu");
}

}  // namespace
}  // namespace translucent::reference
