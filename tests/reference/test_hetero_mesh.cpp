// SPDX-License-Identifier: GPL-3.0-or-later
// The heterogeneous mesh walk (delta tracking through a majorant grid, majorant_grid.h) against
// independent computations of the same medium: the homogeneous walk for a homogeneous field
// traced with a loose majorant (null collisions), the homogeneous walk of the upper medium for a
// field that changes only far below the surface, and the layered slab tracer (layered_slab.h:
// exact optical-depth flights, no null collisions) for a plane-layered field in a wide flat box.
// Plus determinism across thread counts and the material entry point's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "radial_tally.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/mesh_tracer.h"
#include "test_fields.h"

namespace translucent::reference {
namespace {

using testing::grey;

constexpr double kPi = std::numbers::pi;

void expectAgree(const Estimate& a, const Estimate& b, double k, const std::string& what) {
  EXPECT_NEAR(a.value, b.value, k * std::hypot(a.std_error, b.std_error))
      << what << ": " << a.value << " ± " << a.std_error << " vs " << b.value << " ± "
      << b.std_error;
}

material::Material volumeMaterial(std::shared_ptr<const material::VolumeField> field, double eta) {
  material::Material m;
  m.kind = material::Material::Kind::Volume;
  m.medium.eta = eta;
  m.medium.scale = 1.0;
  m.volume = std::move(field);
  return m;
}

Medium mediumOf(const material::LocalMedium& l, double eta) {
  Medium m;
  m.sigma_a = l.sigma_a;
  m.sigma_s = l.sigma_s;
  m.g = l.g;
  m.eta = eta;
  m.scale = 1.0;
  return m;
}

// A unit icosphere under an oblique directional light, seen from above by a 12² pinhole camera.
struct LitSphere {
  geometry::TriangleMesh mesh = geometry::makeIcosphere(3);
  Light light{DirectionalLight{glm::normalize(glm::dvec3(0.4, 0.2, 1.0)), 1.0}, {1.0, 1.0, 1.0}};
  Camera camera() const {
    Camera cam;
    cam.position = {0.0, -2.0, 3.5};
    cam.look_at = {0.0, 0.0, 0.0};
    cam.fov = 40.0;
    cam.width = cam.height = 12;
    return cam;
  }
};

// Whole image and its four quadrants, per channel, and the exited flux per channel: 18 z-tests,
// |z| < 3.5 (Bonferroni at ~1%).
void expectSameImages(const MeshPathTracer& a, const MeshPathTracer& b) {
  const uint64_t na = a.stats().photons[0], nb = b.stats().photons[0];
  std::vector<std::vector<uint32_t>> regions(5);
  for (uint32_t y = 0; y < 12; ++y)
    for (uint32_t x = 0; x < 12; ++x) {
      regions[0].push_back(y * 12 + x);
      regions[1 + (y / 6) * 2 + x / 6].push_back(y * 12 + x);
    }
  for (int c = 0; c < 3; ++c) {
    expectAgree(a.stats().exited[static_cast<size_t>(c)].estimate(na),
                b.stats().exited[static_cast<size_t>(c)].estimate(nb), 3.5,
                "exited flux, channel " + std::to_string(c));
    for (size_t r = 0; r < regions.size(); ++r)
      expectAgree(a.images().exitance.average(regions[r], c),
                  b.images().exitance.average(regions[r], c), 3.5,
                  "exitance region " + std::to_string(r) + " channel " + std::to_string(c));
  }
  // The test has power: the whole-image mean is known to 2%.
  const Estimate whole = a.images().exitance.average(regions[0], 0);
  EXPECT_LT(whole.std_error, 0.02 * whole.value);
}

TEST(HeterogeneousMesh, HomogeneousFieldWithLooseMajorantMatchesTheHomogeneousWalk) {
  // σt = 10, 12, 15 per unit (the sphere is 20-30 mean free paths across), α ≈ 0.9; the field
  // claims 3σt, so two tentative collisions in three are null.
  const material::LocalMedium lm{{1.0, 1.2, 2.0}, {9.0, 10.8, 13.0}, 0.3};
  const double eta = 1.3;
  LitSphere s;
  TracerOptions o;
  o.seed = 5;
  o.threads = 2;
  MeshPathTracer homogeneous(s.mesh, mediumOf(lm, eta), {s.light}, s.camera(), 5.0, o);
  homogeneous.addPass(60'000);
  o.seed = 6;
  MeshPathTracer hetero(s.mesh, volumeMaterial(std::make_shared<testing::UniformField>(lm, 3.0), eta),
                        {s.light}, s.camera(), 5.0, o);
  hetero.addPass(60'000);
  ASSERT_NE(hetero.volume(), nullptr);
  EXPECT_DOUBLE_EQ(hetero.volume()->grid->maxBound(0), 30.0);
  EXPECT_EQ(hetero.volume()->grid->cells(), MajorantGrid::defaultCells(s.mesh.bounds().lower,
                                                                        s.mesh.bounds().upper));
  expectSameImages(hetero, homogeneous);
  EXPECT_EQ(hetero.majorantViolations(), 0u);
}

TEST(HeterogeneousMesh, HomogeneousMaterialTakesTheHomogeneousWalkBitForBit) {
  const material::LocalMedium lm{{1.0, 1.2, 2.0}, {9.0, 10.8, 13.0}, 0.3};
  LitSphere s;
  TracerOptions o;
  o.seed = 9;
  o.threads = 2;
  material::Material m;
  m.medium = mediumOf(lm, 1.3);
  MeshPathTracer a(s.mesh, mediumOf(lm, 1.3), {s.light}, s.camera(), 5.0, o);
  MeshPathTracer b(s.mesh, m, {s.light}, s.camera(), 5.0, o);
  a.addPass(4096);
  b.addPass(4096);
  EXPECT_EQ(b.volume(), nullptr);
  EXPECT_EQ(a.images().exitance.rgb(), b.images().exitance.rgb());
  EXPECT_EQ(a.stats().scattering_events, b.stats().scattering_events);
}

TEST(HeterogeneousMesh, CoreFarBelowTheSurfaceDoesNotShowUp) {
  // Outer medium: σa = 2, σs = 48 per unit: diffusion length 1/σtr = 0.058. The core (radius
  // 0.45, a clear weak absorber) starts 0.55 = 9.5 diffusion lengths below the surface: light
  // that reaches it and comes back is e^-19 of the exitance.
  const material::LocalMedium outer = grey(2.0, 48.0, 0.0), inner = grey(0.01, 3.0, 0.8);
  LitSphere s;
  TracerOptions o;
  o.seed = 11;
  o.threads = 2;
  MeshPathTracer homogeneous(s.mesh, mediumOf(outer, 1.4), {s.light}, s.camera(), 5.0, o);
  homogeneous.addPass(40'000);
  o.seed = 12;
  MeshPathTracer cored(s.mesh,
                       volumeMaterial(std::make_shared<testing::CoreField>(0.45, inner, outer), 1.4),
                       {s.light}, s.camera(), 5.0, o);
  cored.addPass(40'000);
  expectSameImages(cored, homogeneous);
  EXPECT_EQ(cored.majorantViolations(), 0u);
}

using test_support::RadialTally;

TEST(HeterogeneousMesh, LayeredFieldInAFlatBoxMatchesTheLayeredSlab) {
  // A 200 x 200 x 4 box under a pencil beam, η = 1.4: a forward-scattering top layer 1 unit
  // deep over a more absorbing, less forward one. Walls 100 mean free paths from the beam: the
  // box is the two-layer slab. Two independent computations: delta tracking through the grid
  // (the field's bound in the cells that straddle z = -1 is the larger σt: null collisions
  // there) and the layered slab's exact flights. 10 annuli + 2 totals: |z| < 3.2.
  const double T = 4.0, half = 100.0, eta = 1.4;
  const material::LocalMedium top = grey(0.05, 0.95, 0.7), bottom = grey(0.2, 1.8, 0.3);
  const MeshBody box(geometry::makeBox({-half, -half, -T}, {half, half, 0.0}));
  VolumeMedium v = VolumeMedium::make(
      volumeMaterial(std::make_shared<testing::PlaneLayers>(std::vector<double>{-1.0},
                                                            std::vector{top, bottom}),
                     eta),
      {-half, -half, -T - 1e-3}, {half, half, 1e-3});
  const Light beam{BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}};
  RadialTally tally(10, 0.4);
  TransportOptions o;
  o.photons = 60'000;
  o.seed = 21;
  o.threads = 2;
  const TransportStats s = tracePhotons(box, v, std::span<const Light>(&beam, 1), o, tally);
  const uint64_t n = 3 * s.photons[0];

  LayeredSlabSetup slab;
  slab.layers = {{1.0, 0.05, 0.95, 0.7}, {T - 1.0, 0.2, 1.8, 0.3}};
  slab.n_inside = eta;
  TraceOptions so;
  so.photons = 400'000;
  so.seed = 4;
  so.threads = 2;
  so.radial_bins = 10;
  so.radial_max = 4.0;
  const SlabResult r = traceLayeredSlab(slab, so);

  constexpr double kZ = 3.2;
  expectAgree(tally.top.estimate(n), r.diffuse_reflectance, kZ, "diffuse reflectance");
  expectAgree(tally.elsewhere.estimate(n), r.transmittance, kZ, "transmittance");
  for (int k = 0; k < 10; ++k) {
    const double area = kPi * 0.16 * ((k + 1) * (k + 1) - k * k);
    expectAgree(tally.annuli[static_cast<size_t>(k)].estimate(n, area),
                {r.radial.rd[static_cast<size_t>(k)], r.radial.rd_stderr[static_cast<size_t>(k)]},
                kZ, "Rd(r) annulus " + std::to_string(k));
  }
  EXPECT_LT(tally.top.estimate(n).std_error, 0.01 * tally.top.estimate(n).value);
  EXPECT_EQ(v.majorantViolations(), 0u);
}

// A field whose majorant() lies (half of σt) is caught: the walk counts the tentative
// collisions where the field exceeded the bound.
class LyingField final : public material::VolumeField {
 public:
  material::LocalMedium at(const glm::dvec3&) const override { return grey(1.0, 9.0, 0.0); }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override { return {5.0, 5.0, 5.0}; }
};

TEST(HeterogeneousMesh, CountsTentativeCollisionsAboveTheMajorant) {
  LitSphere s;
  TracerOptions o;
  o.threads = 2;
  MeshPathTracer t(s.mesh, volumeMaterial(std::make_shared<LyingField>(), 1.3), {s.light},
                   s.camera(), 5.0, o);
  t.addPass(1024);
  // Every tentative collision is above the bound: at least one per photon that entered and
  // scattered.
  EXPECT_GT(t.majorantViolations(), 1000u);
}

TEST(HeterogeneousMesh, SameSeedSameImagesForAnyThreadCount) {
  const material::LocalMedium outer = grey(1.0, 9.0, 0.5), inner = grey(0.1, 30.0, 0.0);
  LitSphere s;
  auto run = [&](int threads) {
    TracerOptions o;
    o.seed = 77;
    o.threads = threads;
    auto t = std::make_unique<MeshPathTracer>(
        s.mesh, volumeMaterial(std::make_shared<testing::CoreField>(0.6, inner, outer), 1.3),
        std::vector<Light>{s.light}, s.camera(), 5.0, o);
    t->addPass(3 * 1024);
    t->addPass(2 * 1024);  // a second pass continues the block sequence
    return t;
  };
  const auto one = run(1), three = run(3);
  EXPECT_EQ(one->images().exitance.rgb(), three->images().exitance.rgb());
  EXPECT_EQ(one->images().cone_radiance.rgb(), three->images().cone_radiance.rgb());
  EXPECT_EQ(one->stats().scattering_events, three->stats().scattering_events);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(one->stats().exited[static_cast<size_t>(c)].s(), three->stats().exited[static_cast<size_t>(c)].s());
    EXPECT_EQ(one->stats().exited[static_cast<size_t>(c)].s2(), three->stats().exited[static_cast<size_t>(c)].s2());
  }
  EXPECT_GT(one->stats().scattering_events, 0u);
}

TEST(HeterogeneousMesh, StopsOnRequestKeepingWholeBlocks) {
  // Progress and Ctrl-C as for the homogeneous walk (the same block driver): a stop keeps the
  // blocks traced so far, marks the pass partial, and the next pass continues after them.
  LitSphere s;
  TracerOptions o;
  o.threads = 2;
  MeshPathTracer t(s.mesh,
                   volumeMaterial(std::make_shared<testing::UniformField>(grey(0.001, 50.0, 0.0), 2.0), 1.3),
                   {s.light}, s.camera(), 5.0, o);
  const TransportStats p = t.addPass(50'000'000, [](const TraceProgress& pr) { return pr.seconds < 0.2; });
  EXPECT_TRUE(p.partial);
  EXPECT_LT(p.photons[0], 50'000'000u);
  EXPECT_EQ(p.photons[0] % kBlockPhotons, 0u);
}

TEST(HeterogeneousMesh, ErrorsNameTheProblem) {
  LitSphere s;
  material::Material m;
  m.kind = material::Material::Kind::Surface;
  auto make = [&] { MeshPathTracer t(s.mesh, m, {s.light}, s.camera(), 5.0, TracerOptions{}); };
  EXPECT_THROW(make(), ParameterError);
  try {
    make();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("model reference"), std::string::npos) << e.what();
  }
  m.kind = material::Material::Kind::Volume;  // no field
  EXPECT_THROW(make(), ParameterError);
}

TEST(MajorantGrid, BoundsEachCellByTheFieldOverItsMaterialBox) {
  // Two layers at material z = 0; the frame turns the scene by 90° about x (scene y -> material
  // z) and scales by 2: cells above scene y = 0 bound the top medium, below the bottom one, and
  // cells straddling it both.
  const material::LocalMedium top = grey(1.0, 2.0, 0.0), bottom = grey(5.0, 5.0, 0.0);
  testing::PlaneLayers field({0.0}, {top, bottom});
  material::MaterialFrame f;
  f.rotation = glm::dmat3(1, 0, 0, 0, 0, -1, 0, 1, 0);  // columns: R e_x = e_x, R e_y = -e_z, R e_z = e_y
  f.scale = 2.0;
  const MajorantGrid g(field, f, 0.5, {-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}, {2, 4, 2});
  // Rᵀ maps scene y to material z: q.z = 2 · y.
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k) {
      EXPECT_DOUBLE_EQ(g.bound(i, 0, k, 0), 5.0);  // y in [-1, -0.5]: bottom, x0.5
      EXPECT_DOUBLE_EQ(g.bound(i, 1, k, 0), 5.0);  // y in [-0.5, 0] (enlarged: straddles)
      EXPECT_DOUBLE_EQ(g.bound(i, 2, k, 0), 5.0);  // y in [0, 0.5] (enlarged: straddles)
      EXPECT_DOUBLE_EQ(g.bound(i, 3, k, 0), 1.5);  // y in [0.5, 1]: top
    }
  EXPECT_DOUBLE_EQ(g.maxBound(0), 5.0);
  EXPECT_EQ(MajorantGrid::defaultCells({0, 0, 0}, {200, 200, 4}), glm::ivec3(32, 32, 8));
  EXPECT_EQ(MajorantGrid::defaultCells({0, 0, 0}, {1, 2, 1}), glm::ivec3(16, 32, 16));
  EXPECT_THROW(MajorantGrid(field, f, 1.0, {0, 0, 0}, {1, 0, 1}), ParameterError);
}

TEST(MajorantGrid, DeltaTrackingSamplesTheExactFreePathAcrossCells) {
  // Two layers along a vertical ray: the first collision distance has P(t > s) =
  // exp(-∫0^s σt). Checked at three depths against the exact transmittance, 200k flights.
  const material::LocalMedium top = grey(0.0, 1.0, 0.0), bottom = grey(0.0, 4.0, 0.0);
  testing::PlaneLayers field({0.0}, {top, bottom});
  const VolumeMedium v = VolumeMedium::make(
      [&] {
        material::Material m;
        m.kind = material::Material::Kind::Volume;
        m.volume = std::make_shared<testing::PlaneLayers>(field);
        return m;
      }(),
      {-1.0, -1.0, -3.0}, {1.0, 1.0, 1.0}, {3, 3, 7});
  Rng rng(3, 0);
  const glm::dvec3 o{0.1, -0.2, 1.0}, d{0.0, 0.0, -1.0};
  const int N = 200'000;
  int beyond[3] = {0, 0, 0};
  const double depths[3] = {0.5, 1.25, 1.6};
  for (int p = 0; p < N; ++p) {
    double t = 0.0;
    auto accept = [&](double tc, double bound) {
      const double st = v.at(o + tc * d).sigmaT()[0];
      return detail::uniform01(rng) * bound < st;
    };
    if (!v.grid->track(o, d, 4.0, 0, rng, accept, t)) t = 4.0;
    for (int k = 0; k < 3; ++k) beyond[k] += t > depths[k];
  }
  for (int k = 0; k < 3; ++k) {
    const double s = depths[k];
    const double expected = std::exp(-(std::min(s, 1.0) + 4.0 * std::max(0.0, s - 1.0)));
    const double se = std::sqrt(expected * (1.0 - expected) / N);
    EXPECT_NEAR(static_cast<double>(beyond[k]) / N, expected, 4.0 * se) << "depth " << s;
  }
}

}  // namespace
}  // namespace translucent::reference
