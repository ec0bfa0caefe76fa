// SPDX-License-Identifier: GPL-3.0-or-later
// The mesh tracer's GPU walk (reference/gpu/mesh_gpu.h) against analytic fluxes (a cube under a
// beam, three index-matched cubes in a row) and against the CPU tracer pixel by pixel on a cube
// (two directional lights; an environment light) and on the bunny (non-convex: exits, flights
// in air, re-entries; a point light); heterogeneous media (delta tracking through the majorant
// grid, the fields of fields.glsl) against the CPU's delta tracking; same seed, same images
// whatever the pass split; the refusals. GL runs on whatever EGL offers
// (llvmpipe here): small images and photon counts, bounds from the standard errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "gpu/gpu_test.h"
#include "translucent/material/checker.h"
#include "translucent/material/gradient.h"
#include "translucent/material/layers.h"
#include "translucent/material/medium_desc.h"
#include "translucent/material/veins.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/gpu/mesh_gpu.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/scene/scene.h"
#include "image_zmap.h"
#include "mesh_test_scenes.h"
#include "scattering_orders_checks.h"

namespace translucent::reference {
namespace {

using gpu::testing::GpuTest;

using test_support::orthographic;
using test_support::threeCubes;

Light directional(glm::dvec3 toLight, double irradiance, Rgb color = {1.0, 1.0, 1.0}) {
  return Light{DirectionalLight{glm::normalize(toLight), irradiance}, color};
}

void useGpu(MeshPathTracer& t, const geometry::TriangleMesh& mesh) {
  t.setWalker(makeGpuMeshWalker(gpu::testing::context(), mesh));
}

const geometry::TriangleMesh& bunny() { return test_support::unitBunny(); }

using test_support::bonferroniZ;
using test_support::ZMap;
using test_support::zmap;
using test_support::meanAndError;

// The images of the GPU and CPU walks agree pixel by pixel: mean z² within 6 of its standard
// deviations sqrt(2/N) of 1, and no pixel beyond the Bonferroni-corrected 1% threshold. (With
// few photons per pixel z is not quite normal; pixels with few scores have heavier tails, which
// the corrected threshold at 1% leaves room for.)
void expectImagesAgree(const CameraImages& g, const CameraImages& c, int minPixels) {
  const std::pair<const char*, std::pair<const McImage*, const McImage*>> all[] = {
      {"exitance", {&g.exitance, &c.exitance}},
      {"radiance", {&g.radiance, &c.radiance}},
      {"cone radiance", {&g.cone_radiance, &c.cone_radiance}}};
  for (const auto& [name, images] : all) {
    const ZMap m = zmap(*images.first, *images.second);
    EXPECT_GT(m.n, minPixels) << name;
    EXPECT_NEAR(m.meanZ2, 1.0, 6.0 * std::sqrt(2.0 / std::max(m.n, 1)))
        << name << ": mean z² over " << m.n << " pixel values";
    EXPECT_LT(m.maxAbs, bonferroniZ(m.n, 0.01)) << name << ": largest |z| over " << m.n;
  }
}

// Within 4 combined standard errors, plus 1e-6 relative: the GPU's entry cosines are float, so
// its Fresnel weights are the CPU's to ~1e-7 (which shows when every photon enters alike and
// the standard error is 0).
void expectFluxAgree(const TransportStats& g, const TransportStats& c) {
  for (size_t ch = 0; ch < g.photons.size(); ++ch)
    for (const auto& [name, a, b] :
         {std::tuple{"entered", &g.entered[ch], &c.entered[ch]},
          std::tuple{"exited", &g.exited[ch], &c.exited[ch]},
          std::tuple{"escaped", &g.escaped[ch], &c.escaped[ch]}}) {
      const Estimate p = a->estimate(g.photons[ch]), q = b->estimate(c.photons[ch]);
      EXPECT_NEAR(p.value, q.value, 4.0 * std::hypot(p.std_error, q.std_error) + 1e-6 * std::abs(q.value))
          << name << " " << ch;
    }
}

class MeshGpu : public GpuTest {};

TEST_F(MeshGpu, CubeUnderABeamEntersTheAnalyticFlux) {
  // A beam of radius 0.8 along -z onto the top face of the cube [-1, 1]³: every photon enters
  // at normal incidence with weight 1 - F(1), F(1) = ((η - 1)/(η + 1))² (from float cosines on
  // the GPU: to ~1e-7); without absorption every entered photon leaves (entered = escaped).
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  const Light beam{BeamLight{{0.1, -0.1, 5.0}, {0.0, 0.0, -1.0}, 0.8, 2.0}, {1.0, 1.0, 1.0}};
  MeshPathTracer t(cube, ScalarMedium{0.0, 3.0, 0.4, 1.5}, {beam},
                   orthographic({0.0, 0.0, 4.0}, 2.4, 8), 5.0, {3, 1});
  useGpu(t, cube);
  EXPECT_EQ(t.device().rfind("gpu (", 0), 0u) << t.device();
  const TransportStats st = t.addPass(32 * kBlockPhotons);
  const uint64_t n = st.photons[0];
  const double f0 = (0.5 / 2.5) * (0.5 / 2.5);
  EXPECT_NEAR(st.entered[0].estimate(n).value, 2.0 * (1.0 - f0), 2e-6);
  EXPECT_NEAR(st.escaped[0].estimate(n).value, st.entered[0].estimate(n).value, 1e-12);
  EXPECT_NEAR(st.exited[0].estimate(n).value, st.entered[0].estimate(n).value, 1e-12);
  EXPECT_FALSE(st.partial);
}

TEST_F(MeshGpu, ThreeMatchedCubesInARowExitAndReenterAsTheChordsSay) {
  // Three unit cubes along z, 0.5 apart, η = 1 (no Fresnel), pure absorber σa: a pencil beam
  // along -z crosses them all, leaving each: a photon's exits sum to w (T + T² + T³), T = e^{-σa}
  // on average, and it escapes with w T³. Three exits per photon also overflow the walker's first
  // exit buffer (2 per photon): the batch is traced again into a larger one.
  const geometry::TriangleMesh row = threeCubes();
  const double sa = 0.4, T = std::exp(-sa);
  const Light beam{BeamLight{{0.05, 0.1, 5.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
  MeshPathTracer t(row, ScalarMedium{sa, 0.0, 0.0, 1.0}, {beam},
                   orthographic({3.0, 0.0, 0.0}, 5.0, 8), 5.0, {4, 1});
  useGpu(t, row);
  const TransportStats st = t.addPass(64 * kBlockPhotons);
  const uint64_t n = st.photons[0];
  EXPECT_NEAR(st.entered[0].estimate(n).value, 1.0, 1e-12);
  const Estimate exited = st.exited[0].estimate(n), escaped = st.escaped[0].estimate(n);
  EXPECT_NEAR(exited.value, T + T * T + T * T * T, 4.0 * exited.std_error);
  EXPECT_NEAR(escaped.value, T * T * T, 4.0 * escaped.std_error);
  EXPECT_LT(exited.std_error, 0.01);  // the test has power
}

TEST_F(MeshGpu, ExitsThroughThreeCubesAreScoredInTheirOwnScatteringOrders) {
  // The order of each exit comes back from the GPU with its rank (mesh_walk.comp): the checks of
  // the CPU test (scattering_orders_checks.h), on the GPU walk.
  const geometry::TriangleMesh row = threeCubes();
  MeshPathTracer t = test_support::threeCubesTracer({6, 1});
  useGpu(t, row);
  test_support::expectThreeCubesOrders(t, 64 * kBlockPhotons);
}

TEST_F(MeshGpu, ThreeMismatchedCubesMatchTheCpuTracerThroughEveryReentry) {
  // The row of three cubes with η = 1.5 and a pencil beam along the axis: every crossing is at
  // normal incidence, so photons bounce between the faces and between the cubes (internal
  // reflections, exits, re-entries and reflections off the outside, each with F(1) = 0.04),
  // and the flux sums of the two walks must agree (no scattering: a 1D problem with exact
  // Fresnel decisions all along).
  const geometry::TriangleMesh row = threeCubes();
  const Light beam{BeamLight{{0.05, 0.1, 5.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
  const ScalarMedium m{0.1, 0.0, 0.0, 1.5};
  const Camera cam = orthographic({3.0, 0.0, 0.0}, 5.0, 8);
  MeshPathTracer gpu(row, m, {beam}, cam, 5.0, {11, 1}), cpu(row, m, {beam}, cam, 5.0, {12, 2});
  useGpu(gpu, row);
  gpu.addPass(128 * kBlockPhotons);
  cpu.addPass(128 * kBlockPhotons);
  expectFluxAgree(gpu.stats(), cpu.stats());
  const Estimate e = gpu.stats().exited[0].estimate(gpu.stats().photons[0]);
  EXPECT_LT(e.std_error, 0.003 * e.value);  // the test has power
}

TEST_F(MeshGpu, CubeImagesMatchTheCpuTracerPixelByPixel) {
  // RGB medium with anisotropy, two directional lights of different colours (the light choice
  // by flux per channel), oblique orthographic view with a wide cone.
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  Medium medium;
  medium.sigma_a = {0.3, 0.1, 0.03};
  medium.sigma_s = {4.0, 6.0, 8.0};
  medium.g = 0.8;  // strongly forward: a wrong g changes σs' = (1 - g) σs by tens of percent
  medium.eta = 1.4;
  const std::vector<Light> lights = {directional({0.3, 1.0, 0.5}, 1.0, {1.0, 0.8, 0.6}),
                                     directional({-1.0, 0.2, 0.4}, 0.4, {0.5, 0.7, 1.0})};
  const Camera cam = orthographic({2.0, 1.5, 3.0}, 4.0, 12);
  MeshPathTracer gpu(cube, medium, lights, cam, 30.0, {5, 1}), cpu(cube, medium, lights, cam, 30.0, {6, 2});
  useGpu(gpu, cube);
  gpu.addPass(96 * kBlockPhotons);
  cpu.addPass(96 * kBlockPhotons);
  expectImagesAgree(gpu.images(), cpu.images(), 200);
  expectFluxAgree(gpu.stats(), cpu.stats());
  EXPECT_NEAR(double(gpu.stats().scattering_events) / double(cpu.stats().scattering_events), 1.0, 0.01);
}

TEST_F(MeshGpu, BunnyImagesMatchTheCpuTracerPixelByPixel) {
  // The bunny (non-convex: light leaving the ears and paws re-enters the body) under a point
  // light and a directional one, a pinhole camera: the images and the flux statistics of the
  // two walks agree; both see re-entries (exited > escaped).
  Medium medium;  // Marble's scattering at 2 mm per unit (~10 mean free paths across), g = 0.6
  medium.scale = 2.0;
  medium.sigma_a = {0.05, 0.02, 0.01};
  medium.g = 0.6;
  const std::vector<Light> lights = {
      Light{PointLight{{1.5, 2.0, 2.5}, 6.0}, {1.0, 1.0, 1.0}},
      directional({-0.5, 0.3, 1.0}, 0.5, {0.8, 0.9, 1.0})};
  Camera cam;
  cam.position = {0.3, 0.4, 3.2};
  cam.fov = 40.0;
  cam.width = cam.height = 20;  // the bunny covers about a third of the frame
  MeshPathTracer gpu(bunny(), medium, lights, cam, 30.0, {7, 1}),
      cpu(bunny(), medium, lights, cam, 30.0, {8, 2});
  useGpu(gpu, bunny());
  gpu.addPass(64 * kBlockPhotons);
  cpu.addPass(64 * kBlockPhotons);
  expectImagesAgree(gpu.images(), cpu.images(), 250);
  expectFluxAgree(gpu.stats(), cpu.stats());
  for (size_t c = 0; c < 3; ++c) {
    const TransportStats& s = gpu.stats();
    EXPECT_GT(s.exited[c].estimate(s.photons[c]).value, s.escaped[c].estimate(s.photons[c]).value * 1.001)
        << "no re-entry seen in channel " << c;
  }
}

// TracerOptions::after_specular_only (the camera method's complement): only the light that meets
// the boundary again (internally reflected, or out through an ear and into the head) before it
// first scatters is scored. The bunny at η = 1.3 (Marble at 5 mm per unit: the ears are a few
// mean free paths thick) under a sun and a point light, the images and the exited flux of the GPU
// walk against the CPU's; the part is a few per cent of the whole (a third pass without the
// option, on the CPU).
TEST_F(MeshGpu, OnlyLightMetByTheBoundaryBeforeItScattersMatchesTheCpu) {
  Medium medium;
  medium.scale = 5.0;
  medium.eta = 1.3;
  const std::vector<Light> lights = {
      Light{PointLight{{0.9, 1.1, 0.8}, 2.0}, {1.0, 1.0, 1.0}},
      directional({-0.5, 0.3, 1.0}, 0.5, {0.8, 0.9, 1.0})};
  Camera cam;
  cam.position = {0.3, 0.4, 3.2};
  cam.fov = 40.0;
  cam.width = cam.height = 20;
  TracerOptions o{9, 1};
  o.after_specular_only = true;
  MeshPathTracer gpu(bunny(), medium, lights, cam, 30.0, o);
  o.seed = 10;
  o.threads = 2;
  MeshPathTracer cpu(bunny(), medium, lights, cam, 30.0, o);
  useGpu(gpu, bunny());
  gpu.addPass(512 * kBlockPhotons);
  cpu.addPass(512 * kBlockPhotons);
  // (Few of these photons leave towards the camera within the cone: 40-odd pixel values.)
  expectImagesAgree(gpu.images(), cpu.images(), 25);
  expectFluxAgree(gpu.stats(), cpu.stats());
  o.after_specular_only = false;
  MeshPathTracer all(bunny(), medium, lights, cam, 30.0, o);
  all.addPass(16 * kBlockPhotons);
  for (size_t c = 0; c < 3; ++c) {
    const Estimate part = gpu.stats().exited[c].estimate(gpu.stats().photons[c]);
    const Estimate whole = all.stats().exited[c].estimate(all.stats().photons[c]);
    EXPECT_GT(part.value, 0.005 * whole.value) << "channel " << c;
    EXPECT_LT(part.value, 0.3 * whole.value) << "channel " << c;
  }
}

TEST_F(MeshGpu, SameSeedSameImagesWhateverThePassSplit) {
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  const std::vector<Light> lights = {directional({0.2, 1.0, 0.3}, 1.0)};
  const Camera cam = orthographic({1.0, 2.0, 3.0}, 4.0, 8);
  Medium medium;
  medium.scale = 2.0;
  MeshPathTracer one(cube, medium, lights, cam, 5.0, {9, 1}), split(cube, medium, lights, cam, 5.0, {9, 1}),
      other(cube, medium, lights, cam, 5.0, {10, 1});
  for (MeshPathTracer* t : {&one, &split, &other}) useGpu(*t, cube);
  one.addPass(6 * kBlockPhotons);
  split.addPass(2 * kBlockPhotons);
  split.addBlocks(2, 4);
  other.addPass(6 * kBlockPhotons);
  bool differs = false;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(one.images().exitance.pixel(x, y, c).value, split.images().exitance.pixel(x, y, c).value);
        ASSERT_EQ(one.images().exitance.pixel(x, y, c).std_error,
                  split.images().exitance.pixel(x, y, c).std_error);
        differs |= other.images().exitance.pixel(x, y, c).value != one.images().exitance.pixel(x, y, c).value;
      }
  EXPECT_TRUE(differs);
}

// A small sky: 8 x 4 texels of different radiance per channel (brighter towards +y, bluer
// towards the horizon, so that the per-channel samplers differ) with a "sun" texel 40 times as
// bright (most of the flux from one direction: a wrong direction shows in the images).
std::shared_ptr<lights::EnvironmentMap> smallSky() {
  auto map = std::make_shared<lights::EnvironmentMap>();
  map->width = 8;
  map->height = 4;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const float up = 1.0f - 0.25f * static_cast<float>(y), side = 0.5f + 0.06f * static_cast<float>(x);
      const float sun = x == 5 && y == 1 ? 40.0f : 1.0f;
      map->rgb.insert(map->rgb.end(), {2.0f * up * side * sun, 1.5f * up * sun,
                                       (0.5f + 0.5f * static_cast<float>(y)) * sun});
    }
  return map;
}

// The medium of the cube under environment lights: a different absorption per channel.
Medium environmentCubeMedium() {
  Medium m;
  m.sigma_a = {0.2, 0.1, 0.05};
  m.sigma_s = {3.0, 4.0, 5.0};
  m.g = 0.3;
  m.eta = 1.3;
  return m;
}

TEST_F(MeshGpu, EnvironmentLightMatchesTheCpuTracerPixelByPixel) {
  // The cube under the small sky (rotated 30°) and a weak directional light: the directions
  // come from the map's sampler on the CPU, the rest of the emission and the walk on the GPU;
  // images and fluxes agree with the CPU tracer's.
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  const Medium medium = environmentCubeMedium();
  const std::vector<Light> lights = {Light{EnvironmentLight::make(smallSky(), 30.0, 1.0), {1.0, 1.0, 1.0}},
                                     directional({0.3, 1.0, 0.2}, 0.3)};
  const Camera cam = orthographic({2.0, 1.0, 3.0}, 4.0, 12);
  MeshPathTracer gpu(cube, medium, lights, cam, 30.0, {13, 1}), cpu(cube, medium, lights, cam, 30.0, {14, 2});
  useGpu(gpu, cube);
  gpu.addPass(96 * kBlockPhotons);
  cpu.addPass(96 * kBlockPhotons);
  expectImagesAgree(gpu.images(), cpu.images(), 200);
  expectFluxAgree(gpu.stats(), cpu.stats());
}

TEST_F(MeshGpu, TwoEnvironmentLightsAndADirectionalOneMatchTheCpuTracer) {
  // The light of each photon is chosen in the shader; an environment photon's direction on the
  // CPU, which makes the same choice from the same word (mesh_gpu.cpp: environmentDirections): a
  // direction from the wrong map would show here, the two skies being far apart (one rotated and
  // tinted, at a different intensity).
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  const Medium medium = environmentCubeMedium();
  const std::vector<Light> lights = {Light{EnvironmentLight::make(smallSky(), 0.0, 1.0), {1.0, 1.0, 1.0}},
                                     directional({0.3, 1.0, 0.2}, 0.3),
                                     Light{EnvironmentLight::make(smallSky(), 120.0, 2.5), {0.2, 0.6, 1.0}}};
  const Camera cam = orthographic({2.0, 1.0, 3.0}, 4.0, 12);
  MeshPathTracer gpu(cube, medium, lights, cam, 30.0, {15, 1}), cpu(cube, medium, lights, cam, 30.0, {16, 2});
  useGpu(gpu, cube);
  EXPECT_EQ(gpu.device().rfind("gpu (", 0), 0u);
  gpu.addPass(96 * kBlockPhotons);
  cpu.addPass(96 * kBlockPhotons);
  expectImagesAgree(gpu.images(), cpu.images(), 200);
  expectFluxAgree(gpu.stats(), cpu.stats());
}

}  // namespace
}  // namespace translucent::reference

namespace translucent::reference {
namespace {

// ---- Heterogeneous media ----------------------------------------------------------------------

material::Material volumeMaterial(std::shared_ptr<const material::VolumeField> field, double eta,
                                  double coefficientScale) {
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium.eta = eta;
  m.medium.scale = coefficientScale;
  m.volume = std::move(field);
  return m;
}

// Two media far apart in σt, albedo and g (a field evaluated in the wrong place, a wrong local
// albedo or g shows), as the fields' descriptions take them.
std::vector<material::MediumDesc> twoMedia() {
  return {material::mediumDesc({0.3, 0.1, 0.05}, {2.0, 3.0, 4.0}, 0.2),
          material::mediumDesc({0.02, 0.03, 0.4}, {9.0, 6.0, 2.5}, 0.75)};
}

// The GPU walk of a heterogeneous body against the CPU's, pixel by pixel and in flux, with no
// majorant violation on either. The scattering counts (what a wrong local σs/σt, g or field
// position changes most) are compared over `passes` independent passes each: their means within
// 5 combined standard errors (Student's t with 2 (passes − 1) degrees of freedom, 14 at 8
// passes: 5 is beyond its 0.02% tail).
void expectHeteroAgree(const geometry::TriangleMesh& mesh, const material::Material& m,
                       const std::vector<Light>& lights, const Camera& cam, uint64_t blocks,
                       int minPixels, int passes = 8) {
  MeshPathTracer gpu(mesh, m, lights, cam, 30.0, {21, 1}), cpu(mesh, m, lights, cam, 30.0, {22, 2});
  EXPECT_EQ(meshGpuRefusal(gpu), "");
  useGpu(gpu, mesh);
  std::vector<double> g, c;
  for (int p = 0; p < passes; ++p) {
    const uint64_t g0 = gpu.stats().scattering_events, c0 = cpu.stats().scattering_events;
    gpu.addPass(blocks / static_cast<uint64_t>(passes) * kBlockPhotons);
    cpu.addPass(blocks / static_cast<uint64_t>(passes) * kBlockPhotons);
    g.push_back(static_cast<double>(gpu.stats().scattering_events - g0));
    c.push_back(static_cast<double>(cpu.stats().scattering_events - c0));
  }
  expectImagesAgree(gpu.images(), cpu.images(), minPixels);
  expectFluxAgree(gpu.stats(), cpu.stats());
  const auto [gm, ge] = meanAndError(g);
  const auto [cm, ce] = meanAndError(c);
  EXPECT_NEAR(gm, cm, 5.0 * std::hypot(ge, ce)) << "scatterings per pass: GPU " << gm << " ± " << ge
                                                << ", CPU " << cm << " ± " << ce;
  EXPECT_LT(std::hypot(ge, ce), 0.02 * cm);  // the comparison has power
  EXPECT_EQ(gpu.majorantViolations(), 0u);
  EXPECT_EQ(cpu.majorantViolations(), 0u);
}

TEST_F(MeshGpu, CheckerCubeMatchesTheCpuTracerPixelByPixel) {
  // A 3D checker of unequal cells, the material frame rotated, moved and scaled (q = s Rᵀ (x − t))
  // and coefficients per 2 scene units: the frame, the units and the cell parity all count.
  material::CheckerDesc d;
  d.cell = {0.7, 0.5, 0.9};
  d.media = twoMedia();
  material::Material m = volumeMaterial(std::make_shared<material::CheckerField>(d), 1.4, 0.5);
  const double a = 0.5;
  m.frame.rotation = glm::dmat3(std::cos(a), 0.0, -std::sin(a), 0.0, 1.0, 0.0, std::sin(a), 0.0, std::cos(a));
  m.frame.translate = {0.1, -0.2, 0.15};
  m.frame.scale = 1.6;
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  expectHeteroAgree(cube, m,
                    {directional({0.3, 1.0, 0.5}, 1.0, {1.0, 0.8, 0.6}),
                     directional({-1.0, 0.2, 0.4}, 0.4, {0.5, 0.7, 1.0})},
                    orthographic({2.0, 1.5, 3.0}, 4.0, 12), 64, 200);
}

TEST_F(MeshGpu, PlaneLayersAndGradientCubesMatchTheCpuTracer) {
  // Three layers below a tilted plane (the top one thin and dense, the last semi-infinite), and
  // a gradient along a diagonal: a wrong depth, layer or blend shows in the images.
  material::LayersDesc l;
  l.from = material::LayersDesc::From::Plane;
  l.normal = glm::normalize(glm::dvec3(0.2, 1.0, 0.1));
  l.offset = 0.8;
  const auto media = twoMedia();
  l.layers = {{media[1], 0.3}, {media[0], 0.6}, {material::mediumDesc({0.1, 0.2, 0.1}, {1.0, 1.5, 2.0}, 0.0), std::nullopt}};
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  const std::vector<Light> lights = {directional({0.2, 1.0, 0.3}, 1.0)};
  const Camera cam = orthographic({1.5, 2.0, 2.5}, 4.0, 12);
  expectHeteroAgree(cube, volumeMaterial(std::make_shared<material::LayersField>(l, nullptr), 1.3, 0.5),
                    lights, cam, 48, 200);
  material::GradientDesc g;
  g.from = {-0.8, -0.6, -0.9};
  g.to = {0.9, 0.7, 0.5};
  g.media = media;
  expectHeteroAgree(cube, volumeMaterial(std::make_shared<material::GradientField>(g), 1.3, 0.5),
                    lights, cam, 48, 200);
}

TEST_F(MeshGpu, VeinedBunnyMatchesTheCpuTracerPixelByPixel) {
  // Marble veins (turbulent Perlin noise, 4 octaves) in the non-convex bunny under a point light:
  // the noise, exits, re-entries and the tracking restarted after each.
  material::VeinsDesc v;
  v.media = twoMedia();
  v.period = 0.6;
  v.direction = glm::normalize(glm::dvec3(1.0, 0.3, 0.2));
  v.noise_size = 0.5;
  v.octaves = 4;
  v.turbulence = 1.5;
  v.sharpness = 4.0;
  Camera cam;
  cam.position = {0.3, 0.4, 3.2};
  cam.fov = 40.0;
  cam.width = cam.height = 20;
  expectHeteroAgree(bunny(), volumeMaterial(std::make_shared<material::VeinsField>(v), 1.3, 2.0),
                    {Light{PointLight{{1.5, 2.0, 2.5}, 6.0}, {1.0, 1.0, 1.0}},
                     directional({-0.5, 0.3, 1.0}, 0.5, {0.8, 0.9, 1.0})},
                    cam, 48, 250);
}

TEST_F(MeshGpu, HeadWithLayersBelowItsSurfaceMatchesTheCpuTracer) {
  // data/scenes/head-layered-skin.json (epidermis 0.3 mm over Skin1 over fat, a 220 mm head):
  // each tentative collision finds its layer by the distance to the surface, a tree traversal of
  // hundreds of loop iterations, so walks there used to meet llvmpipe's loop limit and stop
  // half-way (8% fewer scatterings than the CPU's); suspended and resumed (mesh_walk.comp) they
  // are the CPU's walks.
  const scene::Scene s =
      scene::loadScene(std::string(TRANSLUCENT_DATA_DIR) + "/scenes/head-layered-skin.json");
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  Camera cam = s.camera;
  cam.width = 20;
  cam.height = 15;
  expectHeteroAgree(mesh, scene::sceneMaterial(s, mesh), scene::referenceLights(s), cam, 96, 120);
}

TEST_F(MeshGpu, LongWalksAreSuspendedAndResumedNotCutShort) {
  // A cube 600 mean free paths across without absorption: every photon that enters leaves,
  // after up to ~10⁵ scatterings (the long-path roulette at its default 10⁶ events, unbiased,
  // rarely acts). Cut at llvmpipe's 65535 loop iterations (about 13000 events of this walk per
  // SIMD group), 2.7% of the light was lost; resumed, the escaping flux is the entering one
  // within its standard error. The scattering counts agree with the CPU's (heavy-tailed:
  // compared over 8 passes).
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const ScalarMedium m{0.0, 600.0, 0.0, 1.0};  // index-matched: every photon enters with the same weight
  TracerOptions o{31, 1};
  MeshPathTracer gpu(cube, m, {directional({-0.4, 1.0, 0.6}, 1.0)}, orthographic({1.0, 1.5, 2.0}, 2.0, 16),
                     20.0, o);
  useGpu(gpu, cube);
  o.seed = 32;
  o.threads = 2;
  MeshPathTracer cpu(cube, m, {directional({-0.4, 1.0, 0.6}, 1.0)}, orthographic({1.0, 1.5, 2.0}, 2.0, 16),
                     20.0, o);
  std::vector<double> g, c;
  for (int p = 0; p < 8; ++p) {
    const uint64_t g0 = gpu.stats().scattering_events, c0 = cpu.stats().scattering_events;
    gpu.addPass(kBlockPhotons);
    cpu.addPass(kBlockPhotons);
    g.push_back(static_cast<double>(gpu.stats().scattering_events - g0));
    c.push_back(static_cast<double>(cpu.stats().scattering_events - c0));
  }
  const TransportStats& st = gpu.stats();
  const Estimate entered = st.entered[0].estimate(st.photons[0]);
  const Estimate escaped = st.escaped[0].estimate(st.photons[0]);
  // The same photons: equal to rounding unless the roulette acted on one (a walk of 10⁶ events,
  // rare here), far from a 2.7% loss.
  EXPECT_NEAR(escaped.value, entered.value, 0.002 * entered.value);
  const auto [gm, ge] = meanAndError(g);
  const auto [cm, ce] = meanAndError(c);
  EXPECT_GT(cm, 100.0 * kBlockPhotons);  // long walks: the limit would have been met
  EXPECT_NEAR(gm, cm, 5.0 * std::hypot(ge, ce)) << "scatterings per pass: GPU " << gm << " ± " << ge
                                                << ", CPU " << cm << " ± " << ce;
  expectImagesAgree(gpu.images(), cpu.images(), 20);
}

// A field that fields.glsl does not know.
struct OpaqueField final : material::VolumeField {
  material::LocalMedium at(const glm::dvec3&) const override { return {{0.1, 0.1, 0.1}, {1.0, 1.0, 1.0}, 0.0}; }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override { return {1.1, 1.1, 1.1}; }
};

TEST_F(MeshGpu, HeterogeneousRefusals) {
  // A field without a GLSL twin: useDevice refuses it with "gpu" and keeps the CPU with "auto".
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  const Camera cam = orthographic({0.0, 0.0, 4.0}, 3.0, 8);
  const TraceDevice dev{Device::Gpu, nullptr};
  MeshPathTracer opaque(cube, volumeMaterial(std::make_shared<OpaqueField>(), 1.3, 1.0),
                        {directional({0.0, 1.0, 0.0}, 1.0)}, cam, 5.0, {1, 1});
  EXPECT_NE(meshGpuRefusal(opaque), "");
  EXPECT_THROW(useDevice(dev, "gpu", opaque, cube, "cube"), ParameterError);
  useDevice(dev, "auto", opaque, cube, "cube");
  EXPECT_EQ(opaque.device(), "cpu");
}

TEST_F(MeshGpu, DeformedCheckerMatchesTheCpuTracer) {
  // A 3D checker read through a bend and a twist of the material frame (MaterialFrame::
  // toMaterial undoes them: exactly for the twist, by Newton's method for the bend; on the GPU
  // in float, common/deform.glsl): a wrong inverse puts cells in the wrong place, which the
  // images and the scattering counts show.
  material::CheckerDesc d;
  d.cell = glm::dvec3(0.45);
  d.media = twoMedia();
  material::Material m = volumeMaterial(std::make_shared<material::CheckerField>(d), 1.3, 0.5);
  geometry::Deformation bend;
  bend.type = geometry::Deformation::Type::Bend;
  bend.amount = 40.0;  // degrees per unit length
  bend.axis = {0.0, 1.0, 0.0};
  bend.direction = {1.0, 0.0, 0.0};
  geometry::Deformation twist;
  twist.type = geometry::Deformation::Type::Twist;
  twist.amount = 60.0;
  twist.period = 4.0;
  twist.axis = glm::normalize(glm::dvec3(0.2, 1.0, 0.1));
  m.frame.deform = {bend, twist};
  m.frame.time = 0.7;
  const geometry::TriangleMesh cube = geometry::makeBox(glm::dvec3(-1.0), glm::dvec3(1.0));
  MeshPathTracer probe(cube, m, {directional({0.0, 1.0, 0.0}, 1.0)}, orthographic({0.0, 0.0, 4.0}, 3.0, 8),
                       5.0, {1, 1});
  EXPECT_EQ(meshGpuRefusal(probe), "");
  expectHeteroAgree(cube, m,
                    {directional({0.3, 1.0, 0.5}, 1.0, {1.0, 0.8, 0.6}),
                     directional({-1.0, 0.2, 0.4}, 0.4, {0.5, 0.7, 1.0})},
                    orthographic({2.0, 1.5, 3.0}, 4.0, 12), 64, 200);
}

}  // namespace
}  // namespace translucent::reference
