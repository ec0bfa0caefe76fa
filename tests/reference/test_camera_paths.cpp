// SPDX-License-Identifier: GPL-3.0-or-later
// The camera method of the mesh reference (src/reference/camera_paths.h): backward paths with
// next-event estimation against closed forms of single scattering (a sun on a half-space, an
// optically thin cube by quadrature of the single-scattering integral), against the light method
// (mesh_tracer.h: the same pixel averages; image means and per-pixel z maps at a Bonferroni-
// corrected level) for directional, point lights and a heterogeneous field, determinism, and the
// refusals. All at η = 1 (the method refuses η ≠ 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "image_zmap.h"
#include "mesh_test_scenes.h"
#include "single_scattering.h"
#include "test_fields.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/phase.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;
using test_support::bonferroniZ;
using test_support::gaussPanels;
using test_support::gaussPanelsSplit;

std::vector<uint32_t> allPixels(const McImage& img) {
  std::vector<uint32_t> p(static_cast<size_t>(img.width() * img.height()));
  for (uint32_t i = 0; i < p.size(); ++i) p[i] = i;
  return p;
}

void expectAgree(const Estimate& a, const Estimate& b, double k, const std::string& what) {
  EXPECT_NEAR(a.value, b.value, k * std::hypot(a.std_error, b.std_error))
      << what << ": " << a.value << " ± " << a.std_error << " vs " << b.value << " ± "
      << b.std_error;
}

// Per pixel, |value - exact(x, y)| / se below the Bonferroni bound for a 1% false alarm rate
// over the image; returns the number of pixels tested.
template <class Exact>
int expectPixelsMatch(const McImage& img, int c, Exact&& exact, const std::string& what) {
  const int n = img.width() * img.height();
  const double bound = bonferroniZ(n, 0.01);
  int tested = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const Estimate e = img.pixel(x, y, c);
      const double want = exact(x, y);
      EXPECT_GT(e.std_error, 0.0) << what << " pixel " << x << "," << y;
      EXPECT_LT(std::abs(e.value - want) / e.std_error, bound)
          << what << " pixel " << x << "," << y << ": " << e.value << " ± " << e.std_error
          << ", exact " << want;
      ++tested;
    }
  return tested;
}

// Henyey-Greenstein per steradian.
double hg(double cosTheta, double g) { return hgCosineDensity(cosTheta, g) / (2.0 * kPi); }

// A 12 x 12 x 3 box of σt = 4 (24 mean free paths from the middle of its top face to the side
// walls, 12 deep) under a sun, seen obliquely by an orthographic camera: a half-space for the
// pixels, so the single-scattered radiance is E α p(d·ω_l) μi / (μi + μo) in every pixel (the
// radiative transfer equation integrated along the camera ray: ∫ σs p E e^{-σt s μo/μi} e^{-σt s} ds).
struct SunOnSlab {
  geometry::TriangleMesh mesh = geometry::makeBox({-6.0, -6.0, -3.0}, {6.0, 6.0, 0.0});
  ScalarMedium medium{2.0, 2.0, 0.4, 1.0};
  glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, 0.2, 1.0));
  Light light{DirectionalLight{sun, 1.5}, {1.0, 1.0, 1.0}};
  Camera camera() const {
    Camera cam = test_support::orthographic({0.0, -10.0, 10.0}, 2.0, 8);
    cam.up = {0.0, 0.0, 1.0};
    return cam;
  }
  double singleScattering() const {
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.0, 10.0, -10.0));  // camera ray
    const double mu_i = sun.z, mu_o = -d.z;
    return 1.5 * medium.albedo() * hg(glm::dot(d, sun), medium.g) * mu_i / (mu_i + mu_o);
  }
};

TEST(CameraPaths, SunOnAHalfSpaceGivesTheClosedFormSingleScattering) {
  SunOnSlab s;
  CameraPathOptions o;
  o.seed = 5;
  o.threads = 2;
  o.split_orders = true;
  o.exitance = false;
  CameraPathTracer t(s.mesh, s.medium, {s.light}, s.camera(), o);
  t.addPass(512);
  const double exact = s.singleScattering();
  const McImage& single = t.orderImages(ScatteringOrder::Single).cone_radiance;
  expectPixelsMatch(single, 0, [&](int, int) { return exact; }, "single scattering");
  const Estimate mean = single.average(allPixels(single), 0);
  EXPECT_NEAR(mean.value, exact, 3.5 * mean.std_error) << mean.value << " ± " << mean.std_error;
  EXPECT_LT(mean.std_error, 0.01 * exact);  // the test has power
  // The orders add up; nothing unscattered reaches the camera.
  const Estimate total = t.images().cone_radiance.average(allPixels(single), 0);
  const Estimate multiple =
      t.orderImages(ScatteringOrder::Multiple).cone_radiance.average(allPixels(single), 0);
  EXPECT_NEAR(total.value, mean.value + multiple.value, 1e-9 * total.value);
  EXPECT_GT(multiple.value, 0.1 * mean.value);
  EXPECT_EQ(t.orderImages(ScatteringOrder::Unscattered).cone_radiance.average(allPixels(single), 0).value,
            0.0);
}

TEST(CameraPaths, SunOnAHalfSpaceAgreesWithTheLightMethod) {
  // The same scene traced both ways: the exitance and the 10° cone radiance (the light method's
  // estimand, which the camera method samples with its cone option) agree in the image means.
  SunOnSlab s;
  CameraPathOptions o;
  o.seed = 6;
  o.threads = 2;
  o.cone_half_angle = 10.0;
  CameraPathTracer cam(s.mesh, s.medium, {s.light}, s.camera(), o);
  cam.addPass(256);
  TracerOptions lo;
  lo.seed = 7;
  lo.threads = 2;
  MeshPathTracer light(s.mesh, s.medium, {s.light}, s.camera(), 10.0, lo);
  light.addPass(3'000'000);
  const auto all = allPixels(cam.images().exitance);
  const Estimate bc = cam.images().exitance.average(all, 0), bl = light.images().exitance.average(all, 0);
  expectAgree(bc, bl, 3.5, "exitance");
  EXPECT_LT(bl.std_error, 0.03 * bl.value);
  expectAgree(cam.images().cone_radiance.average(all, 0), light.images().cone_radiance.average(all, 0),
              3.5, "cone radiance");
  // At η = 1 the diffusion radiance is B / π sample by sample.
  const Estimate lc = cam.images().radiance.average(all, 0);
  EXPECT_NEAR(lc.value, bc.value / kPi, 1e-9 * bc.value);
}

TEST(CameraPaths, OpticallyThinCubeMatchesTheSingleScatteringIntegral) {
  // A unit cube of σt = 0.5 under a sun 40° from the zenith in the xz plane, seen from above by an
  // orthographic camera whose pixels all look through the top face. A camera ray at x crosses
  // depths z in [0, 1]; light reaches (x, z) through the top face or the +x face, whichever is
  // nearer along ω_l: ℓ = min(z / cos θ, (0.5 - x) / sin θ). Per pixel:
  //   L1 = (1 / Δx) ∫_pixel dx ∫_0^1 σs p(-cos θ) E e^{-σt z} e^{-σt ℓ(x, z)} dz.
  const ScalarMedium m{0.1, 0.4, 0.3, 1.0};
  const double theta = 40.0 * kPi / 180.0, E = 2.0;
  const glm::dvec3 sun(std::sin(theta), 0.0, std::cos(theta));
  const Light light{DirectionalLight{sun, E}, {1.0, 1.0, 1.0}};
  Camera camera = test_support::orthographic({0.0, 0.0, 5.0}, 0.8, 8);
  CameraPathOptions o;
  o.seed = 9;
  o.threads = 2;
  o.split_orders = true;
  o.exitance = false;
  CameraPathTracer t(geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5)), m, {light}, camera, o);
  t.addPass(1024);
  // The camera's right vector is +x (forward -z, up +y): pixel i covers x in -0.4 + 0.1 [i, i+1).
  const double sigmaT = m.sigmaT(), phase = hg(-std::cos(theta), m.g);
  auto exact = [&](int i, int) {
    const double x0 = -0.4 + 0.1 * i;
    auto column = [&](double x) {
      const double kink = (0.5 - x) * std::cos(theta) / std::sin(theta);
      return gaussPanelsSplit(
          [&](double z) {
            const double l = std::min(z / std::cos(theta), (0.5 - x) / std::sin(theta));
            return m.sigma_s * phase * E * std::exp(-sigmaT * (z + l));
          },
          0.0, 1.0, kink, 16);
    };
    return gaussPanels(column, x0, x0 + 0.1, 4) / 0.1;
  };
  const McImage& single = t.orderImages(ScatteringOrder::Single).cone_radiance;
  expectPixelsMatch(single, 0, exact, "thin cube single scattering");
  // Power: per column the error is below 2% (columns differ by the +x face's shadow).
  for (int i = 0; i < 8; ++i) {
    std::vector<uint32_t> col;
    for (uint32_t y = 0; y < 8; ++y) col.push_back(y * 8 + static_cast<uint32_t>(i));
    const Estimate e = single.average(col, 0);
    EXPECT_NEAR(e.value, exact(i, 0), 3.5 * e.std_error) << "column " << i;
    EXPECT_LT(e.std_error, 0.02 * e.value);
  }
}

// Image means (z-test) and a per-pixel z map at a Bonferroni-corrected 1% level between the two
// methods, for the exitance and the cone radiance of every channel; pixels where the light
// method's estimate rests on a handful of photons (relative error > 0.3) are left out of the map.
void expectMethodsAgree(const CameraImages& cam, const CameraImages& light, int channels,
                        double meanPower, size_t minPixels) {
  const auto all = allPixels(cam.exitance);
  for (int c = 0; c < channels; ++c) {
    for (const auto& [name, a, b] :
         {std::tuple{"exitance", &cam.exitance, &light.exitance},
          std::tuple{"cone radiance", &cam.cone_radiance, &light.cone_radiance}}) {
      SCOPED_TRACE(::testing::Message() << name << ", channel " << c);
      const Estimate ea = a->average(all, c), eb = b->average(all, c);
      expectAgree(ea, eb, 3.5, "image mean");
      EXPECT_LT(std::hypot(ea.std_error, eb.std_error), meanPower * eb.value);
      std::vector<double> z;
      for (int y = 0; y < a->height(); ++y)
        for (int x = 0; x < a->width(); ++x) {
          const Estimate p = a->pixel(x, y, c), q = b->pixel(x, y, c);
          if (!(p.std_error > 0.0 && q.std_error > 0.0 && q.std_error < 0.3 * q.value)) continue;
          z.push_back((p.value - q.value) / std::hypot(p.std_error, q.std_error));
        }
      ASSERT_GE(z.size(), minPixels);
      const double bound = bonferroniZ(static_cast<int>(z.size()), 0.01);
      double worst = 0.0;
      for (const double v : z) worst = std::max(worst, std::abs(v));
      EXPECT_LT(worst, bound) << z.size() << " pixels";
    }
  }
}

TEST(CameraPaths, AgreesWithTheLightMethodUnderASunOnThreeCubes) {
  // Three cubes in a row (one mesh) under an oblique sun: the cubes shadow one another through
  // their medium (η = 1: straight through every boundary); pinhole camera (the cos³ weights).
  const auto mesh = test_support::threeCubes();
  const ScalarMedium m{0.5, 3.0, 0.3, 1.0};
  const Light sun{DirectionalLight{glm::normalize(glm::dvec3(0.3, 0.5, 1.0)), 1.0}, {1.0, 1.0, 1.0}};
  Camera camera;
  camera.position = {3.5, 2.0, 2.5};
  camera.look_at = {0.0, 0.0, -0.5};
  camera.fov = 60.0;
  camera.width = camera.height = 12;
  CameraPathOptions o;
  o.seed = 11;
  o.threads = 2;
  o.cone_half_angle = 10.0;
  CameraPathTracer cam(mesh, m, {sun}, camera, o);
  cam.addPass(192);
  TracerOptions lo;
  lo.seed = 12;
  lo.threads = 2;
  MeshPathTracer light(mesh, m, {sun}, camera, 10.0, lo);
  light.addPass(2'000'000);
  expectMethodsAgree(cam.images(), light.images(), 1, 0.04, 25);
}

TEST(CameraPaths, AgreesWithTheLightMethodInAHeterogeneousSphere) {
  // A dense core (σt 12) in a thinner shell (σt 3) inside the unit sphere: delta tracking for
  // the flights, ratio tracking for the shadow rays.
  const auto mesh = geometry::makeIcosphere(3);
  material::Material mat;
  mat.kind = material::Material::Kind::Volume;
  mat.medium.eta = 1.0;
  mat.medium.scale = 1.0;
  mat.volume = std::make_shared<testing::CoreField>(0.6, testing::grey(1.0, 11.0, 0.0),
                                                    testing::grey(0.5, 2.5, 0.3));
  const Light sun{DirectionalLight{glm::normalize(glm::dvec3(0.4, 0.2, 1.0)), 1.0}, {1.0, 1.0, 1.0}};
  Camera camera;
  camera.position = {0.0, -2.0, 3.5};
  camera.look_at = {0.0, 0.0, 0.0};
  camera.fov = 40.0;
  camera.width = camera.height = 10;
  CameraPathOptions o;
  o.seed = 15;
  o.threads = 2;
  o.cone_half_angle = 10.0;
  CameraPathTracer cam(mesh, mat, {sun}, camera, o);
  cam.addPass(96);
  TracerOptions lo;
  lo.seed = 16;
  lo.threads = 2;
  MeshPathTracer light(mesh, mat, {sun}, camera, 10.0, lo);
  light.addPass(600'000);
  expectMethodsAgree(cam.images(), light.images(), 1, 0.06, 20);
  EXPECT_EQ(cam.majorantViolations(), 0u);
}

TEST(CameraPaths, SameImagesOnAnyThreadCountAndPassSplit) {
  const auto cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  Medium medium;
  medium.eta = 1.0;
  medium.scale = 4.0;
  const std::vector<Light> lights = {
      Light{DirectionalLight{{-0.3, 1.0, 0.5}, 1.0}, {1.0, 1.0, 1.0}},
      Light{PointLight{{1.5, 0.5, 1.0}, 0.4}, {1.0, 0.7, 0.5}},
      Light{BeamLight{{0.2, 0.1, 3.0}, {0.0, 0.0, -1.0}, 0.3, 0.5}, {1.0, 1.0, 1.0}}};
  Camera camera;
  camera.position = {1.6, 1.2, 2.2};
  camera.width = camera.height = 8;
  std::vector<CameraImages> images;
  for (const int run : {0, 1, 2}) {
    CameraPathOptions o;
    o.seed = 17;
    o.threads = run == 0 ? 1 : 2;
    o.split_orders = true;
    CameraPathTracer t(cube, medium, lights, camera, o);
    if (run < 2) {
      t.addPass(16);
    } else {
      t.addPass(4);  // the same samples in two passes
      t.addPass(12);
    }
    EXPECT_EQ(t.stats().samples, 16u);
    images.push_back(t.images());
  }
  double total = 0.0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c)
        for (int r = 1; r < 3; ++r) {
          // Threads: bit for bit. Passes: the same samples, summed per pass in double before the
          // exact sums (exact_sum.h), so equal to rounding.
          const Estimate a = images[0].exitance.pixel(x, y, c), b = images[r].exitance.pixel(x, y, c);
          const Estimate p = images[0].cone_radiance.pixel(x, y, c);
          const Estimate q = images[r].cone_radiance.pixel(x, y, c);
          if (r == 1) {
            ASSERT_EQ(a.value, b.value);
            ASSERT_EQ(a.std_error, b.std_error);
            ASSERT_EQ(p.value, q.value);
          } else {
            ASSERT_NEAR(a.value, b.value, 1e-12 * std::abs(a.value));
            ASSERT_NEAR(a.std_error, b.std_error, 1e-9 * a.std_error);
            ASSERT_NEAR(p.value, q.value, 1e-12 * std::abs(p.value));
          }
          total += images[0].cone_radiance.pixel(x, y, c).value;
        }
  EXPECT_GT(total, 0.0);
}

TEST(CameraPaths, RefusesWhatItCannotTraceNamingTheLightMethod) {
  const auto cube = geometry::makeBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const Camera camera;
  const Light sun{DirectionalLight{{0.0, 0.0, 1.0}, 1.0}, {1.0, 1.0, 1.0}};
  auto message = [&](const ScalarMedium& m, const Light& l) {
    try {
      CameraPathTracer t(cube, m, {l}, camera, {});
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string refractive = message({0.1, 1.0, 0.0, 1.3}, sun);
  EXPECT_NE(refractive.find("eta 1.3"), std::string::npos) << refractive;
  EXPECT_NE(refractive.find("--method light"), std::string::npos) << refractive;
  const Light pencil{BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
  const std::string beam = message({0.1, 1.0, 0.0, 1.0}, pencil);
  EXPECT_NE(beam.find("pencil beam"), std::string::npos) << beam;
  CameraPathOptions bad;
  bad.cone_half_angle = 90.0;
  EXPECT_THROW(CameraPathTracer(cube, ScalarMedium{0.1, 1.0, 0.0, 1.0}, {sun}, camera, bad),
               ParameterError);
}

}  // namespace
}  // namespace translucent::reference
