// SPDX-License-Identifier: GPL-3.0-or-later
// Environment lights in the references (transport.h EnvironmentLight, model_reference.h): the
// photon tracer's emission against the analytic flux a constant sky sends into a sphere, a sky
// that is one bright texel against the directional light it approximates (same shadows, same
// exits, through a body that shadows and lights itself), and the model reference's irradiance
// integral against the analytic flat-slab value and against that directional light.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/mesh.h"
#include "translucent/lights/environment_map.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/model_reference.h"
#include "translucent/reference/sphere.h"
#include "flat_slab.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;

Light environment(lights::EnvironmentMap map, double rotate = 0.0, double intensity = 1.0) {
  return Light{EnvironmentLight::make(std::make_shared<const lights::EnvironmentMap>(std::move(map)),
                                      rotate, intensity),
               {1.0, 1.0, 1.0}};
}

// A black map with one bright texel (x0, y0) of radiance `radiance`, and the directional light
// it approximates: towards the texel's centre, irradiance L ΔΩ (ΔΩ its exact solid angle).
struct Spot {
  lights::EnvironmentMap map;
  Light directional;
};
Spot spot(int width, int height, int x0, int y0, float radiance, double rotate) {
  Spot s;
  s.map = lights::EnvironmentMap::constant(glm::vec3(0.0f), width, height);
  float* p = &s.map.rgb[(size_t(y0) * size_t(width) + size_t(x0)) * 3];
  p[0] = p[1] = p[2] = radiance;
  const double dOmega = 2.0 * kPi / width *
                        (std::cos(kPi * y0 / height) - std::cos(kPi * (y0 + 1) / height));
  const glm::dvec3 d = lights::EnvironmentMap::direction((x0 + 0.5) / width, (y0 + 0.5) / height, rotate);
  s.directional = Light{DirectionalLight{d, double(radiance) * dOmega}, {1.0, 1.0, 1.0}};
  return s;
}

// Flux leaving each of two parts of the surface (x < split, x >= split), per photon summed.
class PartTally final : public ExitTally {
 public:
  explicit PartTally(double split) : split_(split) {}
  class Exits final : public Block {
   public:
    explicit Exits(double split) : split_(split) {}
    void record(const ExitRecord& e) override { photon_[e.position.x < split_ ? 0 : 1] += e.weight; }
    void endPhoton() override {
      for (int k = 0; k < 2; ++k) sums[k].add(photon_[k]), photon_[k] = 0.0;
    }
    Moments sums[2];

   private:
    double split_;
    double photon_[2]{};
  };
  std::unique_ptr<Block> newBlock() const override { return std::make_unique<Exits>(split_); }
  void merge(Block& b) override {
    for (int k = 0; k < 2; ++k) parts[k].merge(static_cast<Exits&>(b).sums[k]);
  }
  Moments parts[2];

 private:
  double split_;
};

TransportOptions options(uint64_t photons, uint64_t seed) {
  TransportOptions o;
  o.photons = photons;
  o.seed = seed;
  o.threads = 2;
  return o;
}

TEST(EnvironmentTransport, ConstantSkyIntoASphereCarriesTheAnalyticFlux) {
  // Radiance L from every direction onto a sphere of radius R: each surface point receives the
  // transmitted irradiance L λ0(η), λ0 = 2π ∫0^1 Ft(η, μ) μ dμ, so 4πR² L λ0 enters; the photons
  // leave the disc of the bounding sphere, π R_b² 4π L. Per channel (one sampler each).
  const SphereBody sphere(0.8, {0.1, -0.2, 0.3});
  const std::vector<ScalarMedium> media{{0.1, 3.0, 0.4, 1.3}, {0.2, 2.0, 0.0, 1.3}, {0.05, 5.0, 0.8, 1.3}};
  const glm::vec3 L(0.5f, 1.0f, 2.0f);
  const Light sky = environment(lights::EnvironmentMap::constant(L, 64, 32), 30.0, 1.5);
  PartTally tally(0.0);
  const TransportStats s = tracePhotons(sphere, media, std::span<const Light>(&sky, 1),
                                        options(40 * kBlockPhotons, 3), tally);
  const double lambda0 = lights::transmittedIrradianceLambdas(1.3)[0];
  const double R = 0.8, Rb = sphere.bounds().radius;
  for (size_t c = 0; c < 3; ++c) {
    const double Lc = 1.5 * double(L[int(c)]);
    const Estimate emitted = s.emitted[c].estimate(s.photons[c]);
    EXPECT_NEAR(emitted.value, kPi * Rb * Rb * 4.0 * kPi * Lc, 1e-9 * emitted.value) << c;
    const Estimate entered = s.entered[c].estimate(s.photons[c]);
    const double want = 4.0 * kPi * R * R * Lc * lambda0;
    EXPECT_GT(entered.std_error, 0.0);
    EXPECT_LT(entered.std_error, 0.01 * want) << "the test has power";
    EXPECT_NEAR(entered.value, want, 4.0 * entered.std_error) << "channel " << c;
  }
}

// Two unit boxes, B behind A along x with a gap: light from the upper -x side reaches B partly
// past A, partly through it (photons leaving A re-enter B) and A shadows part of B.
geometry::TriangleMesh twoBoxes() {
  geometry::TriangleMesh a = geometry::makeBox({-1.25, -0.5, -0.5}, {-0.25, 0.5, 0.5});
  const geometry::TriangleMesh b = geometry::makeBox({0.25, -0.5, -0.5}, {1.25, 0.5, 0.5});
  const auto base = static_cast<unsigned>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (const auto& t : b.triangles) a.triangles.push_back(t + glm::uvec3(base));
  return a;
}

TEST(EnvironmentTransport, OneBrightTexelActsAsItsDirectionalLight) {
  // The texel spans 0.18 x 0.16 degrees: its directions differ from the directional light's by
  // less than 0.002 rad, which moves the shadow of A on B by ~0.002 units and changes n·l by as
  // little: far below the 1% noise. So the flux leaving each box agrees within the noise.
  const MeshBody body(twoBoxes(), "two boxes");
  const ScalarMedium m{0.2, 4.0, 0.3, 1.4};
  // Texel (1991, 360) of 2048 x 1024, the map rotated by 100 degrees: the light comes from -x
  // and 27 degrees above the horizon, d ≈ (-0.89, 0.45, 0).
  const Spot sp = spot(2048, 1024, 1991, 360, 5000.0f, 100.0);
  const Light env = environment(sp.map, 100.0);
  const glm::dvec3 d = std::get<DirectionalLight>(sp.directional.emitter).direction;
  ASSERT_LT(d.x, -0.5) << "the set-up wants the light from -x";
  PartTally te(0.0), td(0.0);
  const TransportStats se = tracePhotons(body, std::span<const ScalarMedium>(&m, 1),
                                         std::span<const Light>(&env, 1), options(30 * kBlockPhotons, 5), te);
  const TransportStats sd = tracePhotons(body, std::span<const ScalarMedium>(&m, 1),
                                         std::span<const Light>(&sp.directional, 1),
                                         options(30 * kBlockPhotons, 6), td);
  // Same emitted flux: π R_b² L ΔΩ.
  EXPECT_NEAR(se.emitted[0].estimate(se.photons[0]).value, sd.emitted[0].estimate(sd.photons[0]).value,
              1e-6 * sd.emitted[0].estimate(sd.photons[0]).value);
  for (int k = 0; k < 2; ++k) {
    const Estimate a = te.parts[k].estimate(se.photons[0]), b = td.parts[k].estimate(sd.photons[0]);
    EXPECT_GT(b.value, 20.0 * b.std_error) << "box " << k << ": no signal";
    EXPECT_NEAR(a.value, b.value, 4.0 * std::hypot(a.std_error, b.std_error))
        << "box " << k << ": environment " << a.value << " ± " << a.std_error << ", directional "
        << b.value << " ± " << b.std_error;
  }
  // B is lit less than A (shadowed, and partly lit through A): the scene tests something.
  EXPECT_LT(td.parts[1].s, 0.8 * td.parts[0].s);
}

using testing::shortRangeMedium;

TEST(EnvironmentModelReference, ConstantSkyOverAFlatSlabGivesLambda0TimesRd) {
  // The top face of a wide box sees the whole upper hemisphere unoccluded: E = L λ0(η) there, so
  // B = L λ0 Rd in pixels farther than r_max from the edges (as the directional flat-slab test;
  // the sides and the bottom are lit too but lie beyond r_max).
  const Medium medium = shortRangeMedium();
  const Camera cam = testing::flatSlabCamera();
  ModelReferenceOptions o;
  o.samples = 400000;
  o.tail = 1e-3;
  o.threads = 2;
  o.environment_rays = 16;
  const glm::vec3 L(0.7f, 1.0f, 1.3f);
  const std::vector<Light> sky{environment(lights::EnvironmentMap::constant(L, 32, 16), 0.0, 2.0)};
  const bssrdf::Model& model = bssrdf::model("dipole");
  const auto img = renderModelReference(testing::flatSlab(), medium, model, sky, cam, o);
  const double lambda0 = lights::transmittedIrradianceLambdas(medium.eta)[0];
  std::array<double, 3> expected{};
  for (int c = 0; c < 3; ++c)
    expected[size_t(c)] = 2.0 * double(L[c]) * lambda0 * model.profile(medium.channel(c))->Rd();
  testing::expectFlatSlab(img, cam, expected, 0.03, "constant sky");
}

TEST(EnvironmentModelReference, OneBrightTexelActsAsItsDirectionalLight) {
  // The same two boxes as the transport test, seen from above and -x: the model reference with
  // the one-texel sky and with its directional light agree pixel by pixel (the environment rays
  // that the sky's sampler draws all point into the texel, so only the texel's 0.002 rad spread
  // and the noise of the E estimates differ).
  const Medium medium = shortRangeMedium();
  const Spot sp = spot(2048, 1024, 1991, 360, 5000.0f, 100.0);
  Camera cam;
  cam.position = {-2.5, 2.0, 3.0};
  cam.look_at = {0.0, 0.0, 0.0};
  cam.fov = 40.0;
  cam.width = 24;
  cam.height = 16;
  ModelReferenceOptions o;
  o.samples = 100000;
  o.threads = 2;
  o.environment_rays = 8;
  const bssrdf::Model& model = bssrdf::model("dipole");
  const std::vector<Light> env{environment(sp.map, 100.0)};
  const std::vector<Light> dir{sp.directional};
  const auto a = renderModelReference(twoBoxes(), medium, model, env, cam, o);
  const auto b = renderModelReference(twoBoxes(), medium, model, dir, cam, o);
  double lit = 0.0, maxValue = 0.0;
  for (size_t i = 0; i < b.exitance.size(); ++i) maxValue = std::max(maxValue, double(b.exitance[i]));
  ASSERT_GT(maxValue, 0.0);
  for (size_t i = 0; i < a.exitance.size(); ++i) {
    // The same surface samples: their noise is shared and cancels; what is left is the spread of
    // the texel and the environment rays' noise, counted in a's standard error.
    EXPECT_NEAR(a.exitance[i], b.exitance[i], 4.0 * double(a.exitance_se[i]) + 0.01 * maxValue) << "value " << i;
    lit += double(b.exitance[i]) > 0.1 * maxValue ? 1.0 : 0.0;
  }
  EXPECT_GT(lit, 0.1 * double(b.exitance.size()));  // 14%: the boxes fill part of the frame
}

}  // namespace
}  // namespace translucent::reference
