// SPDX-License-Identifier: GPL-3.0-or-later
// Single scattering S⁽¹⁾ per pixel (techniques/common/single_scattering.h, through the transfer
// technique's `scattering single`) against the path tracers' single-scattering split
// (ScatteringOrder::Single): the camera method's true radiance at η = 1 (where the per-pixel
// integrand is exact) on a lit sphere and on the bunny, and the light method's at η = 1.3 (where
// the light's refraction uses Jensen et al. 2001's approximation).
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/techniques/registry.h"
#include "translucent/techniques/transfer/transfer_technique.h"
#include "render_helpers.h"

namespace translucent::transfer {
namespace {

using pointcloud::testing::TempDir;
using pointcloud::testing::writeObj;

// An optically thin-ish body (σt = 4.5 to 6 per unit: a unit sphere is 9 to 12 mean free paths
// across, so single scattering sees the whole geometry) with a forward-scattering phase function.
Medium thinMedium(double eta) { return {{0.5, 1.0, 2.0}, {4.0, 4.0, 4.0}, 0.3, eta, 1.0}; }

geometry::TriangleMesh unitSphere() {
  geometry::TriangleMesh m = geometry::makeIcosphere(4, 1.0);
  m.orientOutwards();
  return m;
}

class SingleScatteringGpu : public gpu::testing::GpuTest {};

struct Rendered {
  techniques::Frame frame;
  geometry::TriangleMesh mesh;
};

// The technique's image at `factor` times the camera's resolution, averaged over factor²
// sub-pixels: the box filter of the path tracers' pixels (camera.h), which a pixel-centre sample
// misses where a pixel straddles an edge between parts of the mesh.
Rendered renderSingle(const scene::Scene& s, int directions = 8, int factor = 2) {
  auto t = techniques::make("transfer");
  t->setParameter("scattering", std::string("single"));
  t->setParameter("single_directions", directions);
  // 16 strata per channel: the quadrature's own error well below the tolerances (4 strata are
  // 0.3-2.3% low on these scenes; the default, 2, trades more of it for speed: on the compare
  // suite the total error against the path tracer does not change).
  t->setParameter("single_samples", 16);
  t->prepare(s, gpu::testing::context());
  techniques::FrameRequest request;
  request.width = factor * s.camera.width;
  request.height = factor * s.camera.height;
  const techniques::Frame fine = t->render(request);
  Rendered r;
  r.mesh = dynamic_cast<TransferTechnique&>(*t).mesh();
  const auto downsample = [&](const std::vector<float>& in) {
    std::vector<float> out(size_t(s.camera.width) * size_t(s.camera.height) * 3, 0.0f);
    for (int y = 0; y < fine.height; ++y)
      for (int x = 0; x < fine.width; ++x)
        for (int c = 0; c < 3; ++c)
          out[(size_t(y / factor) * size_t(s.camera.width) + size_t(x / factor)) * 3 + size_t(c)] +=
              in[(size_t(y) * size_t(fine.width) + size_t(x)) * 3 + size_t(c)] / float(factor * factor);
    return out;
  };
  r.frame.width = s.camera.width;
  r.frame.height = s.camera.height;
  r.frame.rgb = downsample(fine.rgb);
  if (auto it = fine.layers.find("exitance"); it != fine.layers.end())
    r.frame.layers["exitance"] = downsample(it->second);
  return r;
}

// Pixels of an image split into square blocks of `block` pixels; a block counts where it and the
// pixels around it are covered in both images (no partly covered silhouette pixels).
std::vector<std::vector<uint32_t>> coveredBlocks(const techniques::Frame& f, const reference::McImage& ref,
                                                 int block) {
  const auto covered = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= f.width || y >= f.height) return false;
    const uint32_t i = uint32_t(y * f.width + x);
    return f.rgb[3 * i + 1] > 0.0f && ref.average(std::span(&i, 1), 1).value > 0.0;
  };
  std::vector<std::vector<uint32_t>> out;
  for (int by = 0; by + block <= f.height; by += block)
    for (int bx = 0; bx + block <= f.width; bx += block) {
      std::vector<uint32_t> px;
      bool full = true;
      for (int y = by - 1; y <= by + block; ++y)
        for (int x = bx - 1; x <= bx + block; ++x) full = full && covered(x, y);
      for (int y = by; y < by + block; ++y)
        for (int x = bx; x < bx + block; ++x) px.push_back(uint32_t(y * f.width + x));
      if (full) out.push_back(std::move(px));
    }
  return out;
}

// Block averages of the technique's image against the reference's: at least `fraction` of the
// blocks (every channel) within `rel` of the reference plus 4 of its standard errors, and the
// sum over all blocks within `rel` plus 4 standard errors. Returns the largest relative deviation.
double expectBlocksAgree(const techniques::Frame& f, const reference::McImage& ref, int block,
                         double rel, double fraction, const std::string& what) {
  const auto blocks = coveredBlocks(f, ref, block);
  EXPECT_GE(blocks.size(), 8u) << what;
  double worst = 0.0, worstSe = 0.0;
  int within = 0, tests = 0;
  std::vector<uint32_t> all;
  for (const auto& px : blocks) {
    all.insert(all.end(), px.begin(), px.end());
    for (int c = 0; c < 3; ++c) {
      const reference::Estimate e = ref.average(px, c);
      double mine = 0.0;
      for (uint32_t i : px) mine += double(f.rgb[3 * i + size_t(c)]);
      mine /= double(px.size());
      ++tests;
      if (std::abs(mine - e.value) <= rel * e.value + 4.0 * e.std_error) ++within;
      worst = std::max(worst, std::abs(mine - e.value) / e.value);
      worstSe = std::max(worstSe, e.std_error / e.value);
    }
  }
  EXPECT_GE(within, int(fraction * tests)) << what << ": " << within << " of " << tests << " blocks agree";
  for (int c = 0; c < 3; ++c) {
    const reference::Estimate e = ref.average(all, c);
    double mine = 0.0;
    for (uint32_t i : all) mine += double(f.rgb[3 * i + size_t(c)]);
    mine /= double(all.size());
    EXPECT_NEAR(mine, e.value, rel * e.value + 4.0 * e.std_error) << what << ": mean, channel " << c;
    std::printf("%s, channel %d: mean %.5g vs %.5g ± %.2g (%+.2f%%); %d of %d blocks agree\n",
                what.c_str(), c, mine, e.value, e.std_error, 100.0 * (mine / e.value - 1.0), within, tests);
  }
  // The test has power: the reference's errors per block are below the tolerance.
  EXPECT_LT(worstSe, rel) << what;
  return worst;
}

// The camera path tracer (η = 1) on the scene's mesh, medium, first (directional) light and
// camera, with the images split by scattering order: `samples` per pixel and channel.
std::unique_ptr<reference::CameraPathTracer> cameraMethod(const geometry::TriangleMesh& mesh,
                                                          const scene::Scene& s, uint64_t seed,
                                                          bool exitance, uint64_t samples) {
  reference::CameraPathOptions o;
  o.seed = seed;
  o.threads = 2;
  o.split_orders = true;
  o.exitance = exitance;
  const reference::Light sun{std::get<reference::DirectionalLight>(s.lights[0].emitter), Rgb{1, 1, 1}};
  auto cam = std::make_unique<reference::CameraPathTracer>(mesh, s.medium, std::vector{sun}, s.camera, o);
  cam->addPass(samples);
  return cam;
}

TEST_F(SingleScatteringGpu, MatchesTheCameraMethodOnASphereAtEtaOne) {
  // A sun from the side (45°) and the orthographic camera along +z: the phase function, the
  // light's path through the sphere to every point of the view ray and the view ray's own
  // extinction all vary across the disc. At η = 1 the estimator's integrand is exact; what is
  // left is the quadrature (16 strata per channel, midpoints) and float ray queries: 2%.
  TempDir dir;
  scene::Scene s = pointcloud::testing::testScene(writeObj(unitSphere(), dir.path() / "sphere.obj"), 24);
  s.medium = thinMedium(1.0);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(1.0, 0.0, 1.0)), 2.0};
  const Rendered r = renderSingle(s);

  const auto cam = cameraMethod(r.mesh, s, 3, true, 1024);
  const auto& single = cam->orderImages(reference::ScatteringOrder::Single);
  const double worst = expectBlocksAgree(r.frame, single.cone_radiance, 3, 0.02, 0.95, "sphere radiance");
  std::printf("sphere, eta 1: radiance blocks within %.2f%% of the camera method\n", 100.0 * worst);
  // The exitance over 8 cosine-weighted exit directions (a coarse quadrature of a smooth
  // integrand): 5%.
  techniques::Frame b = r.frame;
  b.rgb = r.frame.layers.at("exitance");
  const double worstB = expectBlocksAgree(b, single.exitance, 3, 0.05, 0.95, "sphere exitance");
  std::printf("sphere, eta 1: exitance blocks within %.2f%%\n", 100.0 * worstB);
}

TEST_F(SingleScatteringGpu, MatchesTheCameraMethodOnTheBunnyAtEtaOne) {
  // A real mesh: ears and paws shadow the body through the medium, view rays leave and re-enter
  // (the estimator follows them through air gaps, as the camera method's memoryless flights do).
  const std::filesystem::path bunny = "/usr/share/glmark2/models/bunny.obj";
  ASSERT_TRUE(std::filesystem::exists(bunny)) << "glmark2-data is a test dependency";
  scene::Scene s = pointcloud::testing::testScene(bunny, 32);
  s.mesh_normalize = true;
  // The normalised bunny fills about 0.8 of a 1-unit view.
  s.camera.view_height = 0.9;
  s.medium = thinMedium(1.0);
  s.medium.scale = 2.0;  // the normalised bunny is about 2 units tall
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(-0.4, 0.8, 0.5)), 2.0};
  Rendered r = renderSingle(s, 0);
  // Centre the camera on the bunny (its box's centre), then render again.
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : r.mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 mid = 0.5 * (lo + hi);
  s.camera.position = {mid.x, mid.y, 5.0};
  s.camera.look_at = {mid.x, mid.y, 0.0};
  r = renderSingle(s, 0);

  const auto cam = cameraMethod(r.mesh, s, 4, false, 2048);
  const double worst = expectBlocksAgree(
      r.frame, cam->orderImages(reference::ScatteringOrder::Single).cone_radiance, 2, 0.04, 0.9, "bunny radiance");
  std::printf("bunny, eta 1: radiance blocks within %.2f%% of the camera method\n", 100.0 * worst);
}

TEST_F(SingleScatteringGpu, MatchesTheLightMethodOnASphereAtEta13) {
  // η = 1.3: the light method's single-scattering exitance (photons from the sun; the camera
  // method cannot pass a refractive boundary towards a delta light). Rings of the image disc
  // within 8%: measured 2-7% low (Jensen et al. 2001's refracted-length approximation at the
  // light's entry, and single-scattered light that the exit reflects back inside, up to total
  // internal reflection, and that leaves elsewhere: the estimator leaves it out). The radiance
  // estimator is the same integral along one exit direction (checked exactly at η = 1 above);
  // the light method's cone radiance is too noisy here to test it at a few per cent.
  TempDir dir;
  scene::Scene s = pointcloud::testing::testScene(writeObj(unitSphere(), dir.path() / "sphere.obj"), 32);
  s.medium = thinMedium(1.3);
  s.lights[0].emitter = reference::DirectionalLight{{0.0, 0.0, 1.0}, 2.0};
  const Rendered r = renderSingle(s);

  reference::TracerOptions po;
  po.seed = 6;
  po.threads = 2;
  po.split_orders = true;
  const reference::Light sun{std::get<reference::DirectionalLight>(s.lights[0].emitter), Rgb{1, 1, 1}};
  reference::MeshPathTracer pt(r.mesh, s.medium, {sun}, s.camera, 5.0, po);
  pt.addPass(2'000'000);
  const auto& single = pt.orderImages(reference::ScatteringOrder::Single);
  const int n = 32;
  std::array<std::vector<uint32_t>, 4> rings;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double u = ((x + 0.5) / n - 0.5) * 2.2, v = ((y + 0.5) / n - 0.5) * 2.2;
      const double rr = std::sqrt(u * u + v * v);
      if (rr < 0.9) rings[size_t(rr / 0.9 * 4.0)].push_back(uint32_t(y * n + x));
    }
  const std::vector<float>& img = r.frame.layers.at("exitance");
  for (size_t k = 0; k < rings.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const reference::Estimate e = single.exitance.average(rings[k], c);
      double mine = 0.0;
      for (uint32_t i : rings[k]) mine += double(img[3 * i + size_t(c)]);
      mine /= double(rings[k].size());
      std::printf("eta 1.3, exitance, ring %zu, channel %d: %.5g vs %.5g ± %.2g (%+.2f%%)\n", k, c,
                  mine, e.value, e.std_error, 100.0 * (mine / e.value - 1.0));
      EXPECT_NEAR(mine, e.value, 0.08 * e.value + 4.0 * e.std_error) << "ring " << k << ", channel " << c;
      EXPECT_LT(e.std_error, 0.04 * e.value);  // the test has power
    }
}

TEST_F(SingleScatteringGpu, RefusesLightsItCannotTrace) {
  TempDir dir;
  scene::Scene s = pointcloud::testing::testScene(writeObj(unitSphere(), dir.path() / "sphere.obj"), 8);
  s.lights[0].emitter = reference::BeamLight{{0.0, 0.0, 5.0}, {0.0, 0.0, -1.0}, 0.0, 1.0};
  auto t = techniques::make("transfer");
  t->setParameter("scattering", std::string("single"));
  try {
    t->prepare(s, gpu::testing::context());
    FAIL() << "a pencil beam was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("lights[0]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace translucent::transfer
