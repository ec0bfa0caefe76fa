// SPDX-License-Identifier: GPL-3.0-or-later
// The lit sphere path tracer (src/reference/sphere.h) and the cameras (camera.h): energy
// conservation against the analytic transmitted flux, the image tally against an independent
// tally of the same photons, mirror symmetry, determinism over thread counts and pass splits,
// camera geometry, and clear errors for bad scenes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/sphere.h"
#include "published_setups.h"
#include "translucent/reference/transport_impl.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;

SphereScene headOn(double radius, int size) {
  SphereScene s;
  s.radius = radius;
  s.light_direction = {0.0, 0.0, 1.0};
  s.view_direction = {0.0, 0.0, 1.0};
  s.width = s.height = size;
  return s;
}

TracerOptions threads(int n, uint64_t seed = 11) {
  TracerOptions o;
  o.threads = n;
  o.seed = seed;
  return o;
}

TEST(SpherePathTracer, ConservesEnergyWithoutAbsorption) {
  // σa = 0: every photon that enters leaves again (the walk ends with probability 1 in a finite
  // body), so the exiting flux equals the entering flux photon by photon; the entering flux
  // itself must match πR² E0 · 2∫Ft μ dμ within its standard error.
  SphereScene scene = headOn(1.5, 16);
  scene.light_direction = {0.3, -0.2, 1.0};
  scene.irradiance = 2.0;
  const ScalarMedium m{0.0, 2.0, 0.5, 1.4};
  SpherePathTracer t(scene, m, threads(2));
  const TransportStats s = t.addPass(100'000);
  const uint64_t n = s.photons[0];
  EXPECT_EQ(n, 98 * kBlockPhotons);
  const Estimate emitted = s.emitted[0].estimate(n), entered = s.entered[0].estimate(n),
                 exited = s.exited[0].estimate(n);
  EXPECT_NEAR(emitted.value, 2.0 * kPi * 1.5 * 1.5, 1e-9);
  const double expected = 2.0 * kPi * 1.5 * 1.5 * test_support::sphereEnteringFraction(1.4);
  EXPECT_NEAR(entered.value, expected, 4.0 * entered.std_error);
  EXPECT_GT(entered.std_error, 0.0);
  EXPECT_NEAR(exited.value, entered.value, 1e-12 * entered.value);
  EXPECT_FALSE(s.partial);
}

TEST(SpherePathTracer, AbsorptionRemovesTheExpectedShareOfAnIndexMatchedSphere) {
  // η = 1: all light enters (no Fresnel), so the entering flux is exactly πR² per photon; with
  // absorption the exiting flux is lower, and for a pure absorber (σs = 0) it is the chord
  // transmittance averaged over the disc: ∫ e^{-σa 2 sqrt(R² - ρ²)} 2πρ dρ / (πR²)
  //   = 2 [1 - (1 + 2σaR) e^{-2σaR}] / (2σaR)².
  const double R = 1.0, sa = 0.7;
  SpherePathTracer t(headOn(R, 8), ScalarMedium{sa, 0.0, 0.0, 1.0}, threads(2));
  const TransportStats s = t.addPass(60'000);
  const uint64_t n = s.photons[0];
  EXPECT_NEAR(s.entered[0].estimate(n).value, kPi * R * R, 1e-12);
  EXPECT_EQ(s.entered[0].estimate(n).std_error, 0.0);
  const double x = 2.0 * sa * R;
  const double expected = kPi * R * R * 2.0 * (1.0 - (1.0 + x) * std::exp(-x)) / (x * x);
  const Estimate exited = s.exited[0].estimate(n);
  EXPECT_NEAR(exited.value, expected, 4.0 * exited.std_error);
}

// An independent tally of the same photons: the flux leaving the visible hemisphere, weighted by
// n·v (the projected area measure), whose mean is what the exitance image sums to.
class ProjectedFlux final : public ExitTally {
 public:
  explicit ProjectedFlux(glm::dvec3 v) : v_(v) {}
  class Sum final : public Block {
   public:
    explicit Sum(glm::dvec3 v) : v_(v) {}
    void record(const ExitRecord& e) override {
      const double c = glm::dot(e.normal, v_);
      if (c > 0.0) s += e.weight * c;
    }
    double s = 0.0;

   private:
    glm::dvec3 v_;
  };
  std::unique_ptr<Block> newBlock() const override { return std::make_unique<Sum>(v_); }
  void merge(Block& b) override { total += static_cast<Sum&>(b).s; }
  double total = 0.0;

 private:
  glm::dvec3 v_;
};

TEST(SpherePathTracer, ImageSumsToTheProjectedExitingFlux) {
  // Σ_pixels B_p a_p = ∫_visible B (n·v) dA: the image tally (projection, pixel areas) against
  // a direct sum over the same photons (same seed, same blocks).
  SphereScene scene = headOn(2.0, 24);
  scene.light_direction = {1.0, 0.5, 0.8};
  scene.view_direction = {0.2, 0.1, 1.0};
  const ScalarMedium m{0.05, 1.0, 0.3, 1.3};
  SpherePathTracer t(scene, m, threads(2, 5));
  t.addPass(40'000);
  const auto& img = t.images().exitance;
  const double pixelArea = std::pow(t.camera().pixelSize(), 2);
  double imageSum = 0.0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) imageSum += img.pixel(x, y, 0).value * pixelArea;

  const SphereBody body(scene.radius);
  ProjectedFlux direct(glm::normalize(scene.view_direction));
  TransportOptions o;
  o.photons = 40'000;
  o.seed = 5;
  o.threads = 2;
  const Light light = scene.light();
  const TransportStats s = tracePhotons(body, std::span<const ScalarMedium>(&m, 1),
                                        std::span<const Light>(&light, 1), o, direct);
  EXPECT_NEAR(imageSum, direct.total / static_cast<double>(s.photons[0]), 1e-9 * imageSum);
  EXPECT_GT(imageSum, 0.0);
}

TEST(SpherePathTracer, HeadOnImageIsMirrorSymmetric) {
  // Light and camera on the same axis: the exitance is rotationally symmetric about it, so the
  // left and right (and top and bottom) halves of the image agree within their errors.
  SpherePathTracer t(headOn(3.0, 20), ScalarMedium{0.02, 1.0, 0.0, 1.3}, threads(2, 3));
  t.addPass(60'000);
  const auto& img = t.images().exitance;
  std::vector<uint32_t> left, right, top, bottom;
  for (uint32_t y = 0; y < 20; ++y)
    for (uint32_t x = 0; x < 20; ++x) {
      (x < 10 ? left : right).push_back(y * 20 + x);
      (y < 10 ? top : bottom).push_back(y * 20 + x);
    }
  const Estimate l = img.average(left, 0), r = img.average(right, 0);
  const Estimate tp = img.average(top, 0), bt = img.average(bottom, 0);
  EXPECT_NEAR(l.value, r.value, 4.0 * std::hypot(l.std_error, r.std_error));
  EXPECT_NEAR(tp.value, bt.value, 4.0 * std::hypot(tp.std_error, bt.std_error));
  EXPECT_GT(l.value, 50.0 * l.std_error);  // the test has power
}

TEST(SpherePathTracer, SameImagesOnAnyThreadCountAndPassSplit) {
  SphereScene scene = headOn(1.0, 12);
  scene.light_direction = {1.0, 1.0, 1.0};
  Medium medium;  // marble, RGB
  medium.scale = 5.0;
  SpherePathTracer one(scene, medium, threads(1, 9)), two(scene, medium, threads(2, 9)),
      split(scene, medium, threads(2, 9));
  one.addPass(4 * kBlockPhotons);
  two.addPass(4 * kBlockPhotons);
  split.addPass(kBlockPhotons);
  split.addPass(3 * kBlockPhotons);
  EXPECT_EQ(split.passes(), 2);
  for (const SpherePathTracer* t : {&two, &split}) {
    const auto& a = one.images(), &b = t->images();
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x)
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(a.exitance.pixel(x, y, c).value, b.exitance.pixel(x, y, c).value);
          ASSERT_EQ(a.exitance.pixel(x, y, c).std_error, b.exitance.pixel(x, y, c).std_error);
          ASSERT_EQ(a.radiance.pixel(x, y, c).value, b.radiance.pixel(x, y, c).value);
          ASSERT_EQ(a.cone_radiance.pixel(x, y, c).value, b.cone_radiance.pixel(x, y, c).value);
        }
  }
  // A different seed gives different images.
  SpherePathTracer other(scene, medium, threads(2, 10));
  other.addPass(4 * kBlockPhotons);
  EXPECT_NE(other.images().exitance.pixel(6, 6, 0).value, one.images().exitance.pixel(6, 6, 0).value);
}

TEST(SpherePathTracer, RejectsBadScenesWithClearMessages) {
  const ScalarMedium m{0.1, 1.0, 0.0, 1.3};
  auto message = [&](SphereScene s, const ScalarMedium& medium) -> std::string {
    try {
      SpherePathTracer t(s, medium, threads(1));
    } catch (const ParameterError& e) {
      return e.what();
    }
    return "no error";
  };
  SphereScene s = headOn(1.0, 8);
  s.radius = -1.0;
  EXPECT_NE(message(s, m).find("radius is -1"), std::string::npos) << message(s, m);
  s = headOn(1.0, 8);
  s.light_direction = {0.0, 0.0, 0.0};
  EXPECT_NE(message(s, m).find("light direction"), std::string::npos) << message(s, m);
  s = headOn(1.0, 8);
  s.width = 0;
  EXPECT_NE(message(s, m).find("resolution"), std::string::npos) << message(s, m);
  ScalarMedium bad = m;
  bad.sigma_s = std::nan("");
  EXPECT_NE(message(headOn(1.0, 8), bad).find("sigma_s is nan"), std::string::npos)
      << message(headOn(1.0, 8), bad);
}

TEST(Camera, PinholePixelSolidAnglesSumToTheImageAndRaysProjectBack) {
  Camera c;
  c.position = {1.0, 2.0, 3.0};
  c.look_at = {0.0, 0.5, 0.0};
  c.fov = 50.0;
  c.width = 40;
  c.height = 30;
  const CameraModel m(c);
  double total = 0.0;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) total += m.pixelMeasure(i, j);
  // Solid angle of the whole rectangle [-a, a] x [-b, b] at distance 1: 4 atan(ab / sqrt(1+a²+b²)).
  const double b = std::tan(0.5 * 50.0 * kPi / 180.0), a = b * 40.0 / 30.0;
  EXPECT_NEAR(total, 4.0 * std::atan(a * b / std::sqrt(1.0 + a * a + b * b)), 1e-12);
  for (const auto& [px, py] : {std::pair{0.5, 0.5}, std::pair{20.0, 15.0}, std::pair{39.9, 7.3}}) {
    glm::dvec3 o, d;
    m.ray(px, py, o, d);
    double qx, qy;
    ASSERT_TRUE(m.project(o + 2.7 * d, qx, qy));
    EXPECT_NEAR(qx, px, 1e-9);
    EXPECT_NEAR(qy, py, 1e-9);
  }
  glm::dvec3 o, d;
  m.ray(20.0, 15.0, o, d);
  double qx, qy;
  EXPECT_FALSE(m.project(o - d, qx, qy));  // behind the camera
}

TEST(Camera, RejectsDegenerateSetups) {
  Camera c;
  c.up = glm::normalize(c.look_at - c.position);
  EXPECT_THROW(c.validate(), ParameterError);
  c = Camera{};
  c.fov = 180.0;
  EXPECT_THROW(c.validate(), ParameterError);
  c = Camera{};
  c.look_at = c.position;
  EXPECT_THROW(c.validate(), ParameterError);
}

}  // namespace
}  // namespace translucent::reference
