// SPDX-License-Identifier: GPL-3.0-or-later
// The split of every tally by scattering order (slab.h: ScatteringOrder; seed Eq. 2.13, the
// explorer's "multi + single scattering" selector): the parts add up to the totals, and the
// single-scattering part equals the analytic single-scattering term of the searchlight problem
// (single_scattering.h) for every slab walker; the unscattered part of a finite slab's
// reflectance equals its closed form; the sphere's and the mesh's images and fluxes split too.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/sphere.h"
#include "image_zmap.h"
#include "published_setups.h"
#include "scattering_orders_checks.h"
#include "single_scattering.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;
using test_support::singleScatteringAnnulus;
using test_support::singleScatteringRd;

constexpr ScatteringOrder kUnscattered = ScatteringOrder::Unscattered;
constexpr ScatteringOrder kSingle = ScatteringOrder::Single;
constexpr ScatteringOrder kMultiple = ScatteringOrder::Multiple;

TEST(SingleScatteringTerm, QuadratureMatchesTheIsotropicClosedFormAndItsAnnuliAddUp) {
  // Isotropic, η = 1: R1 = α (1 - ln 2) / 2 (single_scattering.h); the annuli [0, ∞) hold it all.
  EXPECT_NEAR(singleScatteringRd(0.8, 0.0, 1.0), 0.4 * (1.0 - std::log(2.0)), 1e-12);
  for (const auto& [g, eta] : {std::pair{0.0, 1.0}, std::pair{0.5, 1.3}, std::pair{-0.3, 1.5}}) {
    const double total = singleScatteringRd(0.8, g, eta);
    double annuli = 0.0;
    const double edges[] = {0.0, 0.05, 0.2, 0.5, 1.0, 2.0, 5.0,
                            std::numeric_limits<double>::infinity()};
    for (size_t k = 0; k + 1 < std::size(edges); ++k)
      annuli += singleScatteringAnnulus(0.8, 2.0, g, eta, edges[k], edges[k + 1]);
    EXPECT_NEAR(annuli, total, 1e-6 * total) << "g " << g << " eta " << eta;
  }
}

SlabSetup halfSpace() { return test_support::singleScatteringHalfSpace(); }

TraceOptions radialOptions(uint64_t photons, uint64_t seed) {
  TraceOptions o;
  o.photons = photons;
  o.seed = seed;
  o.threads = 2;
  o.radial_bins = 12;
  o.radial_max = 1.2;  // 2.4 mean free paths
  o.angle_bins = 6;
  return o;
}

// Every annulus and the total of the single-scattering part against the closed form: 14 z-tests
// at the Bonferroni bound for 1% over all of them.
void expectSingleScatteringTerm(const SlabResult& r, const SlabSetup& s, const std::string& what) {
  SCOPED_TRACE(what);
  const double entering = 1.0 - r.specular_reflectance.value;
  const double albedo = s.sigma_s / (s.sigma_a + s.sigma_s), sigmaT = s.sigma_a + s.sigma_s;
  const double z = test_support::bonferroniZ(14, 0.01);
  const SlabResult::Order& single = r.order(kSingle);
  const double total = entering * singleScatteringRd(albedo, s.g, s.n_inside);
  EXPECT_NEAR(single.diffuse_reflectance.value, total, z * single.diffuse_reflectance.std_error)
      << "single-scattering Rd " << single.diffuse_reflectance.value << " ± "
      << single.diffuse_reflectance.std_error << ", expected " << total;
  // A test with power: the standard error is well below the quantity's size.
  EXPECT_LT(single.diffuse_reflectance.std_error, 0.01 * total);
  const auto& rad = single.radial;
  ASSERT_EQ(rad.rd.size(), 12u);
  for (size_t k = 0; k <= rad.rd.size(); ++k) {
    const bool beyond = k == rad.rd.size();
    const double a = k * rad.dr;
    const double b = beyond ? std::numeric_limits<double>::infinity() : a + rad.dr;
    const double area = 2.0 * kPi * (a + 0.5 * rad.dr) * rad.dr;  // the tally's annulus area
    const double expected =
        entering * singleScatteringAnnulus(albedo, sigmaT, s.g, s.n_inside, a, b) / (beyond ? 1.0 : area);
    const Estimate got = beyond ? rad.beyond : Estimate{rad.rd[k], rad.rd_stderr[k]};
    EXPECT_NEAR(got.value, expected, z * got.std_error) << "annulus " << k;
  }
}

TEST(ScatteringOrders, SingleScatteringMatchesTheAnalyticTermForEveryWalker) {
  const SlabSetup s = halfSpace();
  struct Walker {
    const char* name;
    Kernel kernel;
    Absorption absorption;
    uint64_t photons;
  };
  for (const Walker& w : {Walker{"lanes, analog", Kernel::Lanes, Absorption::Analog, 1'000'000},
                          Walker{"lanes, weighted", Kernel::Lanes, Absorption::Weighted, 1'000'000},
                          Walker{"scalar", Kernel::Scalar, Absorption::Analog, 1'000'000}}) {
    TraceOptions o = radialOptions(w.photons, 17);
    o.kernel = w.kernel;
    o.absorption = w.absorption;
    expectSingleScatteringTerm(traceSlab(s, o), s, w.name);
  }
  // The layered walker with one semi-infinite layer of the same medium.
  LayeredSlabSetup l;
  l.layers = {{std::numeric_limits<double>::infinity(), s.sigma_a, s.sigma_s, s.g}};
  l.n_inside = s.n_inside;
  expectSingleScatteringTerm(traceLayeredSlab(l, radialOptions(1'000'000, 19)), s, "layered");
}

TEST(ScatteringOrders, TheAnalyticCheckFailsForAMislabelledOrder) {
  // The check above has power: the multiple-scattering part of the same run is far from the
  // single-scattering term (it is not the whole light either).
  const SlabSetup s = halfSpace();
  const SlabResult r = traceSlab(s, radialOptions(200'000, 3));
  const double single = (1.0 - r.specular_reflectance.value) * singleScatteringRd(0.8, s.g, s.n_inside);
  const Estimate m = r.order(kMultiple).diffuse_reflectance;
  EXPECT_GT(std::abs(m.value - single), 20.0 * m.std_error);
  EXPECT_GT(std::abs(r.diffuse_reflectance.value - single), 20.0 * r.diffuse_reflectance.std_error);
}

// Every tally's orders add up to its total (the same photons: to rounding).
void expectOrdersAddUp(const SlabResult& r) {
  auto sum = [&](auto get) {
    double v = 0.0;
    for (ScatteringOrder o : kAllScatteringOrders) v += get(r.order(o));
    return v;
  };
  constexpr double tol = 1e-12;
  EXPECT_NEAR(sum([](const SlabResult::Order& o) { return o.diffuse_reflectance.value; }),
              r.diffuse_reflectance.value, tol);
  EXPECT_NEAR(sum([](const SlabResult::Order& o) { return o.transmittance.value; }),
              r.transmittance.value, tol);
  EXPECT_EQ(r.order(kUnscattered).transmittance.value, r.unscattered_transmittance.value);
  for (size_t i = 0; i < r.radial.rd.size(); ++i)
    EXPECT_NEAR(sum([&](const SlabResult::Order& o) { return o.radial.rd[i]; }), r.radial.rd[i],
                tol * (1.0 + r.radial.rd[i]));
  EXPECT_NEAR(sum([](const SlabResult::Order& o) { return o.radial.beyond.value; }),
              r.radial.beyond.value, tol);
  for (size_t j = 0; j < r.angular.rd.size(); ++j)
    EXPECT_NEAR(sum([&](const SlabResult::Order& o) { return o.angular.rd[j]; }), r.angular.rd[j],
                tol * (1.0 + r.angular.rd[j]));
  for (size_t k = 0; k < r.angular.rd_r_theta.size(); ++k)
    EXPECT_NEAR(sum([&](const SlabResult::Order& o) { return o.angular.rd_r_theta[k]; }),
                r.angular.rd_r_theta[k], tol * (1.0 + r.angular.rd_r_theta[k]));
  // Each photon leaves once, into one order: the per-photon second moments add up as well, so
  // the variances (σ² n ≈ mean square - mean²) of the parts and the total are consistent:
  // Σ (σ_k² + m_k²/n) = σ² + m²/n up to rounding (n = photons).
  const double n = static_cast<double>(r.photons);
  double parts = 0.0;
  for (ScatteringOrder o : kAllScatteringOrders) {
    const Estimate e = r.order(o).diffuse_reflectance;
    parts += e.std_error * e.std_error * n * (n - 1.0) / n + e.value * e.value;
  }
  const Estimate t = r.diffuse_reflectance;
  EXPECT_NEAR(parts, t.std_error * t.std_error * n * (n - 1.0) / n + t.value * t.value, 1e-9);
}

TEST(ScatteringOrders, EveryTallyOfAFiniteSlabAddsUpAndItsUnscatteredPartIsExact) {
  // test_support::interreflectingSlab: light bounces between the faces without scattering, so
  // every order reaches both sides; its unscattered reflectance has a closed form there.
  const test_support::InterreflectingSlab c = test_support::interreflectingSlab();
  const SlabSetup& s = c.setup;
  const double r0 = c.unscattered_reflectance;
  for (const auto& [kernel, absorption] : {std::pair{Kernel::Lanes, Absorption::Analog},
                                           std::pair{Kernel::Lanes, Absorption::Weighted},
                                           std::pair{Kernel::Scalar, Absorption::Analog}}) {
    TraceOptions o = radialOptions(kernel == Kernel::Scalar ? 300'000 : 1'000'000, 9);
    o.kernel = kernel;
    o.absorption = absorption;
    const SlabResult r = traceSlab(s, o);
    expectOrdersAddUp(r);
    const Estimate u = r.order(kUnscattered).diffuse_reflectance;
    EXPECT_NEAR(u.value, r0, 4.0 * u.std_error) << u.value << " ± " << u.std_error << " vs " << r0;
    EXPECT_LT(u.std_error, 0.02 * r0);
    for (ScatteringOrder k : kAllScatteringOrders)
      EXPECT_GT(r.order(k).transmittance.value, 0.0) << toString(k);
  }
}

TEST(ScatteringOrders, SphereImagesAndFluxesSplitIntoOrdersThatAddUp) {
  // The lit sphere, small enough (R = 3 mean free paths) for every order to show, under a
  // mismatched boundary. The orders' images add up to the totals pixel by pixel (exact sums on
  // one grid: to rounding), as do the exited fluxes; without the option there are none.
  SphereScene scene;
  scene.radius = 1.0;
  scene.width = scene.height = 24;
  scene.light_direction = {0.3, 0.4, 1.0};
  const ScalarMedium m{0.5, 2.5, 0.3, 1.4};
  TracerOptions o;
  o.seed = 5;
  o.threads = 2;
  o.split_orders = true;
  SpherePathTracer tracer(scene, m, o);
  tracer.addPass(200'000);
  ASSERT_TRUE(tracer.splitsOrders());
  auto check = [&](auto member) {
    const McImage& total = tracer.images().*member;
    double unscattered = 0.0;
    for (int y = 0; y < total.height(); ++y)
      for (int x = 0; x < total.width(); ++x) {
        double sum = 0.0;
        for (ScatteringOrder k : kAllScatteringOrders) sum += (tracer.orderImages(k).*member).pixel(x, y, 0).value;
        const double t = total.pixel(x, y, 0).value;
        EXPECT_NEAR(sum, t, 1e-12 * (1.0 + t)) << x << "," << y;
        unscattered += (tracer.orderImages(kUnscattered).*member).pixel(x, y, 0).value;
      }
    return unscattered;
  };
  EXPECT_GT(check(&CameraImages::exitance), 0.0);  // light crossing the sphere unscattered
  check(&CameraImages::radiance);
  check(&CameraImages::cone_radiance);
  const TransportStats& st = tracer.stats();
  double sum = 0.0;
  for (ScatteringOrder k : kAllScatteringOrders) {
    const Estimate e = st.exited_by_order[static_cast<size_t>(k)][0].estimate(st.photons[0]);
    EXPECT_GT(e.value, 0.0) << toString(k);
    sum += e.value;
  }
  EXPECT_NEAR(sum, st.exited[0].estimate(st.photons[0]).value, 1e-12);

  TracerOptions plain = o;
  plain.split_orders = false;
  SpherePathTracer without(scene, m, plain);
  EXPECT_FALSE(without.splitsOrders());
  EXPECT_THROW(without.orderImages(kSingle), std::logic_error);
  // The split does not change the totals: the same photons, the same images.
  without.addPass(200'000);
  EXPECT_EQ(without.images().exitance.rgb(), tracer.images().exitance.rgb());
}

TEST(ScatteringOrders, ExitsOfAPhotonThroughThreeCubesAreScoredInTheirOwnOrders) {
  // test_support::expectThreeCubesOrders: the unscattered exits of a pencil beam through three
  // index-matched cubes sum to T + T² + T³, the images and fluxes of the orders add up.
  MeshPathTracer t = test_support::threeCubesTracer({5, 2});
  test_support::expectThreeCubesOrders(t, 64 * kBlockPhotons);
}

}  // namespace
}  // namespace translucent::reference
