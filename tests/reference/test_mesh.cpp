// SPDX-License-Identifier: GPL-3.0-or-later
// The triangle-mesh tracer (src/reference/mesh_tracer.h) against the slab walker (slab.h):
// a thin, wide box lit by a pencil beam must reproduce the slab's diffuse reflectance, radial
// profile and transmittance; a box lit by a wide beam, seen by pinhole and orthographic cameras,
// must show the slab's plane-wave exitance and its angular radiance in every pixel. Plus
// determinism, mesh loading and scene files, image files, and clear errors for bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "radial_tally.h"
#include "translucent/io/image_io.h"
#include "translucent/geometry/mesh.h"
#include "translucent/optics/fresnel.h"
#include "translucent/scene/mesh_scene.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/slab.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;
namespace fs = std::filesystem;

using test_support::RadialTally;

// |a - b| < k sqrt(σa² + σb²)
void expectAgree(const Estimate& a, const Estimate& b, double k, const std::string& what) {
  EXPECT_NEAR(a.value, b.value, k * std::hypot(a.std_error, b.std_error))
      << what << ": mesh " << a.value << " ± " << a.std_error << ", slab " << b.value << " ± "
      << b.std_error;
}

TEST(MeshTracer, ThinWideBoxUnderAPencilBeamReproducesTheSlab) {
  // A 200 x 200 x 4 mean-free-path box, η = 1.4, g = 0.7, α = 0.95: the side walls are 100 mfp
  // (more than 20 diffusion lengths) from the beam, so the box is the slab for every tally.
  // Per-annulus z-scores are tested at a Bonferroni-corrected 1% level (10 annuli + 2 totals:
  // |z| < 3.2).
  const double T = 4.0, half = 100.0;
  const ScalarMedium m{0.05, 0.95, 0.7, 1.4};
  const MeshBody box(geometry::makeBox({-half, -half, -T}, {half, half, 0.0}));
  const Light beam{BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
  RadialTally tally(10, 0.4);
  TransportOptions o;
  o.photons = 250'000;
  o.seed = 21;
  o.threads = 2;
  const TransportStats s = tracePhotons(box, std::span<const ScalarMedium>(&m, 1),
                                        std::span<const Light>(&beam, 1), o, tally);
  const uint64_t n = s.photons[0];

  SlabSetup slab;
  slab.sigma_a = m.sigma_a;
  slab.sigma_s = m.sigma_s;
  slab.g = m.g;
  slab.n_inside = m.eta;
  slab.thickness = T;
  TraceOptions so;
  so.photons = 1'000'000;
  so.seed = 4;
  so.threads = 2;
  so.radial_bins = 10;
  so.radial_max = 4.0;
  const SlabResult r = traceSlab(slab, so);

  constexpr double kZ = 3.2;
  expectAgree(tally.top.estimate(n), r.diffuse_reflectance, kZ, "diffuse reflectance");
  expectAgree(tally.elsewhere.estimate(n), r.transmittance, kZ, "transmittance");
  for (int k = 0; k < 10; ++k) {
    const double area = kPi * 0.16 * ((k + 1) * (k + 1) - k * k);  // exact annulus area
    // The slab divides by 2π r_c dr, the exact annulus area too.
    const Estimate mesh = tally.annuli[static_cast<size_t>(k)].estimate(n, area);
    expectAgree(mesh, {r.radial.rd[static_cast<size_t>(k)], r.radial.rd_stderr[static_cast<size_t>(k)]},
                kZ, "Rd(r) annulus " + std::to_string(k));
  }
  // Specular reflection is not traced by either: the entering flux is 1 - Rsp.
  EXPECT_NEAR(s.entered[0].estimate(n).value, 1.0 - r.specular_reflectance.value, 1e-12);
}

// A box lit over a wide disc: far from the disc's edge the exitance of the top face is the
// slab's plane-wave reflectance times the irradiance. The cameras below see the top face within
// 5 units of the centre, 9 units (5 diffusion lengths, 1/σtr = 1.8) inside the disc's edge.
struct WideBeamBox {
  static constexpr double kT = 2.0, kHalf = 60.0, kBeam = 14.0;
  ScalarMedium medium;
  geometry::TriangleMesh mesh = geometry::makeBox({-kHalf, -kHalf, -kT}, {kHalf, kHalf, 0.0});
  Light light{BeamLight{{0.0, 0.0, 5.0}, {0.0, 0.0, -1.0}, kBeam, 1.0}, {1.0, 1.0, 1.0}};
  double irradiance() const { return 1.0 / (kPi * kBeam * kBeam); }

  SlabResult slab(int angleBins) const {
    SlabSetup s;
    s.sigma_a = medium.sigma_a;
    s.sigma_s = medium.sigma_s;
    s.g = medium.g;
    s.n_inside = medium.eta;
    s.thickness = kT;
    TraceOptions o;
    o.photons = 1'000'000;
    o.seed = 8;
    o.threads = 2;
    o.angle_bins = angleBins;
    return traceSlab(s, o);
  }
};

TEST(MeshTracer, PinholeImageShowsThePlaneWaveExitanceEverywhere) {
  // An oblique pinhole view of the middle of the lit top face: every pixel's exitance is Rd·E. Checked on the whole image and on its near and
  // far halves (different distances and angles, same exitance: the d² and cosine weighting).
  WideBeamBox scene;
  scene.medium = {0.1, 0.9, 0.0, 1.3};
  Camera cam;
  cam.position = {0.0, -12.0, 12.0};
  cam.look_at = {0.0, 0.0, 0.0};
  cam.up = {0.0, 0.0, 1.0};
  cam.fov = 25.0;
  cam.width = cam.height = 16;
  TracerOptions o;
  o.seed = 3;
  o.threads = 2;
  MeshPathTracer t(scene.mesh, scene.medium, {scene.light}, cam, 5.0, o);
  t.addPass(400'000);
  const SlabResult r = scene.slab(0);
  const Estimate expected{r.diffuse_reflectance.value * scene.irradiance(),
                          r.diffuse_reflectance.std_error * scene.irradiance()};
  std::vector<uint32_t> all, nearHalf, farHalf;
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x) {
      all.push_back(y * 16 + x);
      (y < 8 ? farHalf : nearHalf).push_back(y * 16 + x);
    }
  const auto& img = t.images().exitance;
  expectAgree(img.average(all, 0), expected, 4.0, "whole image");
  expectAgree(img.average(nearHalf, 0), expected, 4.0, "near half");
  expectAgree(img.average(farHalf, 0), expected, 4.0, "far half");
  EXPECT_LT(img.average(all, 0).std_error, 0.03 * expected.value);  // the test has power
}

// The cone average the image tally estimates, ∫cone L(θ(ω)) cos θ dω / ∫cone cos θ dω about a
// view direction at θv from the normal, from the slab's exit-angle tally: L(θ) = E rd(θ) / cos θ
// at the bin centres (rd per steradian), linearly interpolated.
double coneAverage(const SlabResult& r, double irradiance, double thetaV, double halfAngle) {
  const auto& th = r.angular.theta;
  auto L = [&](double t) {
    const double x = std::clamp((t - th.front()) / r.angular.dtheta, 0.0, th.size() - 1.000001);
    const size_t j = static_cast<size_t>(x);
    const double f = x - static_cast<double>(j);
    const double a = r.angular.rd[j] / std::cos(th[j]), b = r.angular.rd[j + 1] / std::cos(th[j + 1]);
    return irradiance * ((1.0 - f) * a + f * b);
  };
  double num = 0.0, den = 0.0;
  const int na = 64, np = 128;
  for (int i = 0; i < na; ++i) {
    const double al = (i + 0.5) * halfAngle / na;
    for (int k = 0; k < np; ++k) {
      const double ph = (k + 0.5) * 2.0 * kPi / np;
      const double c = std::cos(thetaV) * std::cos(al) + std::sin(thetaV) * std::sin(al) * std::cos(ph);
      const double w = c * std::sin(al);
      num += L(std::acos(c)) * w;
      den += w;
    }
  }
  return num / den;
}

TEST(MeshTracer, ConeRadianceIsTheSlabsAngularRadiance) {
  // An orthographic view at 45° of the same face: the cone-averaged radiance (10° half-angle)
  // must match the same cone average of the slab's exit-angle tally (2.5° bins). Checked for an
  // index-matched medium (photons leave along their own direction) and a refractive one.
  for (const double eta : {1.0, 1.4}) {
    SCOPED_TRACE(::testing::Message() << "eta " << eta);
    WideBeamBox scene;
    scene.medium = {0.1, 0.9, 0.0, eta};
    Camera cam;
    cam.projection = Camera::Projection::Orthographic;
    cam.position = {0.0, -10.0, 10.0};
    cam.look_at = {0.0, 0.0, 0.0};
    cam.up = {0.0, 0.0, 1.0};
    cam.view_height = 6.0;
    cam.width = cam.height = 8;
    TracerOptions o;
    o.seed = 13;
    o.threads = 2;
    MeshPathTracer t(scene.mesh, scene.medium, {scene.light}, cam, 10.0, o);
    t.addPass(1'500'000);
    const SlabResult r = scene.slab(36);
    const double cos45 = std::cos(kPi / 4.0);
    // The slab's error: that of its two bins around 45°, each about L / sqrt(photons in it).
    const double value = coneAverage(r, scene.irradiance(), kPi / 4.0, 10.0 * kPi / 180.0);
    const double relErr = std::hypot(r.angular.rd_stderr[17] / r.angular.rd[17],
                                     r.angular.rd_stderr[18] / r.angular.rd[18]) / 2.0;
    const Estimate expected{value, value * relErr};
    std::vector<uint32_t> all;
    for (uint32_t p = 0; p < 64; ++p) all.push_back(p);
    const Estimate cone = t.images().cone_radiance.average(all, 0);
    expectAgree(cone, expected, 4.0, "cone radiance");
    EXPECT_LT(cone.std_error, 0.05 * expected.value);
    // The diffusion radiance of the same pixels is Ft(45°) B / π by construction; its ratio to
    // the true radiance is the error of the Lambertian exit assumption, not tested here.
    const Estimate b = t.images().exitance.average(all, 0);
    const Estimate l = t.images().radiance.average(all, 0);
    const double ft = eta == 1.0 ? 1.0 : fresnelTransmittance(cos45, eta);
    EXPECT_NEAR(l.value, ft * b.value / kPi, 1e-12 * b.value);
  }
}

TEST(MeshTracer, SameImagesOnAnyThreadCount) {
  const auto cube = geometry::makeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  Medium medium;
  medium.scale = 4.0;
  std::vector<Light> lights = {
      Light{DirectionalLight{{-0.3, 1.0, 0.5}, 1.0}, {1.0, 1.0, 1.0}},
      Light{PointLight{{1.5, 0.5, 1.0}, 0.4}, {1.0, 0.7, 0.5}}};
  Camera cam;
  cam.position = {1.6, 1.2, 2.2};
  cam.width = cam.height = 10;
  std::vector<CameraImages> images;
  for (const int threads : {1, 2}) {
    TracerOptions o;
    o.seed = 17;
    o.threads = threads;
    MeshPathTracer t(cube, medium, lights, cam, 5.0, o);
    t.addPass(3 * kBlockPhotons);
    images.push_back(t.images());
  }
  double total = 0.0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(images[0].exitance.pixel(x, y, c).value, images[1].exitance.pixel(x, y, c).value);
        ASSERT_EQ(images[0].cone_radiance.pixel(x, y, c).value,
                  images[1].cone_radiance.pixel(x, y, c).value);
        total += images[0].exitance.pixel(x, y, c).value;
      }
  EXPECT_GT(total, 0.0);
}

// Temporary files for the loading tests.
class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("translucent_test_mesh_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

const char* kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

std::string meshError(const std::string& path) {
  try {
    (void)geometry::loadMesh(path);
  } catch (const geometry::MeshError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeshLoading, LoadsObjAndPlyAndChecksClosedness) {
  TempDir dir;
  const auto cube = geometry::loadMesh(dir.write("cube.obj", kCubeObj));
  EXPECT_EQ(cube.triangleCount(), 12u);
  EXPECT_NEAR(cube.area(), 6.0, 1e-12);
  EXPECT_EQ(cube.openEdgeCount(), 0u);
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const auto tetra = geometry::loadMesh(dir.write("tetra.ply", ply));
  EXPECT_EQ(tetra.triangleCount(), 4u);
  EXPECT_NEAR(tetra.area(), 1.5 + 0.5 * std::sqrt(3.0), 1e-6);
  EXPECT_EQ(tetra.openEdgeCount(), 0u);
  // One face missing: open.
  auto open = geometry::loadMesh(dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_EQ(open.openEdgeCount(), 3u);
  try {
    MeshBody body(open, "open.obj");
    ADD_FAILURE() << "an open mesh was accepted";
  } catch (const geometry::MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("closed"), std::string::npos) << e.what();
  }
}

TEST(MeshLoading, BadFilesGiveErrorsNamingTheFile) {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.obj").string();
  EXPECT_NE(meshError(missing).find("does not exist"), std::string::npos) << meshError(missing);
  const std::string empty = dir.write("empty.obj", "");
  EXPECT_NE(meshError(empty).find("is empty"), std::string::npos) << meshError(empty);
  const std::string points = dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_NE(meshError(points).find("points.obj"), std::string::npos) << meshError(points);
  const std::string garbage = dir.write("garbage.ply", "ply\nthis is not a ply header\n");
  EXPECT_NE(meshError(garbage).find("garbage.ply"), std::string::npos) << meshError(garbage);
  // (assimp's OFF reader silently wraps out-of-range indices; its OBJ reader rejects them.)
  const std::string badIndex = dir.write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  EXPECT_NE(meshError(badIndex).find("out of range"), std::string::npos) << meshError(badIndex);
  const std::string truncated = dir.write("truncated.off", "OFF\n3 1\n0 0 0\n1 0\n");
  EXPECT_NE(meshError(truncated).find("truncated.off"), std::string::npos) << meshError(truncated);
  const std::string inf = dir.write("inf.obj", "v 0 0 0\nv 1 0 1e999\nv 0 1 0\nf 1 2 3\n");
  // OBJ vertices are numbered from 1 in messages, as the file's 'f' lines number them.
  EXPECT_NE(meshError(inf).find("line 2: vertex 2 coordinate z is inf"), std::string::npos)
      << meshError(inf);
}

TEST(MeshScene, ParsesRoundTripsAndRejectsBadKeys) {
  TempDir dir;
  dir.write("cube.obj", kCubeObj);
  const std::string text = R"({
    "mesh": {"file": "cube.obj", "scale": 2.0, "translate": [1, 0, 0]},
    "material": {"preset": "Skin1", "scale": 10},
    "lights": [{"type": "directional", "direction": [0, 0, 2]},
               {"type": "beam", "origin": [0, 0, 5], "direction": [0, 0, -1], "radius": 0.1,
                "power": 2, "color": [1, 0.5, 0.25]}],
    "camera": {"type": "orthographic", "position": [0, 0, 5], "view_height": 3,
               "width": 32, "height": 24},
    "cone_angle": 3})";
  const std::string file = dir.write("scene.json", text);
  const MeshScene s = loadMeshScene(file);
  EXPECT_EQ(s.mesh_file, dir.path() / "cube.obj");
  EXPECT_EQ(s.mesh_scale, 2.0);
  EXPECT_EQ(s.preset, "Skin1");
  EXPECT_EQ(s.medium.scale, 10.0);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_NEAR(std::get<DirectionalLight>(s.lights[0].emitter).direction.z, 1.0, 1e-15);
  EXPECT_EQ(s.lights[1].color[2], 0.25);
  EXPECT_EQ(s.camera.projection, Camera::Projection::Orthographic);
  EXPECT_EQ(s.camera.height, 24);
  EXPECT_EQ(s.cone_angle, 3.0);
  // Round trip: the written scene reads back to the same scene.
  const MeshScene again = parseMeshScene(toJson(s), dir.path(), "round trip");
  EXPECT_EQ(toJson(again), toJson(s));

  auto error = [&](const std::string& json) -> std::string {
    try {
      (void)parseMeshScene(json, dir.path(), "scene");
    } catch (const ParameterError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string base = R"("mesh": {"file": "cube.obj"}, "material": {"preset": "Marble"},
      "camera": {"position": [0, 0, 5]})";
  EXPECT_NE(error("{" + base + R"(, "lights": [{"type": "spot", "position": [0,0,1]}]})").find("lights[0].type"),
            std::string::npos);
  EXPECT_NE(error("{" + base + R"(, "lights": [{"type": "point", "positon": [0,0,1]}]})").find("valid keys"),
            std::string::npos);
  EXPECT_NE(error("{" + base + R"(, "lights": []})").find("lights"), std::string::npos);
  EXPECT_NE(error(R"({"mesh": {"file": "cube.obj"}, "material": {"sigma_a": [0.1, "x", 0.1], "sigma_s": 1},
      "lights": [{"type": "directional", "direction": [0,0,1]}], "camera": {"position": [0,0,5]}})")
                .find("material.sigma_a[1]"),
            std::string::npos);
  EXPECT_NE(error("{" + base + R"(, "lights": [{"type": "directional", "direction": [0,0,0]}]})")
                .find("direction"),
            std::string::npos);
  EXPECT_NE(error("{ not json").find("not valid JSON"), std::string::npos);
}

TEST(MeshTracer, RejectsBadMediaAndLights) {
  const auto cube = geometry::makeBox({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0});
  Camera cam;
  auto error = [&](const ScalarMedium& m, std::vector<Light> lights) -> std::string {
    try {
      MeshPathTracer t(cube, m, std::move(lights), cam, 5.0, TracerOptions{});
    } catch (const ParameterError& e) {
      return e.what();
    }
    return "no error";
  };
  const Light sun{DirectionalLight{{0.0, 0.0, 1.0}, 1.0}, {1.0, 1.0, 1.0}};
  EXPECT_NE(error({std::nan(""), 1.0, 0.0, 1.3}, {sun}).find("sigma_a is nan"), std::string::npos);
  EXPECT_NE(error({0.1, 1.0, 0.0, 1.3}, {}).find("no lights"), std::string::npos);
  const Light negative{PointLight{{0.0, 0.0, 3.0}, -1.0}, {1.0, 1.0, 1.0}};
  EXPECT_NE(error({0.1, 1.0, 0.0, 1.3}, {negative}).find("intensity is -1"), std::string::npos);
}

TEST(ImageIo, ExrRoundTripsFloatsAndLayers) {
  TempDir dir;
  const int w = 5, h = 3;
  std::vector<float> rgb(static_cast<size_t>(w * h * 3)), err(rgb.size());
  for (size_t i = 0; i < rgb.size(); ++i) {
    rgb[i] = 1e-6f * static_cast<float>(i * i) + 3.25f * static_cast<float>(i % 3);
    err[i] = 0.5f * static_cast<float>(i);
  }
  const std::string path = (dir.path() / "img.exr").string();
  const analysis::ExrLayer layers[] = {{"stderr", err}};
  analysis::writeExr(path, w, h, rgb, layers);
  const analysis::RgbImage back = analysis::readRgb(path);
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  EXPECT_EQ(back.rgb, rgb);
  EXPECT_NE(std::find(back.channel_names.begin(), back.channel_names.end(), "stderr.G"),
            back.channel_names.end());
  // Tone mapping: exposure in stops, then gamma.
  EXPECT_EQ(analysis::toneMap(0.25f, {1.0, 1.0}), 128);
  EXPECT_EQ(analysis::toneMap(0.25f, {0.0, 2.0}), 128);
  EXPECT_EQ(analysis::toneMap(4.0f, {0.0, 2.2}), 255);
  EXPECT_THROW(analysis::writeExr((dir.path() / "no_dir" / "x.exr").string(), w, h, rgb),
               analysis::ImageError);
  EXPECT_THROW(analysis::writePng((dir.path() / "short.png").string(), w, h + 1, rgb),
               analysis::ImageError);
}

}  // namespace
}  // namespace translucent::reference
